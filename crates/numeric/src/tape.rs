//! A compiled evaluator for a set of `cas` expressions: a flat register tape.
//!
//! [`Tape::compile`] walks the expression DAG once. Hash-consing already makes equal
//! sub-expressions the same node, so visiting each node once *is* common sub-expression
//! elimination across all outputs (mass matrix entries, forcing, constraints, energy share
//! their `sin θ`, `cos θ`, `l₁ l₂`…). Each node becomes one instruction writing one register;
//! the first registers hold the inputs (coordinates, rates, time, parameters) and the constants.
//! [`Tape::eval`] runs the instructions in order over a caller-owned register buffer, so an
//! evaluation allocates nothing.
//!
//! Sums and products of many operands are folded left to right into binary instructions;
//! integer powers become repeated multiplication (`powi`), `x^(1/2)` becomes `sqrt`.

use cas::{Constant, Expr, Func, Node, Symbol};
use rustc_hash::FxHashMap;

/// Why a set of expressions could not be compiled.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TapeError {
    /// An expression uses a symbol that is not one of the tape's inputs.
    #[error("no value for `{name}`")]
    UnboundSymbol {
        /// The symbol, in SymPy syntax (`theta_d` for a rate).
        name: String,
    },
}

/// One instruction: computes register `target` (implicit: instruction `k` writes register
/// `first_computed + k`) from earlier registers.
#[derive(Clone, Copy, Debug)]
enum Op {
    /// `acc + a·b` in one instruction: the shape of every term of an expanded sum.
    MulAdd(u32, u32, u32),
    /// `acc − a·b`.
    MulSub(u32, u32, u32),
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    Neg(u32),
    Recip(u32),
    Square(u32),
    Powi(u32, i32),
    Powf(u32, u32),
    Sqrt(u32),
    Unary(Func, u32),
    Atan2(u32, u32),
}

/// A compiled set of scalar expressions with numbered inputs. Invariant: every operand index
/// of instruction `k` is below `first_computed + k`, and every output index is below
/// `register_count`.
#[derive(Clone, Debug)]
pub struct Tape {
    input_count: usize,
    constants: Vec<f64>,
    ops: Vec<Op>,
    outputs: Vec<u32>,
}

struct Compiler<'a> {
    inputs: &'a FxHashMap<Symbol, u32>,
    constants: Vec<f64>,
    constant_slots: FxHashMap<u64, u32>,
    ops: Vec<Op>,
    memo: FxHashMap<Expr, Slot>,
}

/// Where a value lives while compiling: constants get their final register only once the
/// number of constants is known, so they are kept apart from computed registers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Slot {
    Input(u32),
    Constant(u32),
    Computed(u32),
}

impl Tape {
    /// Compiles `outputs`, whose symbols must all be among `inputs` (in the order their values
    /// will be given to [`Tape::eval`]).
    ///
    /// # Errors
    /// [`TapeError::UnboundSymbol`] for a symbol that is not an input.
    pub fn compile(outputs: &[Expr], inputs: &[Symbol]) -> Result<Tape, TapeError> {
        let index: FxHashMap<Symbol, u32> = inputs
            .iter()
            .enumerate()
            .map(|(k, s)| (*s, k as u32))
            .collect();
        let mut compiler = Compiler {
            inputs: &index,
            constants: Vec::new(),
            constant_slots: FxHashMap::default(),
            ops: Vec::new(),
            memo: FxHashMap::default(),
        };
        let slots = outputs
            .iter()
            .map(|e| compiler.slot(*e))
            .collect::<Result<Vec<_>, _>>()?;
        let input_count = inputs.len();
        let constant_count = compiler.constants.len();
        let first_computed = input_count + constant_count;
        let place = |s: Slot| -> u32 {
            match s {
                Slot::Input(k) => k,
                Slot::Constant(k) => (input_count as u32) + k,
                Slot::Computed(k) => (first_computed as u32) + k,
            }
        };
        // Operands were recorded as encoded slots; decode them to registers now.
        let ops = compiler
            .ops
            .iter()
            .map(|op| map_operands(*op, |r| place(decode(r))))
            .collect();
        let tape = Tape {
            input_count,
            constants: compiler.constants,
            ops,
            outputs: slots.into_iter().map(place).collect(),
        };
        // The invariant `eval` relies on to skip bounds checks; it holds by construction
        // (operands are compiled before the instruction that reads them), and is checked once
        // here so that a bug in the compiler cannot become an out-of-bounds read.
        assert!(
            tape.invariant_holds(),
            "tape operands precede their instruction"
        );
        Ok(tape)
    }

