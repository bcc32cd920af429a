//! A flat program over the `cas` expression graph: every distinct sub-expression once, in an
//! order where operands come first, evaluated over any [`Scalar`].
//!
//! This is how the Kane derivation avoids the normal form: `cas` expressions are hash-consed,
//! so the shared parts of a multibody model's geometry (a rotation matrix used by four points,
//! a `norm()` under a contact point) are one node each, and they stay one slot each here.
//! Evaluating with dual numbers then gives their exact derivatives.

use std::collections::HashMap;

use cas::{Constant, Expr, Func, Node, SymbolKind};

use super::scalar::Scalar;
use super::KaneError;

/// One operation; operands are earlier slots.
#[derive(Clone, Debug)]
enum Op {
    /// A number of the model: its value and the exact number (kept by symbolic scalars).
    Const(f64, Expr),
    Var(usize),
    Add(Box<[usize]>),
    Mul(Box<[usize]>),
    PowI(usize, i32),
    PowF(usize, f64, Expr),
    Pow(usize, usize),
    Sin(usize),
    Cos(usize),
    Tan(usize),
    Asin(usize),
    Acos(usize),
    Atan(usize),
    Atan2(usize, usize),
    Exp(usize),
    Ln(usize),
    Abs(usize),
    Sign(usize),
}

/// Where a program's variables come from: coordinates `q`, rates `q̇`, time, named values.
#[derive(Clone, Debug)]
pub struct Variables {
    coordinates: Vec<String>,
    values: Vec<String>,
}

impl Variables {
    /// Coordinates (and their rates) and the names of the values (parameters, inputs).
    pub fn new(coordinates: &[String], values: &[String]) -> Variables {
        Variables {
            coordinates: coordinates.to_vec(),
            values: values.to_vec(),
        }
    }

    /// How many slots the variables take: `q`, `q̇`, `t`, values.
    pub fn len(&self) -> usize {
        2 * self.coordinates.len() + 1 + self.values.len()
    }

    /// Never: time is always a variable.
    pub fn is_empty(&self) -> bool {
        false
    }

    fn slot(&self, name: &str, kind: SymbolKind) -> Result<usize, KaneError> {
        let n = self.coordinates.len();
        let unknown = || KaneError::UnknownSymbol(name.to_string());
        match kind {
            SymbolKind::Time => Ok(2 * n),
            SymbolKind::TimeFunction { order } => {
                match self.coordinates.iter().position(|c| c == name) {
                    Some(j) if order == 0 => Ok(j),
                    Some(j) if order == 1 => Ok(n + j),
                    Some(_) => Err(KaneError::Acceleration(name.to_string())),
                    None if order == 0 => self.value_slot(name).ok_or_else(unknown),
                    None => Err(unknown()),
                }
            }
            _ => self.value_slot(name).ok_or_else(unknown),
        }
    }

    fn value_slot(&self, name: &str) -> Option<usize> {
        let base = 2 * self.coordinates.len() + 1;
        self.values.iter().position(|v| v == name).map(|k| base + k)
    }
}

/// A straight-line program with outputs.
#[derive(Clone, Debug)]
pub struct Program {
    ops: Vec<Op>,
    outputs: Vec<usize>,
    /// The symbol each variable slot read stands for.
    symbols: Vec<(usize, Expr)>,
}

/// Builds a program: each expression node becomes one slot, found again through `seen`.
struct Builder<'v> {
    vars: &'v Variables,
    ops: Vec<Op>,
    seen: HashMap<Expr, usize>,
    symbols: Vec<(usize, Expr)>,
}

