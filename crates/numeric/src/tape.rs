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
//! A sum is factored greedily (the factor most of its terms share is taken out, recursively)
//! and becomes one `Dot` instruction `Σ aᵢ·bᵢ` over a table of operand pairs, accumulated in
//! machine registers; `sin x` and `cos x` of the same `x` come from one `sincos` call.
//! Products are folded left to right into binary instructions; integer powers become
//! repeated multiplication (`powi`), `x^(1/2)` becomes `sqrt`.

use cas::{Constant, Expr, Func, Node, Symbol};
use rustc_hash::{FxHashMap, FxHashSet};

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
    Mul(u32, u32),
    Div(u32, u32),
    Recip(u32),
    Square(u32),
    Powi(u32, i32),
    Powf(u32, u32),
    Sqrt(u32),
    Unary(Func, u32),
    Atan2(u32, u32),
    /// `sin a` into this instruction's register and `cos a` into the next one's (whose
    /// instruction is [`Op::CosOfPrevious`]): one call instead of two, the argument
    /// reduction shared.
    SinCos(u32),
    /// Written by the [`Op::SinCos`] before it; does nothing.
    CosOfPrevious,
    /// `Σ a·b` over the operand pairs `pairs[start .. start + len]`: a whole sum in one
    /// instruction, accumulated in machine registers instead of through the register buffer
    /// term by term (each term of a chain of multiply-adds waited for the previous one's
    /// store).
    Dot(u32, u32),
}

/// A compiled set of scalar expressions with numbered inputs. Invariant: every operand index
/// of instruction `k` is below `first_computed + k`, and every output index is below
/// `register_count`.
#[derive(Clone, Debug)]
pub struct Tape {
    input_count: usize,
    constants: Vec<f64>,
    ops: Vec<Op>,
    /// The operand pairs of the [`Op::Dot`] instructions.
    pairs: Vec<(u32, u32)>,
    outputs: Vec<u32>,
}

struct Compiler<'a> {
    inputs: &'a FxHashMap<Symbol, u32>,
    constants: Vec<f64>,
    constant_slots: FxHashMap<u64, u32>,
    ops: Vec<Op>,
    /// The operand pairs of [`Op::Dot`], as encoded slots.
    pairs: Vec<(u32, u32)>,
    memo: FxHashMap<Expr, Slot>,
    /// The arguments whose sine and cosine both occur: computed by one [`Op::SinCos`].
    sine_and_cosine: FxHashSet<Expr>,
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
            pairs: Vec::new(),
            memo: FxHashMap::default(),
            sine_and_cosine: sine_and_cosine_arguments(outputs),
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
        let pairs = compiler
            .pairs
            .iter()
            .map(|&(a, b)| (place(decode(a)), place(decode(b))))
            .collect();
        let tape = Tape {
            input_count,
            constants: compiler.constants,
            ops,
            pairs,
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
            if let Op::Dot(start, len) = *op {
                let (start, len) = (start as usize, len as usize);
                ok &= start
                    .checked_add(len)
                    .and_then(|end| self.pairs.get(start..end))
                    .is_some_and(|pairs| pairs.iter().all(|&(a, b)| a < limit && b < limit));
            }
            // A SinCos writes the next register too, which must be its CosOfPrevious.
            if let Op::SinCos(_) = op {
                ok &= matches!(self.ops.get(k + 1), Some(Op::CosOfPrevious));
            }
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
                Op::Mul(a, b) => r(a) * r(b),
                Op::Div(a, b) => r(a) / r(b),
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
                Op::SinCos(a) => {
                    let (sin, cos) = sin_cos(r(a));
                    // SAFETY: compile emits every SinCos followed by its CosOfPrevious, so
                    // first + k + 1 is a register of this tape.
                    unsafe {
                        *registers.get_unchecked_mut(first + k + 1) = cos;
                    }
                    sin
                }
                Op::CosOfPrevious => continue,
                Op::Dot(start, len) => {
                    // SAFETY: compile checked that start + len is within `pairs` and that
                    // every register of these pairs is below first + k.
                    let pairs = unsafe {
                        self.pairs
                            .get_unchecked(start as usize..start as usize + len as usize)
                    };
                    // Two accumulators: consecutive terms do not wait for each other.
                    let (mut even, mut odd) = (0.0, 0.0);
                    let mut chunks = pairs.chunks_exact(2);
                    for chunk in &mut chunks {
                        even += r(chunk[0].0) * r(chunk[0].1);
                        odd += r(chunk[1].0) * r(chunk[1].1);
                    }
                    if let [(a, b)] = chunks.remainder() {
                        even += r(*a) * r(*b);
                    }
                    even + odd
                }
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
        Op::Mul(a, b) => Op::Mul(f(a), f(b)),
        Op::Div(a, b) => Op::Div(f(a), f(b)),
        Op::Recip(a) => Op::Recip(f(a)),
        Op::Square(a) => Op::Square(f(a)),
        Op::Powi(a, n) => Op::Powi(f(a), n),
        Op::Powf(a, b) => Op::Powf(f(a), f(b)),
        Op::Sqrt(a) => Op::Sqrt(f(a)),
        Op::Unary(g, a) => Op::Unary(g, f(a)),
        Op::Atan2(a, b) => Op::Atan2(f(a), f(b)),
        Op::SinCos(a) => Op::SinCos(f(a)),
        Op::CosOfPrevious => Op::CosOfPrevious,
        // Its operands are in the pair table, checked and mapped apart.
        Op::Dot(start, len) => Op::Dot(start, len),
    }
}

