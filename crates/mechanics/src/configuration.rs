//! The configuration a state of the coordinates stands for — every point's position and
//! every body's orientation — so that states which differ in their coordinates but not in
//! the system are told apart from distinct ones: a polar radius `−r` at `θ + π` is the point
//! `r` at `θ`, and such a double cover must not list one equilibrium twice.

use cas::{Expr, Symbol};

use crate::equations::Equations;
use crate::equilibria::{EquilibriumSet, Repeated, Values};
use crate::system::System;

/// Every particle's and point's position, every body's centre and rotation matrix, at the
/// coordinates `q` (in the order of `equations.coordinates()`; the coordinates that
/// constraints eliminated follow from them), `t = 0`. `None` when something does not evaluate.
#[must_use]
pub fn configuration(
    system: &System,
    equations: &Equations,
    q: &[f64],
    values: &Values,
) -> Option<Vec<f64>> {
    let mut known: Vec<(Symbol, f64)> = equations
        .coordinates()
        .iter()
        .zip(q)
        .filter_map(|(name, v)| Some((Expr::coordinate(name).as_symbol()?, *v)))
        .collect();
    known.extend(Expr::time().as_symbol().map(|t| (t, 0.0)));
    let lookup = |known: &[(Symbol, f64)], s: Symbol| {
        known
            .iter()
            .find(|(k, _)| *k == s)
            .map(|(_, v)| *v)
            .or_else(|| values.get(s.name()).copied())
    };
    for elimination in equations.eliminated() {
        let value = elimination.value.eval(&|s| lookup(&known, s)).ok()?;
        known.push((
            Expr::coordinate(&elimination.coordinate).as_symbol()?,
            value,
        ));
    }
    let env = |s: Symbol| lookup(&known, s);
    let vectors = system
        .particles()
        .iter()
        .map(|p| &p.position)
        .chain(system.points().iter().map(|(_, r)| r))
        .chain(system.bodies().iter().map(|b| &b.centre))
        .chain(system.bodies().iter().flat_map(|b| b.rotation.iter()));
    let mut out = Vec::new();
    for vector in vectors {
        for e in vector {
            out.push(e.eval(&env).ok().filter(|v| v.is_finite())?);
        }
    }
    Some(out)
}

/// Keeps one equilibrium of each configuration: of those the coordinates reach twice, the one
/// with fewest negative coordinates that are not angles (a polar radius `r ≥ 0`), and records
/// the others in [`EquilibriumSet::repeated`]. Returns the indices kept, in order (to keep
/// lists made alongside `set.equilibria` in step).
pub fn keep_distinct_configurations(
    set: &mut EquilibriumSet,
    system: &System,
    equations: &Equations,
    values: &Values,
    periodic: &[bool],
) -> Vec<usize> {
    let configurations: Vec<Option<Vec<f64>>> = set
        .equilibria
        .iter()
        .map(|e| configuration(system, equations, &e.values, values))
        .collect();
    let same = |a: usize, b: usize| match (&configurations[a], &configurations[b]) {
        (Some(x), Some(y)) => x
            .iter()
            .zip(y)
            .all(|(u, v)| (u - v).abs() <= 1e-9 * (1.0 + u.abs().max(v.abs()))),
        _ => false,
    };
    let negatives = |i: usize| {
        set.equilibria[i]
            .values
            .iter()
            .zip(periodic)
            .filter(|(v, p)| !**p && **v < -1e-12)
            .count()
    };
    let n = set.equilibria.len();
    let mut group_of: Vec<Option<usize>> = vec![None; n];
    let mut kept = Vec::new();
    for i in 0..n {
        if group_of[i].is_some() {
            continue;
        }
        let members: Vec<usize> = (i..n)
            .filter(|j| group_of[*j].is_none() && same(i, *j))
            .collect();
        let best = members
            .iter()
            .copied()
            .min_by_key(|j| (negatives(*j), *j))
            .unwrap_or(i);
        for j in &members {
            group_of[*j] = Some(best);
        }
        kept.push(best);
    }
    kept.sort_unstable();
    let repeated: Vec<Repeated> = (0..n)
        .filter(|i| !kept.contains(i))
        .filter_map(|i| {
            let best = group_of[i]?;
            Some(Repeated {
                same_as: kept.iter().position(|k| *k == best)?,
                values: set.equilibria[i].values.clone(),
            })
        })
        .collect();
    let mut index = 0;
    set.equilibria.retain(|_| {
        index += 1;
        kept.contains(&(index - 1))
    });
    set.repeated.extend(repeated);
    kept
}
