//! The motion of the constrained system (accelerations and multipliers as functions of the
//! state) and the residuals of a released system's Lagrange equations on it.

use cas::{Expr, Matrix, SolveError, Symbol};

use super::compare::sample;
use super::ReactionError;
use crate::equations::{derive_released, Equations};
use crate::system::{System, Vector};

/// Terms an entry of the multiplier solve may reach: a course's systems stay far below (tens
/// to hundreds), while the four-bar's 5×5 solve grows past it quickly instead of running for
/// minutes.
const SOLVE_BUDGET: usize = 2_000;

/// The motion of the constrained system: how to replace every coordinate (eliminated ones by
/// their value), and accelerations and multipliers as functions of the state.
pub(super) struct Motion {
    pub(super) substitutions: Vec<Vec<(Expr, Expr)>>,
    pub(super) accelerations: Vec<(Expr, Expr)>,
    pub(super) multipliers: Vec<Expr>,
    pub(super) constraint_names: Vec<String>,
}

impl Motion {
    pub(super) fn of(equations: &Equations) -> Result<Motion, ReactionError> {
        let n = equations.coordinates().len();
        let m = equations.constraint_names().len();
        let (accelerations, multipliers) = match equations.accelerations() {
            Some(a) if m == 0 => (a.to_vec(), Vec::new()),
            _ => {
                // Rows that depend on the others (a rolling contact's normal row, say) would make
                // the DAE singular; their multipliers are set to zero, which leaves `Aᵀλ`, the
                // generalized reaction, unchanged.
                let independent = independent_rows(equations.constraint_matrix());
                let kept: Vec<usize> = (0..m).filter(|k| independent[*k]).collect();
                let size = n + kept.len();
                let mut rows = vec![vec![Expr::zero(); size]; size];
                let mut rhs = Vec::with_capacity(size);
                for (i, row) in equations.mass_matrix().iter().enumerate() {
                    rows[i][..n].copy_from_slice(row);
                    rhs.push(equations.forcing()[i]);
                }
                for (slot, &k) in kept.iter().enumerate() {
                    for (j, a) in equations.constraint_matrix()[k].iter().enumerate() {
                        rows[n + slot][j] = *a;
                        rows[j][n + slot] = *a;
                    }
                    rhs.push(equations.constraint_rhs()[k]);
                }
                let matrix = Matrix::from_rows(rows).ok_or(ReactionError::Unsolvable)?;
                let x = matrix
                    .solve_within(&Matrix::column(rhs), SOLVE_BUDGET)
                    .map_err(|e| match e {
                        SolveError::TooLarge { budget, .. } => ReactionError::TooLarge { budget },
                        _ => ReactionError::Unsolvable,
                    })?;
                let value = |i| {
                    x.get(i, 0)
                        .map(Expr::normal)
                        .ok_or(ReactionError::Unsolvable)
                };
                let a = (0..n).map(value).collect::<Result<Vec<_>, _>>()?;
                let mut l = vec![Expr::zero(); m];
                for (slot, &k) in kept.iter().enumerate() {
                    l[k] = value(n + slot)?;
                }
                (a, l)
            }
        };
        // Eliminations are applied in order: a value may name a coordinate eliminated later.
        let substitutions = equations
            .eliminated()
            .iter()
            .map(|e| {
                let v1 = e.value.dt();
                vec![
                    (Expr::coordinate(&e.coordinate), e.value),
                    (Expr::rate(&e.coordinate, 1), v1),
                    (Expr::rate(&e.coordinate, 2), v1.dt()),
                ]
            })
            .collect();
        let accelerations = equations
            .coordinates()
            .iter()
            .zip(accelerations)
            .map(|(q, a)| (Expr::rate(q, 2), a))
            .collect();
        Ok(Motion {
            substitutions,
            accelerations,
            multipliers,
            constraint_names: equations.constraint_names().to_vec(),
        })
    }

    /// `e` on the motion: eliminated coordinates replaced, then accelerations.
    pub(super) fn on_motion(&self, e: Expr) -> Expr {
        let mut e = e;
        for pairs in &self.substitutions {
            e = e.subs(pairs);
        }
        e.subs(&self.accelerations).normal()
    }
}