    fn invariant_holds(&self) -> bool {
        let first = self.input_count + self.constants.len();
        let operands_ok = self.ops.iter().enumerate().all(|(k, op)| {
            let limit = (first + k) as u32;
            let mut ok = true;
            map_operands(*op, |r| {
                ok &= r < limit;
                r
            });
            ok
        });
        let register_count = self.register_count() as u32;
        operands_ok && self.outputs.iter().all(|&o| o < register_count)
    }

    /// How many inputs [`Tape::eval`] takes.
    #[must_use]
    pub fn input_count(&self) -> usize {
        self.input_count
    }

    /// How many outputs [`Tape::eval`] writes.
    #[must_use]
    pub fn output_count(&self) -> usize {
        self.outputs.len()
    }

    /// How many instructions run per evaluation (a measure of the work).
    #[must_use]
    pub fn instruction_count(&self) -> usize {
        self.ops.len()
    }

    /// The size of the register buffer [`Tape::eval`] needs.
    #[must_use]
    pub fn register_count(&self) -> usize {
        self.input_count + self.constants.len() + self.ops.len()
    }

    /// A register buffer of the right size, with the constants in place.
    #[must_use]
    pub fn registers(&self) -> Vec<f64> {
        let mut r = vec![0.0; self.register_count()];
        r[self.input_count..self.input_count + self.constants.len()]
            .copy_from_slice(&self.constants);
        r
    }

    /// Evaluates every output. `registers` must come from [`Tape::registers`] (it is reused
    /// between calls, so nothing is allocated); `inputs` has [`Tape::input_count`] values and
    /// `outputs` room for [`Tape::output_count`].
    ///
    /// # Panics
    /// If a buffer has the wrong length (a programming error, not an input error).
    pub fn eval(&self, inputs: &[f64], registers: &mut [f64], outputs: &mut [f64]) {
        assert_eq!(inputs.len(), self.input_count, "tape input count");
        assert_eq!(
            registers.len(),
            self.register_count(),
            "tape register count"
        );
        assert!(outputs.len() >= self.outputs.len(), "tape output count");
        registers[..self.input_count].copy_from_slice(inputs);
        let first = self.input_count + self.constants.len();
        // Instruction k reads registers below first + k (the invariant of `Tape`) and writes
        // register first + k.
        for (k, op) in self.ops.iter().enumerate() {
            // SAFETY: `Tape::compile` checked that every operand of instruction k is below
            // first + k, and the buffer length is asserted above, so every index is in bounds.
            // Bounds checks here cost about a third of the evaluation time.
            let r = |i: u32| unsafe { *registers.get_unchecked(i as usize) };
            let value = match *op {
                Op::MulAdd(acc, a, b) => r(acc) + r(a) * r(b),
                Op::MulSub(acc, a, b) => r(acc) - r(a) * r(b),
                Op::Add(a, b) => r(a) + r(b),
                Op::Sub(a, b) => r(a) - r(b),
                Op::Mul(a, b) => r(a) * r(b),
                Op::Div(a, b) => r(a) / r(b),
                Op::Neg(a) => -r(a),
                Op::Recip(a) => 1.0 / r(a),
                Op::Square(a) => {
                    let x = r(a);
                    x * x
                }
                Op::Powi(a, n) => r(a).powi(n),
                Op::Powf(a, b) => r(a).powf(r(b)),
                Op::Sqrt(a) => r(a).sqrt(),
                Op::Atan2(y, x) => r(y).atan2(r(x)),
                Op::Unary(f, a) => unary(f, r(a)),
            };
            // SAFETY: first + k < register_count = registers.len() (asserted above).
            unsafe {
                *registers.get_unchecked_mut(first + k) = value;
            }
        }
        for (out, &i) in outputs.iter_mut().zip(&self.outputs) {
            *out = registers[i as usize];
        }
    }
}

