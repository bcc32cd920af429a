//! Substitution and numeric evaluation.
//!
//! [`Expr::subs`] replaces sub-expressions (usually symbols) structurally, sharing work across
//! the expression DAG; [`Expr::eval`] computes an `f64` from values given for the symbols.

use rustc_hash::FxHashMap;

use crate::expr::{Constant, Expr, Node, Symbol};
use crate::normal::eval_float;

/// Why an expression could not be evaluated.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum EvalError {
    /// A symbol had no value.
    #[error("no value for `{0}`")]
    Unbound(String),
}

impl Expr {
    /// Replaces every occurrence of each `from` by its `to` (structural: `from` is usually a
    /// symbol). The result is canonicalised by the constructors but not normalised.
    pub fn subs(self, pairs: &[(Expr, Expr)]) -> Expr {
        let map: FxHashMap<Expr, Expr> = pairs.iter().copied().collect();
        let mut memo: FxHashMap<Expr, Expr> = FxHashMap::default();
        subs_rec(self, &map, &mut memo)
    }

    /// The numeric value, given a value for every symbol (`t` and coordinates included).
    pub fn eval(self, env: &dyn Fn(Symbol) -> Option<f64>) -> Result<f64, EvalError> {
        let mut memo: FxHashMap<Expr, f64> = FxHashMap::default();
        eval_rec(self, env, &mut memo)
    }

    /// The numeric value with symbols looked up by name in a map.
    pub fn eval_map(self, values: &FxHashMap<Symbol, f64>) -> Result<f64, EvalError> {
        self.eval(&|s| values.get(&s).copied())
    }
}

fn subs_rec(e: Expr, map: &FxHashMap<Expr, Expr>, memo: &mut FxHashMap<Expr, Expr>) -> Expr {
    if let Some(&to) = map.get(&e) {
        return to;
    }
    if let Some(&r) = memo.get(&e) {
        return r;
    }
    let r = match e.node() {
        Node::Number(_) | Node::Symbol(_) | Node::Constant(_) => e,
        Node::Add(t) => Expr::add_all(
            t.iter()
                .map(|x| subs_rec(*x, map, memo))
                .collect::<Vec<_>>(),
        ),
        Node::Mul(f) => Expr::mul_all(
            f.iter()
                .map(|x| subs_rec(*x, map, memo))
                .collect::<Vec<_>>(),
        ),
        Node::Pow([b, x]) => subs_rec(*b, map, memo).pow(subs_rec(*x, map, memo)),
        Node::Func(f, args) => {
            Expr::func(*f, args.iter().map(|x| subs_rec(*x, map, memo)).collect())
        }
    };
    memo.insert(e, r);
    r
}

fn eval_rec(
    e: Expr,
    env: &dyn Fn(Symbol) -> Option<f64>,
    memo: &mut FxHashMap<Expr, f64>,
) -> Result<f64, EvalError> {
    if let Some(&v) = memo.get(&e) {
        return Ok(v);
    }
    let v = match e.node() {
        Node::Number(n) => n.to_f64(),
        Node::Symbol(s) => env(*s).ok_or_else(|| EvalError::Unbound(symbol_text(*s)))?,
        Node::Constant(Constant::Pi) => std::f64::consts::PI,
        Node::Add(t) => {
            let mut acc = 0.0;
            for x in t.iter() {
                acc += eval_rec(*x, env, memo)?;
            }
            acc
        }
        Node::Mul(f) => {
            let mut acc = 1.0;
            for x in f.iter() {
                acc *= eval_rec(*x, env, memo)?;
            }
            acc
        }
        Node::Pow([b, x]) => {
            let base = eval_rec(*b, env, memo)?;
            match x.as_number().and_then(|n| n.to_i64()) {
                Some(k) if (i32::MIN as i64..=i32::MAX as i64).contains(&k) => base.powi(k as i32),
                _ => base.powf(eval_rec(*x, env, memo)?),
            }
        }
        Node::Func(f, args) => {
            let mut values = Vec::with_capacity(args.len());
            for a in args.iter() {
                values.push(eval_rec(*a, env, memo)?);
            }
            eval_float(*f, &values).unwrap_or(f64::NAN)
        }
    };
    memo.insert(e, v);
    Ok(v)
}

/// The SymPy-syntax name of a symbol (`theta_d` for the rate of `theta`).
pub(crate) fn symbol_text(s: Symbol) -> String {
    let mut name = s.name().to_owned();
    if s.order() > 0 {
        name.push('_');
        name.extend(std::iter::repeat_n('d', s.order() as usize));
    }
    name
}
