//! Exact solving of one equation `e = 0` for one unknown, the way a mechanics course does it:
//! pull out the factors `x`, `sin x`, `cos x`, `tan x`, then solve what is left when it is
//! linear in `sin`/`cos`/`tan` of the angle, or a polynomial of degree ≤ 2 in `cos x`, `sin x`,
//! `tan x` or `x` itself. Every solution carries the conditions under which it exists (the
//! bead on a hoop: `θ = ±acos(g/(Ω² R))` only when `|g/(Ω² R)| ≤ 1`).
//!
//! The solutions of one equation are *all* of them (modulo 2π for an angle) when
//! [`solve_for`] returns [`Solved::Exact`]; anything else is [`Solved::Unsolved`], and the
//! caller falls back on numbers.

use crate::expr::{Expr, Symbol};

/// A condition for a solution to exist, on the parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Condition {
    /// `|e| ≤ 1` (an `acos`/`asin` argument).
    AbsAtMostOne(Expr),
    /// `e ≥ 0` (a discriminant).
    NonNegative(Expr),
    /// `e ≠ 0` (a leading coefficient divided by).
    NonZero(Expr),
    /// `e = 0` (a leading coefficient that vanishes, lowering the degree).
    Zero(Expr),
}

impl Condition {
    /// Whether the condition holds for numbers (`None` when it cannot be evaluated). A
    /// relative tolerance keeps a boundary case such as `|g/(Ω²R)| = 1` on the existing side.
    pub fn holds(&self, env: &dyn Fn(Symbol) -> Option<f64>) -> Option<bool> {
        let tol = 1e-12;
        match self {
            Condition::AbsAtMostOne(e) => e.eval(env).ok().map(|x| x.abs() <= 1.0 + tol),
            Condition::NonNegative(e) => e.eval(env).ok().map(|x| x >= -tol),
            Condition::NonZero(e) => e.eval(env).ok().map(|x| x.abs() > tol),
            Condition::Zero(e) => e.eval(env).ok().map(|x| x.abs() <= tol),
        }
    }
}

/// One solution `x = value`, valid where every condition holds.
#[derive(Clone, Debug)]
pub struct Solution {
    /// The value of the unknown.
    pub value: Expr,
    /// When the solution exists.
    pub conditions: Vec<Condition>,
}

/// The outcome of [`solve_for`].
#[derive(Clone, Debug)]
pub enum Solved {
    /// All solutions (for an angle: all modulo 2π), each with its existence conditions.
    Exact(Vec<Solution>),
    /// The equation is not of a form solved exactly (or holds identically).
    Unsolved,
}

/// Whether `e` depends on the symbol `x`.
#[must_use]
pub fn depends_on(e: Expr, x: Symbol) -> bool {
    !e.diff(x).is_zero()
}

/// Solves `equation = 0` for `x` exactly, or says it cannot (see the module doc).
#[must_use]
pub fn solve_for(equation: Expr, x: Symbol) -> Solved {
    let (mut numerator, _) = equation.normal().numer_denom();
    if numerator.is_zero() || !depends_on(numerator, x) {
        return if numerator.is_zero() {
            Solved::Unsolved
        } else {
            Solved::Exact(Vec::new())
        };
    }
    let var = Expr::from_symbol(x);
    let pi = Expr::pi();
    let mut solutions: Vec<Solution> = Vec::new();
    let plain = |value: Expr| Solution {
        value,
        conditions: Vec::new(),
    };
    // Factors of the form x, sin x, cos x, tan x: each divides the numerator when the
    // numerator has no term free of it.
    let factors: [(Expr, Vec<Expr>); 4] = [
        (var, vec![Expr::zero()]),
        (var.sin(), vec![Expr::zero(), pi]),
        (var.cos(), vec![pi / 2, -(pi / 2)]),
        (var.tan(), vec![Expr::zero(), pi]),
    ];
    for (factor, roots) in factors {
        let mut found = false;
        for _ in 0..16 {
            match numerator.coeff(factor, 0) {
                Some(rest) if rest.is_zero() && !numerator.is_zero() => {
                    numerator = (numerator / factor).normal();
                    found = true;
                }
                _ => break,
            }
        }
        if found {
            solutions.extend(roots.into_iter().map(plain));
        }
    }
    if !depends_on(numerator, x) {
        return Solved::Exact(solutions);
    }
    match solve_remainder(numerator, x) {
        Some(more) => {
            solutions.extend(more);
            Solved::Exact(solutions)
        }
        None => Solved::Unsolved,
    }
}