fn unary(f: Func, x: f64) -> f64 {
    match f {
        Func::Sin => x.sin(),
        Func::Cos => x.cos(),
        Func::Tan => x.tan(),
        Func::Asin => x.asin(),
        Func::Acos => x.acos(),
        Func::Atan => x.atan(),
        Func::Exp => x.exp(),
        Func::Ln => x.ln(),
        Func::Abs => x.abs(),
        Func::Sign => {
            if x == 0.0 {
                0.0
            } else {
                x.signum()
            }
        }
        _ => f64::NAN,
    }
}

/// Operands are stored during compilation as encoded slots (two tag bits), then decoded.
fn encode(s: Slot) -> u32 {
    match s {
        Slot::Input(k) => k << 2,
        Slot::Constant(k) => (k << 2) | 1,
        Slot::Computed(k) => (k << 2) | 2,
    }
}

fn decode(r: u32) -> Slot {
    match r & 3 {
        0 => Slot::Input(r >> 2),
        1 => Slot::Constant(r >> 2),
        _ => Slot::Computed(r >> 2),
    }
}

fn map_operands(op: Op, mut f: impl FnMut(u32) -> u32) -> Op {
    match op {
        Op::MulAdd(acc, a, b) => Op::MulAdd(f(acc), f(a), f(b)),
        Op::MulSub(acc, a, b) => Op::MulSub(f(acc), f(a), f(b)),
        Op::Add(a, b) => Op::Add(f(a), f(b)),
        Op::Sub(a, b) => Op::Sub(f(a), f(b)),
        Op::Mul(a, b) => Op::Mul(f(a), f(b)),
        Op::Div(a, b) => Op::Div(f(a), f(b)),
        Op::Neg(a) => Op::Neg(f(a)),
        Op::Recip(a) => Op::Recip(f(a)),
        Op::Square(a) => Op::Square(f(a)),
        Op::Powi(a, n) => Op::Powi(f(a), n),
        Op::Powf(a, b) => Op::Powf(f(a), f(b)),
        Op::Sqrt(a) => Op::Sqrt(f(a)),
        Op::Unary(g, a) => Op::Unary(g, f(a)),
        Op::Atan2(a, b) => Op::Atan2(f(a), f(b)),
    }
}

