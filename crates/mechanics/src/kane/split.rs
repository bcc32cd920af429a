//! Choosing the independent speeds: Gaussian elimination with full pivoting on the constraint
//! rows, holonomic rows first, preferring some coordinates as the dependent ones.

use super::dynamics::{KaneSystem, SpeedSplit};
use super::KaneError;

/// Relative size below which a pivot counts as zero (the rows are then dependent).
const RANK_TOLERANCE: f64 = 1e-9;

impl KaneSystem {
    /// The split of the rates at `q` into speeds and dependent rates. Holonomic rows pivot only
    /// on coordinates with `holonomic_columns` set; velocity rows pivot first on coordinates
    /// with `prefer_dependent` set (the largest entry among them), then on any other.
    ///
    /// # Errors
    /// [`KaneError::Singular`] when a holonomic row has no usable pivot or no speed is left.
    pub fn split(
        &self,
        q: &[f64],
        t: f64,
        values: &[f64],
        prefer_dependent: &[bool],
        holonomic_columns: &[bool],
    ) -> Result<SpeedSplit, KaneError> {
        let n = q.len();
        let (mut a, _) = self.constraint_rows(q, t, values);
        let scale = a.iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
        let tol = RANK_TOLERANCE * scale.max(1e-300);
        let mut used_rows = vec![false; a.len()];
        let mut used_cols = vec![false; n];
        let mut rows = Vec::new();
        let mut dependent = Vec::new();
        let classes: [&dyn Fn(usize, usize) -> bool; 3] = [
            &|r, c| r < self.holonomic && holonomic_columns[c],
            &|r, c| r >= self.holonomic && prefer_dependent[c],
            &|r, _| r >= self.holonomic,
        ];
        for allowed in classes {
            while let Some((r, c)) = best_pivot(&a, &used_rows, &used_cols, allowed, tol) {
                used_rows[r] = true;
                used_cols[c] = true;
                rows.push(r);
                dependent.push(c);
                eliminate(&mut a, r, c, &used_rows);
            }
        }
        let holonomic_rank = rows.iter().filter(|r| **r < self.holonomic).count();
        if holonomic_rank < self.holonomic_rank(q, t, values, tol) {
            return Err(KaneError::Singular("the holonomic constraints' Jacobian"));
        }
        let independent: Vec<usize> = (0..n).filter(|c| !used_cols[*c]).collect();
        if independent.is_empty() {
            return Err(KaneError::Singular(
                "the constraint matrix (no speed is free)",
            ));
        }
        Ok(SpeedSplit {
            independent,
            dependent,
            rows,
        })
    }

    /// The rank of the holonomic rows alone.
    fn holonomic_rank(&self, q: &[f64], t: f64, values: &[f64], tol: f64) -> usize {
        let mut a = self.holonomic_jacobian(q, t, values);
        let n = q.len();
        let mut used_rows = vec![false; a.len()];
        let mut used_cols = vec![false; n];
        let mut rank = 0;
        while let Some((r, c)) = best_pivot(&a, &used_rows, &used_cols, &|_, _| true, tol) {
            used_rows[r] = true;
            used_cols[c] = true;
            eliminate(&mut a, r, c, &used_rows);
            rank += 1;
        }
        rank
    }
}

/// The largest entry among the unused rows and columns that `allowed` admits, above `tol`.
fn best_pivot(
    a: &[Vec<f64>],
    used_rows: &[bool],
    used_cols: &[bool],
    allowed: &dyn Fn(usize, usize) -> bool,
    tol: f64,
) -> Option<(usize, usize)> {
    let mut best: Option<(usize, usize, f64)> = None;
    for (r, row) in a.iter().enumerate() {
        if used_rows[r] {
            continue;
        }
        for (c, x) in row.iter().enumerate() {
            if used_cols[c] || !allowed(r, c) || x.abs() <= tol {
                continue;
            }
            if best.is_none_or(|(_, _, b)| x.abs() > b) {
                best = Some((r, c, x.abs()));
            }
        }
    }
    best.map(|(r, c, _)| (r, c))
}

/// Clears column `c` from the unused rows with row `r`.
fn eliminate(a: &mut [Vec<f64>], r: usize, c: usize, used_rows: &[bool]) {
    let pivot_row = a[r].clone();
    for (k, row) in a.iter_mut().enumerate() {
        if used_rows[k] {
            continue;
        }
        let f = row[c] / pivot_row[c];
        for (x, p) in row.iter_mut().zip(&pivot_row) {
            *x -= f * p;
        }
    }
}