/// The coefficients `[c0, c1, c2]` of `e` as a polynomial of degree ≤ 2 in the atom `a`
/// (coefficients free of `x`), or `None`.
fn quadratic_in(e: Expr, a: Expr, x: Symbol) -> Option<[Expr; 3]> {
    let c: Vec<Expr> = (0..3).map(|k| e.coeff(a, k)).collect::<Option<_>>()?;
    let rebuilt = c[0] + c[1] * a + c[2] * a.powi(2);
    if !(rebuilt - e).is_zero() || c.iter().any(|c| depends_on(*c, x)) {
        return None;
    }
    Some([c[0], c[1], c[2]])
}

/// Roots of `c0 + c1 a + c2 a² = 0` with their conditions; `None` when the polynomial is
/// identically constant in `a`.
fn quadratic_roots(c: [Expr; 3]) -> Option<Vec<Solution>> {
    let [c0, c1, c2] = c;
    if !c2.is_zero() {
        let disc = (c1.powi(2) - 4 * c2 * c0).normal();
        let root = disc.sqrt();
        // A symbolic leading coefficient may vanish for the numbers at hand: then the equation
        // is linear, and its root is a branch of its own.
        let symbolic = c2.as_number().is_none();
        let mut conditions = vec![Condition::NonNegative(disc)];
        if symbolic {
            conditions.push(Condition::NonZero(c2));
        }
        let mut out: Vec<Solution> = if disc.is_zero() {
            vec![Solution {
                value: (-c1 / (2 * c2)).normal(),
                conditions: conditions[1..].to_vec(),
            }]
        } else {
            [root, -root]
                .into_iter()
                .map(|r| Solution {
                    value: ((-c1 + r) / (2 * c2)).normal(),
                    conditions: conditions.clone(),
                })
                .collect()
        };
        if symbolic && !c1.is_zero() {
            out.push(Solution {
                value: (-c0 / c1).normal(),
                conditions: vec![Condition::Zero(c2), Condition::NonZero(c1)],
            });
        }
        return Some(out);
    }
    if !c1.is_zero() {
        let conditions = if c1.as_number().is_some() {
            Vec::new()
        } else {
            vec![Condition::NonZero(c1)]
        };
        return Some(vec![Solution {
            value: (-c0 / c1).normal(),
            conditions,
        }]);
    }
    None
}

/// Solves a numerator with no factor `x`, `sin x`, `cos x`, `tan x` left.
/// The solutions of `e = 0` when `e` is at most quadratic in one trigonometric function `f` of
/// `x`: each root `r` of that quadratic gives the two angles `angles(r)`, which exist only when
/// `|r| ≤ 1` if `bounded` (sine and cosine).
fn inverse_trig(
    e: Expr,
    f: Expr,
    x: Symbol,
    bounded: bool,
    angles: impl Fn(Expr) -> [Expr; 2],
) -> Option<Vec<Solution>> {
    let roots = quadratic_roots(quadratic_in(e, f, x)?)?;
    Some(
        roots
            .into_iter()
            .flat_map(|r| {
                let mut conditions = r.conditions.clone();
                if bounded {
                    conditions.push(Condition::AbsAtMostOne(r.value));
                }
                angles(r.value).map(|value| Solution {
                    value,
                    conditions: conditions.clone(),
                })
            })
            .collect(),
    )
}