impl Compiler<'_> {
    fn constant(&mut self, value: f64) -> Slot {
        let bits = value.to_bits();
        if let Some(&k) = self.constant_slots.get(&bits) {
            return Slot::Constant(k);
        }
        let k = self.constants.len() as u32;
        self.constants.push(value);
        self.constant_slots.insert(bits, k);
        Slot::Constant(k)
    }

    fn emit(&mut self, op: impl FnOnce(&dyn Fn(Slot) -> u32) -> Op) -> Slot {
        let op = op(&encode);
        let k = self.ops.len() as u32;
        self.ops.push(op);
        Slot::Computed(k)
    }

    fn slot(&mut self, e: Expr) -> Result<Slot, TapeError> {
        if let Some(&s) = self.memo.get(&e) {
            return Ok(s);
        }
        let s = match e.node() {
            Node::Number(n) => self.constant(n.to_f64()),
            Node::Constant(Constant::Pi) => self.constant(std::f64::consts::PI),
            Node::Constant(_) => self.constant(f64::NAN),
            Node::Symbol(sym) => match self.inputs.get(sym) {
                Some(&k) => Slot::Input(k),
                None => {
                    let mut name = sym.name().to_owned();
                    if sym.order() > 0 {
                        name.push('_');
                        name.extend(std::iter::repeat_n('d', sym.order() as usize));
                    }
                    return Err(TapeError::UnboundSymbol { name });
                }
            },
            Node::Add(terms) => self.sum(terms)?,
            Node::Mul(factors) => self.product(factors)?,
            Node::Pow([base, exponent]) => self.power(*base, *exponent)?,
            Node::Func(Func::Atan2, args) if args.len() == 2 => {
                let (y, x) = (self.slot(args[0])?, self.slot(args[1])?);
                self.emit(|c| Op::Atan2(c(y), c(x)))
            }
            Node::Func(f, args) if args.len() == 1 => {
                let a = self.slot(args[0])?;
                let f = *f;
                self.emit(|c| Op::Unary(f, c(a)))
            }
            Node::Func(..) => self.constant(f64::NAN),
        };
        self.memo.insert(e, s);
        Ok(s)
    }

    /// A sum; terms of the form `−1·x` are subtracted rather than negated then added.
    fn sum(&mut self, terms: &[Expr]) -> Result<Slot, TapeError> {
        let mut acc: Option<Slot> = None;
        for &term in terms {
            let (negative, magnitude) = split_sign(term);
            if let (Some(a), Some((left, right))) = (acc, self.split_product(magnitude)?) {
                acc = Some(if negative {
                    self.emit(|c| Op::MulSub(c(a), c(left), c(right)))
                } else {
                    self.emit(|c| Op::MulAdd(c(a), c(left), c(right)))
                });
                continue;
            }
            let value = self.slot(magnitude)?;
            acc = Some(match (acc, negative) {
                (None, false) => value,
                (None, true) => self.emit(|c| Op::Neg(c(value))),
                (Some(a), false) => self.emit(|c| Op::Add(c(a), c(value))),
                (Some(a), true) => self.emit(|c| Op::Sub(c(a), c(value))),
            });
        }
        Ok(match acc {
            Some(s) => s,
            None => self.constant(0.0),
        })
    }

    /// A product term `c·x·y⋯` of a sum as two operands for a fused multiply-add: the
    /// coefficient and the monomial (which other terms and outputs may share), or the monomial
    /// without its last factor and that factor. `None` for anything else, and for products
    /// with a divisor (those compile as a division).
    fn split_product(&mut self, term: Expr) -> Result<Option<(Slot, Slot)>, TapeError> {
        let Node::Mul(factors) = term.node() else {
            return Ok(None);
        };
        let divides = factors.iter().any(|f| match f.node() {
            Node::Pow([_, e]) => e.as_number().is_some_and(|n| n.to_f64() < 0.0),
            _ => false,
        });
        if divides || factors.len() < 2 {
            return Ok(None);
        }
        let (left, right) = if factors[0].as_number().is_some() {
            (factors[0], Expr::mul_all(factors[1..].iter().copied()))
        } else {
            let last = factors.len() - 1;
            (
                Expr::mul_all(factors[..last].iter().copied()),
                factors[last],
            )
        };
        Ok(Some((self.slot(left)?, self.slot(right)?)))
    }

    /// A product; factors `x^(−k)` divide rather than multiply by a reciprocal.
    fn product(&mut self, factors: &[Expr]) -> Result<Slot, TapeError> {
        let mut numerator: Option<Slot> = None;
        let mut denominator: Option<Slot> = None;
        for &factor in factors {
            if let Node::Pow([base, exponent]) = factor.node() {
                if let Some(k) = exponent.as_number().and_then(|n| n.to_i64()) {
                    if k < 0 && k > i64::from(i32::MIN) {
                        let value = self.integer_power(*base, -k)?;
                        denominator = Some(match denominator {
                            None => value,
                            Some(d) => self.emit(|c| Op::Mul(c(d), c(value))),
                        });
                        continue;
                    }
                }
            }
            let value = self.slot(factor)?;
            numerator = Some(match numerator {
                None => value,
                Some(a) => self.emit(|c| Op::Mul(c(a), c(value))),
            });
        }
        Ok(match (numerator, denominator) {
            (Some(n), None) => n,
            (Some(n), Some(d)) => self.emit(|c| Op::Div(c(n), c(d))),
            (None, Some(d)) => self.emit(|c| Op::Recip(c(d))),
            (None, None) => self.constant(1.0),
        })
    }

    fn power(&mut self, base: Expr, exponent: Expr) -> Result<Slot, TapeError> {
        if let Some(n) = exponent.as_number() {
            if let Some(k) = n.to_i64() {
                if k < 0 && k > i64::from(i32::MIN) {
                    let value = self.integer_power(base, -k)?;
                    return Ok(self.emit(|c| Op::Recip(c(value))));
                }
                if k >= 0 {
                    return self.integer_power(base, k);
                }
            }
            let x = n.to_f64();
            if x == 0.5 {
                let b = self.slot(base)?;
                return Ok(self.emit(|c| Op::Sqrt(c(b))));
            }
            if x == -0.5 {
                let b = self.slot(base)?;
                let root = self.emit(|c| Op::Sqrt(c(b)));
                return Ok(self.emit(|c| Op::Recip(c(root))));
            }
        }
        let (b, x) = (self.slot(base)?, self.slot(exponent)?);
        Ok(self.emit(|c| Op::Powf(c(b), c(x))))
    }

    fn integer_power(&mut self, base: Expr, k: i64) -> Result<Slot, TapeError> {
        let b = self.slot(base)?;
        Ok(match k {
            0 => self.constant(1.0),
            1 => b,
            2 => self.emit(|c| Op::Square(c(b))),
            3 => {
                let square = self.emit(|c| Op::Square(c(b)));
                self.emit(|c| Op::Mul(c(square), c(b)))
            }
            _ => {
                let k = i32::try_from(k).unwrap_or(i32::MAX);
                self.emit(|c| Op::Powi(c(b), k))
            }
        })
    }
}

