//! Constraints that depend on one another: the rank of the constraint matrix `A` at a generic
//! state. Rows of one constraint may depend on each other (a rolling contact's three rows in a
//! plane) without harm: that constraint's reaction `Aᵀλ` stays unique. Rows of *different*
//! constraints that depend on each other make their multipliers indeterminate (`y = 1` and
//! `2 y = 2`: only the sum of the two reactions is known), or the constraints contradict each
//! other (`x = 1` and `x = 2`: no configuration satisfies both), which the velocity level does
//! not see (both give `ẋ = 0`): that is decided from the holonomic equations themselves, at the
//! parameters' values.

use cas::{Expr, Symbol};

use crate::equations::Equations;
use crate::system::{ConstraintForm, System};

/// Constraints whose rows depend on one another's.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{}: constraints {} {}", if *.contradictory { "contradictory constraints" } else { "redundant constraints" }, quoted(.constraints), if *.contradictory { "cannot all hold at once" } else { "restate one another, so their separate reactions are not determined" })]
pub struct ConstraintConflict {
    /// The constraints involved, in the order of the model.
    pub constraints: Vec<String>,
    /// Whether no configuration satisfies them all (at the parameters' values); otherwise
    /// they are redundant.
    pub contradictory: bool,
}

fn quoted(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The constraints kept with multipliers whose rows depend on those of other constraints, if
/// any, and whether they contradict each other. The rank is judged at a pseudo-random state
/// (where a dependence that is not identical would show), with the parameters at their values
/// where the system gives them.
#[must_use]
pub fn constraint_conflict(system: &System, equations: &Equations) -> Option<ConstraintConflict> {
    let names = equations.constraint_names();
    if names.len() < 2 {
        return None;
    }
    let values = parameter_values(system);
    let env = generic_environment(&values);
    let rows = generic_rows(equations.constraint_matrix(), &env)?;
    let mut distinct: Vec<&String> = Vec::new();
    for n in names {
        if !distinct.contains(&n) {
            distinct.push(n);
        }
    }
    let total = rank(&rows);
    let of = |keep: &dyn Fn(&String) -> bool| -> Vec<Vec<f64>> {
        rows.iter()
            .zip(names)
            .filter(|(_, n)| keep(n))
            .map(|(r, _)| r.clone())
            .collect()
    };
    // A constraint is involved when its rows add less to the rank than they have on their own.
    let involved: Vec<String> = distinct
        .iter()
        .filter(|name| {
            let own = rank(&of(&|n| n == **name));
            let others = rank(&of(&|n| n != **name));
            total < others + own
        })
        .map(|n| (*n).clone())
        .collect();
    if involved.is_empty() {
        return None;
    }
    let contradictory = contradict(system, &involved, &env);
    Some(ConstraintConflict {
        constraints: involved,
        contradictory,
    })
}

/// The rank of the constraint matrix `A` at a generic state (the parameters at their values
/// where the system gives them): the number of independent constraints kept with multipliers.
/// When an entry cannot be evaluated there, every row counts.
#[must_use]
pub(crate) fn generic_rank(system: &System, constraint_matrix: &[Vec<Expr>]) -> usize {
    if constraint_matrix.is_empty() {
        return 0;
    }
    let values = parameter_values(system);
    let env = generic_environment(&values);
    generic_rows(constraint_matrix, &env).map_or(constraint_matrix.len(), |rows| rank(&rows))
}

/// Parameter values where known, a pseudo-random value ([`sample`]) for every other symbol.
fn generic_environment(values: &[(String, f64)]) -> impl Fn(Symbol) -> Option<f64> + '_ {
    |s: Symbol| {
        values
            .iter()
            .find(|(n, _)| *n == s.name())
            .map(|(_, v)| *v)
            .or_else(|| Some(sample(s)))
    }
}

/// The rows of `A` evaluated in `env`; `None` when an entry cannot be.
fn generic_rows(
    constraint_matrix: &[Vec<Expr>],
    env: &dyn Fn(Symbol) -> Option<f64>,
) -> Option<Vec<Vec<f64>>> {
    constraint_matrix
        .iter()
        .map(|row| row.iter().map(|e| e.eval(env).ok()).collect())
        .collect()
}

/// Numeric values of the parameters and inputs that have constant ones.
pub(crate) fn parameter_values(system: &System) -> Vec<(String, f64)> {
    let mut known: Vec<(String, f64)> = Vec::new();
    for (name, value) in system.parameters().iter().chain(system.inputs()) {
        let Some(value) = value else { continue };
        let env = |s: Symbol| known.iter().find(|(n, _)| n == s.name()).map(|(_, v)| *v);
        if let Ok(v) = value.eval(&env) {
            if v.is_finite() {
                known.push((name.clone(), v));
            }
        }
    }
    known
}