fn solve_remainder(e: Expr, x: Symbol) -> Option<Vec<Solution>> {
    let var = Expr::from_symbol(x);
    let (s, c, t) = (var.sin(), var.cos(), var.tan());
    let marks = [
        Expr::symbol("__solve_sin"),
        Expr::symbol("__solve_cos"),
        Expr::symbol("__solve_tan"),
    ];
    let masked = e.subs(&[(s, marks[0]), (c, marks[1]), (t, marks[2])]);
    let uses = |m: Expr| m.as_symbol().is_some_and(|m| depends_on(masked, m));
    let (has_s, has_c, has_t) = (uses(marks[0]), uses(marks[1]), uses(marks[2]));
    let trig_free = !depends_on(masked, x);
    let pi = Expr::pi();
    match (trig_free, has_s, has_c, has_t) {
        // A polynomial in x itself.
        (_, false, false, false) => quadratic_roots(quadratic_in(e, var, x)?),
        // Only cos x: x = ±acos(r), |r| ≤ 1.
        (true, false, true, false) => inverse_trig(e, c, x, true, |r| {
            let a = r.acos();
            [a, -a]
        }),
        // Only sin x: x = asin(r), π − asin(r).
        (true, true, false, false) => inverse_trig(e, s, x, true, |r| {
            let a = r.asin();
            [a, pi - a]
        }),
        // Only tan x: x = atan(r), atan(r) + π.
        (true, false, false, true) => inverse_trig(e, t, x, false, |r| {
            let a = r.atan();
            [a, a + pi]
        }),
        // a sin x + b cos x + d = 0.
        (true, true, true, false) => {
            let (coefficients, d) = e.affine_coefficients(&[s, c])?;
            let (a, b) = (coefficients[0], coefficients[1]);
            if [a, b, d].iter().any(|k| depends_on(*k, x)) {
                return None;
            }
            if d.is_zero() {
                // tan x = −b/a.
                let phi = Expr::atan2(-b, a);
                return Some(vec![
                    Solution {
                        value: phi,
                        conditions: Vec::new(),
                    },
                    Solution {
                        value: phi + pi,
                        conditions: Vec::new(),
                    },
                ]);
            }
            // b cos x + a sin x = R cos(x − φ), R = √(a² + b²), φ = atan2(a, b).
            let radius = (a.powi(2) + b.powi(2)).normal().sqrt();
            let phi = Expr::atan2(a, b);
            let ratio = (-d / radius).normal();
            let opening = ratio.acos();
            let conditions = vec![Condition::AbsAtMostOne(ratio)];
            Some(
                [phi + opening, phi - opening]
                    .into_iter()
                    .map(|value| Solution {
                        value,
                        conditions: conditions.clone(),
                    })
                    .collect(),
            )
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values(s: Solved, env: &dyn Fn(Symbol) -> Option<f64>) -> Vec<f64> {
        let Solved::Exact(list) = s else {
            panic!("not solved")
        };
        let mut v: Vec<f64> = list
            .iter()
            .filter(|s| s.conditions.iter().all(|c| c.holds(env) == Some(true)))
            .filter_map(|s| s.value.eval(env).ok())
            .map(|x| x.sin().atan2(x.cos()))
            .collect();
        v.sort_by(f64::total_cmp);
        v
    }

    #[test]
    fn bead_on_hoop_has_the_off_centre_branch_only_when_fast() {
        let th = Expr::coordinate("theta");
        let (m, r, w, g) = (
            Expr::symbol("m"),
            Expr::symbol("R"),
            Expr::symbol("Omega"),
            Expr::symbol("g"),
        );
        let f = m * r.powi(2) * w.powi(2) * th.sin() * th.cos() - m * g * r * th.sin();
        let x = th.as_symbol().unwrap();
        let env = |omega: f64| {
            move |s: Symbol| match s.name() {
                "m" => Some(1.0),
                "R" => Some(0.5),
                "g" => Some(9.81),
                "Omega" => Some(omega),
                _ => None,
            }
        };
        let slow = values(solve_for(f, x), &env(4.0));
        assert_eq!(slow.len(), 2, "{slow:?}");
        let fast = values(solve_for(f, x), &env(6.0));
        assert_eq!(fast.len(), 4, "{fast:?}");
        let expected = (9.81 / (36.0 * 0.5_f64)).acos();
        assert!(fast.iter().any(|v| (v - expected).abs() < 1e-12));
        assert!(fast.iter().any(|v| (v + expected).abs() < 1e-12));
    }

    #[test]
    fn linear_in_sin_and_cos() {
        let th = Expr::coordinate("phi");
        let x = th.as_symbol().unwrap();
        // 3 sin φ + 4 cos φ = 2.
        let f = 3 * th.sin() + 4 * th.cos() - 2;
        let env = |_: Symbol| None;
        let v = values(solve_for(f, x), &env);
        assert_eq!(v.len(), 2);
        for phi in v {
            assert!((3.0 * phi.sin() + 4.0 * phi.cos() - 2.0).abs() < 1e-12);
        }
    }

    #[test]
    fn quadratic_in_the_variable() {
        let y = Expr::coordinate("y");
        let x = y.as_symbol().unwrap();
        let f = y.powi(2) - 3 * y + 2;
        let v = values(solve_for(f, x), &|_| None);
        assert_eq!(v.len(), 2);
        assert!((v[0] - 1.0).abs() < 1e-12 && (v[1] - 2.0).abs() < 1e-12);
    }

    #[test]
    fn a_vanishing_leading_coefficient_keeps_the_linear_root() {
        let y = Expr::coordinate("y");
        let x = y.as_symbol().unwrap();
        // a y² − 3 y + 2 with a = 0: y = 2/3 only; with a = 1: y = 1, 2.
        let f = Expr::symbol("a") * y.powi(2) - 3 * y + 2;
        let env = |a: f64| move |s: Symbol| (s.name() == "a").then_some(a);
        let v = values(solve_for(f, x), &env(0.0));
        assert_eq!(v.len(), 1);
        assert!((v[0] - 2.0 / 3.0).abs() < 1e-12);
        let v = values(solve_for(f, x), &env(1.0));
        assert_eq!(v.len(), 2);
    }
}