/// `(true, x)` for a term `−x` (a product whose number is −1, or a negative number's
/// magnitude), so sums subtract instead of negating.
fn split_sign(term: Expr) -> (bool, Expr) {
    if let Node::Mul(factors) = term.node() {
        if let Some(n) = factors.first().and_then(|f| f.as_number()) {
            if n.to_i64() == Some(-1) {
                return (true, Expr::mul_all(factors[1..].iter().copied()));
            }
        }
    }
    (false, term)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn symbols(names: &[&str]) -> Vec<Symbol> {
        names
            .iter()
            .filter_map(|n| Expr::symbol(n).as_symbol())
            .collect()
    }

    #[test]
    fn tape_matches_the_symbolic_evaluator_at_random_points() {
        let (x, y, z) = (Expr::symbol("x"), Expr::symbol("y"), Expr::symbol("z"));
        let outputs = [
            (x.sin() * y.cos() - x.powi(3) / (y.powi(2) + 1) + z.sqrt()).normal(),
            (x * y - z).exp() + Expr::atan2(y, x) + (x.powi(2) + 1).ln() - x.powi(-3),
            (x + y).pow(z) + Expr::pi() * z.abs().sign(),
            Expr::int(7),
        ];
        let tape = Tape::compile(&outputs, &symbols(&["x", "y", "z"])).unwrap();
        let mut registers = tape.registers();
        let mut out = vec![0.0; tape.output_count()];
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..50 {
            let mut next = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                0.3 + 1.4 * ((state >> 11) as f64 / (1u64 << 53) as f64)
            };
            let point = [next(), next(), next()];
            tape.eval(&point, &mut registers, &mut out);
            let env = |s: Symbol| match s.name() {
                "x" => Some(point[0]),
                "y" => Some(point[1]),
                "z" => Some(point[2]),
                _ => None,
            };
            for (k, e) in outputs.iter().enumerate() {
                let expected = e.eval(&env).unwrap();
                assert!(
                    (out[k] - expected).abs() <= 1e-12 * expected.abs().max(1.0),
                    "output {k}: tape {} vs eval {expected}",
                    out[k]
                );
            }
        }
    }

    #[test]
    fn shared_subexpressions_are_computed_once() {
        let x = Expr::symbol("x");
        let s = x.sin();
        let outputs = [s * 2, s * 3, s.powi(2)];
        let tape = Tape::compile(&outputs, &symbols(&["x"])).unwrap();
        // sin x once, then 2·s, 3·s, s²: four instructions.
        assert_eq!(tape.instruction_count(), 4);
    }

    #[test]
    fn unknown_symbol_is_an_error() {
        let err = Tape::compile(&[Expr::symbol("k") * 2], &symbols(&["x"])).unwrap_err();
        assert_eq!(
            err,
            TapeError::UnboundSymbol {
                name: "k".to_owned()
            }
        );
    }
}
