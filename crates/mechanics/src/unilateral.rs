//! Unilateral contacts: where along the motion a normal force (or a rope's tension) would
//! change sign, for one degree of freedom with an energy (or Jacobi) integral.
//!
//! With `h(q, q̇) = h₀` the rate is a function of the position along the motion, so the
//! reaction `N(q, q̇)` is too. Symbolically, when `h = α(q) q̇² + γ(q)` and
//! `N = N₀(q) + N₂(q) q̇²`, the reaction along the motion is `N₀ + N₂ (h₀ − γ)/α`. Numerically,
//! from the initial state the position is stepped in the direction of motion, the rate taken
//! from the integral, until `N` changes sign (bisected to machine precision) or the motion
//! turns back.

use cas::{Expr, Symbol};

use crate::compiled_eval::CompiledExprs;
use crate::equations::Equations;

/// What happens to a unilateral reaction along the motion from the initial state.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Unilateral {
    /// The reaction changes sign at this position and rate: contact is lost (or the rope
    /// goes slack) there.
    Lost {
        /// The coordinate.
        coordinate: String,
        /// Its value where the reaction vanishes.
        value: f64,
        /// Its rate there.
        rate: f64,
    },
    /// The reaction is already of the wrong sign at the initial state.
    LostAtStart,
    /// The reaction keeps its sign until the motion turns back at this position (and then
    /// retraces the same states).
    Kept {
        /// The coordinate.
        coordinate: String,
        /// Where the motion turns back, if it does within the scanned range.
        turning_point: Option<f64>,
    },
}

/// `N` along the motion, `N₀ + N₂ (h₀ − γ)/α` with `h₀` written as the symbol `h_0`, when the
/// system has one coordinate, an energy or Jacobi integral `α q̇² + γ`, and `N` is even in `q̇`
/// with only a `q̇²` term.
#[must_use]
pub fn along_motion(equations: &Equations, reaction: Expr) -> Option<Expr> {
    let (q, h) = integral(equations)?;
    let qd = Expr::rate(q, 1);
    let qd_symbol = qd.as_symbol()?;
    let (alpha, gamma) = quadratic(h, qd_symbol)?;
    let (n2, n0) = quadratic(reaction, qd_symbol)?;
    let h0 = Expr::symbol("h_0");
    Some((n0 + n2 * (h0 - gamma) / alpha).normal())
}

/// `e = a q̇² + c` exactly (no odd powers, degree 2 at most): `(a, c)`.
fn quadratic(e: Expr, qd: Symbol) -> Option<(Expr, Expr)> {
    let d1 = e.diff(qd);
    let a = (d1.diff(qd) / 2).normal();
    if !a.diff(qd).is_zero() {
        return None;
    }
    let c = e.subs(&[(Expr::from_symbol(qd), Expr::zero())]).normal();
    let back = (a * Expr::from_symbol(qd).powi(2) + c - e).normal();
    back.is_zero().then_some((a, c))
}

fn integral(equations: &Equations) -> Option<(&str, Expr)> {
    let [q] = equations.coordinates() else {
        return None;
    };
    let h = equations
        .first_integrals()
        .iter()
        .find(|f| f.kind == "energy" || f.kind == "jacobi")?
        .value;
    Some((q.as_str(), h))
}

/// Scans the motion from `(q0, q̇0)` for a sign change of `reaction`, with parameters from
/// `parameters` (every other symbol but the coordinate, its rate and `t` must have a value).
/// `None` when the system is not one degree of freedom with an energy integral, the initial
/// state is an equilibrium, or a value is missing.
#[must_use]
pub fn scan(
    equations: &Equations,
    reaction: Expr,
    initial: (f64, f64),
    parameters: &dyn Fn(Symbol) -> Option<f64>,
) -> Option<Unilateral> {
    let (q, h) = integral(equations)?;
    let q_symbol = Expr::coordinate(q).as_symbol()?;
    let qd_symbol = Expr::rate(q, 1).as_symbol()?;
    let by_tree = |e: Expr, x: f64, v: f64| -> Option<f64> {
        let env = |s: Symbol| {
            if s == q_symbol {
                Some(x)
            } else if s == qd_symbol {
                Some(v)
            } else if Expr::time().as_symbol() == Some(s) {
                Some(0.0)
            } else {
                parameters(s)
            }
        };
        e.eval(&env).ok().filter(|y| y.is_finite())
    };
    // The scan below evaluates both tens of thousands of times: on tapes where they compile.
    let time = Expr::time().as_symbol()?;
    let compile = |e: Expr| CompiledExprs::new(&[e], &[q_symbol, qd_symbol, time], &[], parameters);
    let tapes = [(h, compile(h)), (reaction, compile(reaction))];
    let eval = |e: Expr, x: f64, v: f64| -> Option<f64> {
        match tapes.iter().find(|(t, _)| *t == e) {
            Some((_, Some(tape))) => tape.eval_one(&[x, v, 0.0]),
            _ => by_tree(e, x, v),
        }
    };
    let (q0, qd0) = initial;
    let h0 = eval(h, q0, qd0)?;
    let n_start = eval(reaction, q0, qd0)?;
    if n_start < 0.0 {
        return Some(Unilateral::LostAtStart);
    }
    let direction = if qd0 != 0.0 {
        qd0.signum()
    } else {
        // From rest the motion starts down the potential: q̈ has the sign of −∂h/∂q.
        let step = 1e-7;
        let slope = (eval(h, q0 + step, 0.0)? - eval(h, q0 - step, 0.0)?) / (2.0 * step);
        if slope == 0.0 {
            return None;
        }
        -slope.signum()
    };
    // The rate on the motion at q: the root of α v² + β v + c = h₀ in the direction of motion.
    let rate_at = |x: f64| -> Option<Option<f64>> {
        let (hp, hm, hz) = (eval(h, x, 1.0)?, eval(h, x, -1.0)?, eval(h, x, 0.0)?);
        let (a, b, c) = ((hp + hm) / 2.0 - hz, (hp - hm) / 2.0, hz - h0);
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 || a <= 0.0 {
            return Some(None);
        }
        Some(Some((-b + direction * disc.sqrt()) / (2.0 * a)))
    };
    let reaction_at = |x: f64| -> Option<Option<(f64, f64)>> {
        match rate_at(x)? {
            None => Some(None),
            Some(v) => Some(Some((eval(reaction, x, v)?, v))),
        }
    };
    let step = 1e-3 * direction;
    let mut previous = q0;
    for k in 1..=20_000 {
        let x = q0 + f64::from(k) * step;
        let Some((n, _)) = reaction_at(x)? else {
            return Some(Unilateral::Kept {
                coordinate: q.to_string(),
                turning_point: Some(previous),
            });
        };
        if n < 0.0 {
            let (mut lo, mut hi) = (previous, x);
            for _ in 0..60 {
                let mid = (lo + hi) / 2.0;
                match reaction_at(mid)? {
                    Some((m, _)) if m >= 0.0 => lo = mid,
                    _ => hi = mid,
                }
            }
            let value = (lo + hi) / 2.0;
            let rate = rate_at(value)?.unwrap_or(0.0);
            return Some(Unilateral::Lost {
                coordinate: q.to_string(),
                value,
                rate,
            });
        }
        previous = x;
    }
    Some(Unilateral::Kept {
        coordinate: q.to_string(),
        turning_point: None,
    })
}