/// Which rows of `a` are independent of the rows before them, judged by their values at a
/// pseudo-random state (Gram–Schmidt; a row whose remainder is below 1e-9 of its size is
/// dependent: at a random state that happens only for rows dependent everywhere). When a row
/// cannot be evaluated every row is kept.
pub(super) fn independent_rows(a: &[Vec<Expr>]) -> Vec<bool> {
    let env = |s: Symbol| Some(sample(s, 11));
    let mut keep = vec![true; a.len()];
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for (k, row) in a.iter().enumerate() {
        let values: Result<Vec<f64>, _> = row.iter().map(|e| e.eval(&env)).collect();
        let Ok(mut v) = values else {
            return vec![true; a.len()];
        };
        let size = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        for b in &basis {
            let p: f64 = v.iter().zip(b).map(|(x, y)| x * y).sum();
            for (x, y) in v.iter_mut().zip(b) {
                *x -= p * y;
            }
        }
        let rest = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if rest > 1e-9 * size.max(f64::MIN_POSITIVE) {
            basis.push(v.iter().map(|x| x / rest).collect());
        } else {
            keep[k] = false;
        }
    }
    keep
}

/// `u = u̇ = ü = 0` for every displacement.
pub(super) fn at_rest(displacements: &[(String, Vector)]) -> Vec<(Expr, Expr)> {
    displacements
        .iter()
        .flat_map(|(u, _)| {
            [
                (Expr::coordinate(u), Expr::zero()),
                (Expr::rate(u, 1), Expr::zero()),
                (Expr::rate(u, 2), Expr::zero()),
            ]
        })
        .collect()
}

/// Residuals `E_j − Q_j + Σ_k A_kj λ_k` of the system `without` (a constraint dropped, maybe
/// displacements added) on the motion of the constrained system, for every coordinate of
/// `without` that `wanted` accepts. Other constraints' rows are matched to the constrained
/// system's by name, in order.
///
/// Putting a residual on the motion (the accelerations substituted, the result in normal
/// form) is most of a reaction's cost, and a release asks only for its displacements' and
/// rotations' residuals: the released system's other coordinates are left out (the double
/// pendulum's hinge reactions did twice the work; issue 20).
pub(super) fn residuals(
    name: &str,
    without: &System,
    motion: &Motion,
    zero: &[(Expr, Expr)],
    wanted: &dyn Fn(&str) -> bool,
) -> Result<Vec<Residual>, ReactionError> {
    let released = derive_released(without).map_err(|source| ReactionError::Mechanics {
        reaction: name.to_string(),
        source,
    })?;
    let mut used = vec![false; motion.constraint_names.len()];
    let mut terms: Vec<Expr> = released
        .lagrange_lhs()
        .iter()
        .zip(released.generalized_forces())
        .map(|(e, q)| *e - *q)
        .collect();
    for (row, other) in released
        .constraint_matrix()
        .iter()
        .zip(released.constraint_names())
    {
        let position = motion
            .constraint_names
            .iter()
            .zip(&used)
            .position(|(n, u)| n == other && !u);
        let Some(k) = position else {
            return Err(ReactionError::Entangled {
                reaction: name.to_string(),
                other: other.clone(),
            });
        };
        used[k] = true;
        for (term, a) in terms.iter_mut().zip(row) {
            *term += *a * motion.multipliers[k];
        }
    }
    let equations = released
        .lagrange_lhs()
        .iter()
        .zip(released.generalized_forces());
    Ok(released
        .coordinates()
        .iter()
        .zip(terms)
        .zip(equations)
        .filter(|((q, _), _)| wanted(q))
        .map(|((q, r), (e, f))| Residual {
            coordinate: q.clone(),
            on_motion: motion.on_motion(r.subs(zero)),
            at_rest: (*e - *f).subs(zero),
        })
        .collect())
}

/// One coordinate's residual from [`residuals`].
pub(super) struct Residual {
    /// The released system's coordinate.
    pub(super) coordinate: String,
    /// `E_j − Q_j + Σ_k A_kj λ_k` on the constrained motion.
    pub(super) on_motion: Expr,
    /// `E_j − Q_j` with the substitution `zero` only (not in normal form).
    pub(super) at_rest: Expr,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dependent_constraint_rows_are_found() {
        let (x, y) = (Expr::coordinate("x"), Expr::coordinate("y"));
        let rows = vec![
            vec![x.cos(), x.sin()],
            vec![2 * x.cos(), 2 * x.sin()],
            vec![y, Expr::one()],
        ];
        assert_eq!(independent_rows(&rows), vec![true, false, true]);
    }
}