/// A value in `[0.35, 1.65]` drawn from a symbol's name and order.
pub(crate) fn sample(s: Symbol) -> f64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325 ^ 0x5851_f42d_4c95_7f2d;
    for b in s.name().bytes().chain([s.order()]) {
        h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
    }
    0.35 + 1.3 * ((h >> 11) as f64 / (1u64 << 53) as f64)
}

/// The numerical rank of `rows` (Gram–Schmidt; a remainder below 1e-9 of its row's size is
/// dependent).
pub(crate) fn rank(rows: &[Vec<f64>]) -> usize {
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for row in rows {
        let mut v = row.clone();
        let size = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        for _ in 0..2 {
            for b in &basis {
                let p: f64 = v.iter().zip(b).map(|(x, y)| x * y).sum();
                for (x, y) in v.iter_mut().zip(b) {
                    *x -= p * y;
                }
            }
        }
        let rest = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if rest > 1e-9 * size && rest > 0.0 {
            basis.push(v.iter().map(|x| x / rest).collect());
        }
    }
    basis.len()
}

/// Whether the holonomic equations of the `involved` constraints have no common solution:
/// Gauss–Newton on `Σ f²` over the coordinates, from a pseudo-random configuration, stops at
/// a positive minimum. Velocity constraints cannot contradict at the configuration level and
/// are left out.
fn contradict(system: &System, involved: &[String], env: &dyn Fn(Symbol) -> Option<f64>) -> bool {
    let functions: Vec<Expr> = system
        .constraints()
        .iter()
        .filter(|c| involved.contains(&c.name))
        .flat_map(|c| &c.equations)
        .filter_map(|f| match f {
            ConstraintForm::Holonomic(e) => Some(*e),
            ConstraintForm::Velocity(_) => None,
        })
        .collect();
    let coordinates: Vec<Symbol> = system
        .coordinates()
        .iter()
        .filter_map(|q| Expr::coordinate(q).as_symbol())
        .collect();
    if functions.len() < 2 || coordinates.is_empty() {
        return false;
    }
    let gradients: Vec<Vec<Expr>> = functions
        .iter()
        .map(|f| coordinates.iter().map(|q| f.diff(*q).normal()).collect())
        .collect();
    let mut x: Vec<f64> = coordinates.iter().map(|q| sample(*q)).collect();
    let at = |x: &[f64], e: Expr| -> Option<f64> {
        let local = |s: Symbol| coordinates.iter().position(|q| *q == s).map(|i| x[i]);
        e.eval(&|s| local(s).or_else(|| env(s)))
            .ok()
            .filter(|v| v.is_finite())
    };
    let residual =
        |x: &[f64]| -> Option<Vec<f64>> { functions.iter().map(|f| at(x, *f)).collect() };
    let norm = |r: &[f64]| r.iter().map(|v| v * v).sum::<f64>().sqrt();
    let Some(mut r) = residual(&x) else {
        return false;
    };
    for _ in 0..100 {
        let Some(j) = gradients
            .iter()
            .map(|row| row.iter().map(|e| at(&x, *e)).collect::<Option<Vec<f64>>>())
            .collect::<Option<Vec<_>>>()
        else {
            return false;
        };
        // The least-squares step, slightly damped for the dependent rows (Levenberg–
        // Marquardt): (JᵀJ + μ I) dx = −Jᵀ r.
        let m = functions.len();
        let n = coordinates.len();
        let mut a = vec![0.0; n * n];
        for p in 0..n {
            for q in 0..n {
                a[p * n + q] = (0..m).map(|k| j[k][p] * j[k][q]).sum();
            }
        }
        let scale = (0..n).map(|p| a[p * n + p]).fold(0.0f64, f64::max);
        for p in 0..n {
            a[p * n + p] += 1e-10 * scale.max(f64::MIN_POSITIVE);
        }
        let mut step: Vec<f64> = (0..n)
            .map(|p| -(0..m).map(|k| j[k][p] * r[k]).sum::<f64>())
            .collect();
        if numeric::solve_in_place(n, &mut a, &mut step).is_err() {
            return false;
        }
        let trial: Vec<f64> = x.iter().zip(&step).map(|(a, b)| a + b).collect();
        let Some(rt) = residual(&trial) else {
            return false;
        };
        let (before, after) = (norm(&r), norm(&rt));
        x = trial;
        r = rt;
        if after <= 1e-12 * (1.0 + x.iter().fold(0.0f64, |m, v| m.max(v.abs()))) {
            return false;
        }
        if after >= before * (1.0 - 1e-9) {
            break;
        }
    }
    // Stuck at a positive minimum of the residual: no common solution.
    norm(&r) > 1e-8 * (1.0 + x.iter().fold(0.0f64, |m, v| m.max(v.abs())))
}
