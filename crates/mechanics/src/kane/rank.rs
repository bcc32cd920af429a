//! The number of independent constraint rows of a system, read off its graph (no derivation):
//! `lagrange check` counts the degrees of freedom as `lagrange solve` does, `n − rank A`,
//! where a 3-D rolling contact is one statement with two or three rows.

use cas::Expr;

use super::dynamics::KaneSystem;
use crate::constraint_rank::{parameter_values, rank, sample};
use crate::system::System;

/// Entries below this fraction of the largest are rounding noise.
const NOISE: f64 = 1e-12;

/// The rank of the constraint rows `A` (holonomic rows `∂f/∂q`, then velocity rows) at a
/// pseudo-random state, the parameters at their values where the system gives them; `None`
/// when the system's expressions cannot be evaluated (a function the numeric evaluation
/// does not know, a symbol without a value).
#[must_use]
pub fn constraint_rank(system: &System) -> Option<usize> {
    if system.constraints().is_empty() {
        return Some(0);
    }
    let known = parameter_values(system);
    let names: Vec<String> = system
        .parameters()
        .iter()
        .chain(system.inputs())
        .map(|(n, _)| n.clone())
        .collect();
    let values: Vec<f64> = names
        .iter()
        .map(|n| {
            known
                .iter()
                .find(|(k, _)| k == n)
                .map(|(_, v)| *v)
                .or_else(|| Expr::symbol(n).as_symbol().map(sample))
                .unwrap_or(0.5)
        })
        .collect();
    let kane = KaneSystem::new(system, &names).ok()?;
    let q: Vec<f64> = system
        .coordinates()
        .iter()
        .map(|c| Expr::coordinate(c).as_symbol().map_or(0.5, sample))
        .collect();
    let (mut rows, _) = kane.constraint_rows(&q, 0.3, &values);
    if rows.iter().flatten().any(|x| !x.is_finite()) {
        return None;
    }
    // Entries at rounding level of the whole matrix are zeros that the evaluation did not
    // cancel exactly (the rolling cone's vertical row is 1e-17): without this, a row of such
    // noise would count as independent, since `rank` judges each row against its own size.
    let scale = rows.iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
    for x in rows.iter_mut().flatten() {
        if x.abs() <= NOISE * scale {
            *x = 0.0;
        }
    }
    Some(rank(&rows))
}