impl Program {
    /// The program computing `outputs` (in order) from the variables.
    ///
    /// # Errors
    /// A symbol that is none of the variables, or an acceleration in an expression.
    pub fn new(vars: &Variables, outputs: &[Expr]) -> Result<Program, KaneError> {
        let mut b = Builder {
            vars,
            ops: Vec::new(),
            seen: HashMap::new(),
            symbols: Vec::new(),
        };
        let outputs = outputs
            .iter()
            .map(|e| b.slot(*e))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Program {
            ops: b.ops,
            outputs,
            symbols: b.symbols,
        })
    }

    /// The symbols the program reads, with their variable slots.
    pub fn symbols(&self) -> &[(usize, Expr)] {
        &self.symbols
    }

    /// The number of operations (the size of the graph).
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    /// Whether the program has no operation (no outputs).
    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// The outputs at `vars` (one value per variable slot).
    pub fn eval<T: Scalar>(&self, vars: &[T]) -> Vec<T> {
        let mut s: Vec<T> = Vec::with_capacity(self.ops.len());
        for op in &self.ops {
            let x = match op {
                Op::Const(c, e) => T::exact(*e, *c),
                Op::Var(k) => vars.get(*k).copied().unwrap_or(T::constant(0.0)),
                Op::Add(a) => a[1..].iter().fold(s[a[0]], |acc, k| acc + s[*k]),
                Op::Mul(a) => a[1..].iter().fold(s[a[0]], |acc, k| acc * s[*k]),
                Op::PowI(a, k) => s[*a].powi(*k),
                Op::PowF(a, p, e) => s[*a].pow_exact(*e, *p),
                Op::Pow(a, e) => s[*a].pow(s[*e]),
                Op::Sin(a) => s[*a].sin(),
                Op::Cos(a) => s[*a].cos(),
                Op::Tan(a) => s[*a].sin() / s[*a].cos(),
                Op::Asin(a) => s[*a].asin(),
                Op::Acos(a) => s[*a].acos(),
                Op::Atan(a) => s[*a].atan(),
                Op::Atan2(y, x) => s[*y].atan2(s[*x]),
                Op::Exp(a) => s[*a].exp(),
                Op::Ln(a) => s[*a].ln(),
                Op::Abs(a) => s[*a].abs(),
                Op::Sign(a) => s[*a].sign(),
            };
            s.push(x);
        }
        self.outputs.iter().map(|k| s[*k]).collect()
    }
}

impl Builder<'_> {
    fn slot(&mut self, e: Expr) -> Result<usize, KaneError> {
        if let Some(k) = self.seen.get(&e) {
            return Ok(*k);
        }
        let op = self.op(e)?;
        self.ops.push(op);
        let k = self.ops.len() - 1;
        self.seen.insert(e, k);
        Ok(k)
    }

    fn all(&mut self, args: &[Expr]) -> Result<Box<[usize]>, KaneError> {
        args.iter().map(|a| self.slot(*a)).collect()
    }

    fn op(&mut self, e: Expr) -> Result<Op, KaneError> {
        Ok(match e.node() {
            Node::Number(n) => Op::Const(n.to_f64(), e),
            Node::Constant(Constant::Pi) => Op::Const(std::f64::consts::PI, e),
            Node::Constant(_) => return Err(KaneError::UnknownSymbol(format!("{e:?}"))),
            Node::Symbol(s) => {
                let k = self.vars.slot(s.name(), s.kind())?;
                self.symbols.push((k, e));
                Op::Var(k)
            }
            Node::Add(a) => Op::Add(self.all(a)?),
            Node::Mul(a) => Op::Mul(self.all(a)?),
            Node::Pow([b, x]) => {
                let base = self.slot(*b)?;
                match x.as_number() {
                    Some(n) => match n.to_i64().and_then(|k| i32::try_from(k).ok()) {
                        Some(k) if n.is_integer() => Op::PowI(base, k),
                        _ => Op::PowF(base, n.to_f64(), *x),
                    },
                    None => Op::Pow(base, self.slot(*x)?),
                }
            }
            Node::Func(f, args) => self.func(*f, args)?,
        })
    }

    fn func(&mut self, f: Func, args: &[Expr]) -> Result<Op, KaneError> {
        let a = self.all(args)?;
        let one = |k: usize| a.get(k).copied().ok_or(KaneError::Arity(f.name()));
        Ok(match f {
            Func::Sin => Op::Sin(one(0)?),
            Func::Cos => Op::Cos(one(0)?),
            Func::Tan => Op::Tan(one(0)?),
            Func::Asin => Op::Asin(one(0)?),
            Func::Acos => Op::Acos(one(0)?),
            Func::Atan => Op::Atan(one(0)?),
            Func::Atan2 => Op::Atan2(one(0)?, one(1)?),
            Func::Exp => Op::Exp(one(0)?),
            Func::Ln => Op::Ln(one(0)?),
            Func::Abs => Op::Abs(one(0)?),
            Func::Sign => Op::Sign(one(0)?),
            _ => return Err(KaneError::UnknownFunction(f.name())),
        })
    }
}