/// Every argument `x` of which both `sin x` and `cos x` occur among the outputs.
fn sine_and_cosine_arguments(outputs: &[Expr]) -> FxHashSet<Expr> {
    let mut seen: FxHashSet<Expr> = FxHashSet::default();
    let mut sines: FxHashSet<Expr> = FxHashSet::default();
    let mut cosines: FxHashSet<Expr> = FxHashSet::default();
    let mut stack: Vec<Expr> = outputs.to_vec();
    while let Some(e) = stack.pop() {
        if !seen.insert(e) {
            continue;
        }
        match e.node() {
            Node::Func(Func::Sin, args) if args.len() == 1 => {
                sines.insert(args[0]);
            }
            Node::Func(Func::Cos, args) if args.len() == 1 => {
                cosines.insert(args[0]);
            }
            _ => {}
        }
        stack.extend_from_slice(e.children());
    }
    sines.intersection(&cosines).copied().collect()
}

/// `(sin x, cos x)`: glibc's `sincos` where there is one (it shares the argument reduction
/// and much of the polynomial work), else the two functions.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn sin_cos(x: f64) -> (f64, f64) {
    extern "C" {
        fn sincos(x: f64, sin: *mut f64, cos: *mut f64);
    }
    let (mut sin, mut cos) = (0.0, 0.0);
    // SAFETY: glibc's sincos writes one f64 through each pointer, both valid and distinct.
    unsafe { sincos(x, &mut sin, &mut cos) };
    (sin, cos)
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn sin_cos(x: f64) -> (f64, f64) {
    x.sin_cos()
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
            Node::Func(Func::Sin | Func::Cos, args)
                if args.len() == 1 && self.sine_and_cosine.contains(&args[0]) =>
            {
                let a = self.slot(args[0])?;
                let sin = self.emit(|c| Op::SinCos(c(a)));
                let cos = self.emit(|_| Op::CosOfPrevious);
                self.memo.insert(args[0].sin(), sin);
                self.memo.insert(args[0].cos(), cos);
                return Ok(if matches!(e.node(), Node::Func(Func::Sin, _)) {
                    sin
                } else {
                    cos
                });
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

    /// A sum, factored greedily (multivariate Horner): the factor shared by the most terms
    /// is taken out, `rest + f·(Σ terms with f, f removed)`, recursively. The expanded forms
    /// of mechanics repeat `sin θᵢ`, `cos θᵢ`, `θ̇ⱼ²` across many terms of one sum, so this
    /// halves the instructions of the n-link pendulum's forcing, and the factored products
    /// (`θ̇ⱼ² cos θⱼ`) are shared between outputs.
    fn sum(&mut self, terms: &[Expr]) -> Result<Slot, TapeError> {
        let terms = terms
            .iter()
            .map(|&term| {
                let (negative, magnitude) = split_sign(term);
                let factors = match magnitude.node() {
                    Node::Mul(factors) => factors.to_vec(),
                    _ => vec![magnitude],
                };
                Term { negative, factors }
            })
            .collect();
        self.factored_sum(terms)
    }

    fn factored_sum(&mut self, terms: Vec<Term>) -> Result<Slot, TapeError> {
        let pairs = self.sum_pairs(terms)?;
        Ok(self.dot(&pairs))
    }

    /// The sum as operand pairs `Σ a·b`, with shared factors taken out: `rest + f·inner`
    /// is `rest`'s pairs and `(f, inner)`.
    fn sum_pairs(&mut self, terms: Vec<Term>) -> Result<Vec<(Slot, Slot)>, TapeError> {
        if let Some(shared) = most_shared_factor(&terms) {
            let (mut with, without): (Vec<Term>, Vec<Term>) =
                terms.into_iter().partition(|t| t.factors.contains(&shared));
            for term in &mut with {
                if let Some(k) = term.factors.iter().position(|f| *f == shared) {
                    term.factors.remove(k);
                }
            }
            let factor = self.slot(shared)?;
            let inner = self.factored_sum(with)?;
            let mut pairs = self.sum_pairs(without)?;
            pairs.push((factor, inner));
            return Ok(pairs);
        }
        let mut pairs = Vec::with_capacity(terms.len());
        for term in terms {
            pairs.push(self.term_pair(&term)?);
        }
        Ok(pairs)
    }

    /// A term as `a·b`: its coefficient (the sign folded in) and its monomial, or the
    /// monomial without its last factor and that factor, or the term and ±1.
    fn term_pair(&mut self, term: &Term) -> Result<(Slot, Slot), TapeError> {
        let factors = &term.factors;
        if let Some(n) = factors.first().and_then(|f| f.as_number()) {
            if factors.len() >= 2 && !divides(factors) {
                let value = if term.negative {
                    -n.to_f64()
                } else {
                    n.to_f64()
                };
                let coefficient = self.constant(value);
                let monomial = self.slot(Expr::mul_all(factors[1..].iter().copied()))?;
                return Ok((coefficient, monomial));
            }
        }
        if factors.len() >= 2 && !term.negative && !divides(factors) {
            let last = factors.len() - 1;
            let left = self.slot(Expr::mul_all(factors[..last].iter().copied()))?;
            let right = self.slot(factors[last])?;
            return Ok((left, right));
        }
        let value = self.slot(Expr::mul_all(factors.iter().copied()))?;
        let sign = self.constant(if term.negative { -1.0 } else { 1.0 });
        Ok((sign, value))
    }

    /// `Σ a·b` as one instruction; a single pair as a product (or as `a` itself when `b` is
    /// the constant 1), none as 0.
    fn dot(&mut self, pairs: &[(Slot, Slot)]) -> Slot {
        match pairs {
            [] => self.constant(0.0),
            [(a, b)] => {
                let (a, b) = (*a, *b);
                let one = self.constant(1.0);
                if a == one {
                    b
                } else if b == one {
                    a
                } else {
                    self.emit(|c| Op::Mul(c(a), c(b)))
                }
            }
            _ => {
                let start = self.pairs.len() as u32;
                self.pairs
                    .extend(pairs.iter().map(|&(a, b)| (encode(a), encode(b))));
                let len = pairs.len() as u32;
                self.emit(|_| Op::Dot(start, len))
            }
        }
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

/// Whether a product has a divisor (`x^(−k)`): it then compiles as a division.
fn divides(factors: &[Expr]) -> bool {
    factors.iter().any(|f| match f.node() {
        Node::Pow([_, e]) => e.as_number().is_some_and(|n| n.to_f64() < 0.0),
        _ => false,
    })
}

/// A term of a sum being factored: its sign and its factors (a number first, if any).
struct Term {
    negative: bool,
    factors: Vec<Expr>,
}

/// The non-numeric factor that the most terms (at least two) have, the earliest on a tie so
/// that compiling is deterministic.
fn most_shared_factor(terms: &[Term]) -> Option<Expr> {
    if terms.len() < 2 {
        return None;
    }
    let mut counts: FxHashMap<Expr, (usize, usize)> = FxHashMap::default();
    let mut order = 0;
    for term in terms {
        for (k, factor) in term.factors.iter().enumerate() {
            // Counted once per term, even when a factor repeats.
            if factor.as_number().is_some() || term.factors[..k].contains(factor) {
                continue;
            }
            let entry = counts.entry(*factor).or_insert((0, order));
            entry.0 += 1;
            order += 1;
        }
    }
    counts
        .into_iter()
        .filter(|(_, (count, _))| *count >= 2)
        .max_by(|a, b| a.1 .0.cmp(&b.1 .0).then(b.1 .1.cmp(&a.1 .1)))
        .map(|(factor, _)| factor)
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
    fn sums_are_factored_and_sine_and_cosine_share_one_call() {
        let (x, y, a, b) = (
            Expr::symbol("x"),
            Expr::symbol("y"),
            Expr::symbol("a"),
            Expr::symbol("b"),
        );
        let (s, c) = (x.sin(), x.cos());
        // s·(a·y + b·y² + 3) + c·(2a − b): expanded, six terms.
        let expanded = (s * a * y + s * b * y.powi(2) + s * 3 + c * a * 2 - c * b + y * 5).normal();
        let outputs = [expanded, s * c];
        let tape = Tape::compile(&outputs, &symbols(&["x", "y", "a", "b"])).unwrap();
        // sincos (2 registers), y², the two inner sums, b·y², a·y, the outer sum, s·c; the
        // expanded form needs a product per term besides.
        assert!(
            tape.instruction_count() <= 8,
            "{} instructions: {:?}",
            tape.instruction_count(),
            tape.ops
        );
        assert_eq!(
            tape.ops
                .iter()
                .filter(|op| matches!(op, Op::SinCos(_)))
                .count(),
            1
        );
        let mut registers = tape.registers();
        let mut out = [0.0; 2];
        let point = [0.7, -1.3, 0.4, 2.5];
        tape.eval(&point, &mut registers, &mut out);
        let [xv, yv, av, bv] = point;
        let want =
            xv.sin() * (av * yv + bv * yv * yv + 3.0) + xv.cos() * (2.0 * av - bv) + 5.0 * yv;
        assert!((out[0] - want).abs() < 1e-14, "{} vs {want}", out[0]);
        assert!((out[1] - xv.sin() * xv.cos()).abs() < 1e-15);
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
