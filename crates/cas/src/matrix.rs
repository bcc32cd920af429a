//! Small symbolic matrices: Jacobians and exact linear solves.
//!
//! [`Matrix::solve`] runs Gaussian elimination on normal forms, choosing as pivot the first
//! entry whose normal form is not zero (so a pivot is never a hidden zero) and preferring the
//! smallest one, which keeps the fractions short. A system with no non-zero pivot in a column
//! is reported as [`SolveError::Singular`] with the column.

use crate::expr::{Expr, Symbol};
use crate::normal::{from_rf, to_rf, Rf};

/// A dense matrix of expressions, stored by rows.
///
/// Invariant: `entries.len() == rows * cols`.
#[derive(Clone, PartialEq, Eq)]
pub struct Matrix {
    rows: usize,
    cols: usize,
    entries: Vec<Expr>,
}

/// Why a linear system could not be solved.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum SolveError {
    /// No non-zero pivot in a column: the matrix is singular.
    #[error("the matrix is singular: column {column} has no non-zero pivot")]
    Singular {
        /// The column (0-based) that has no pivot.
        column: usize,
    },
    /// An intermediate entry of the elimination grew past the term budget: the solution in
    /// closed form would be too large to be of use.
    #[error("the solution in closed form is too large: an intermediate entry has {terms} terms (budget {budget})")]
    TooLarge {
        /// Terms of the entry that went over.
        terms: usize,
        /// The budget.
        budget: usize,
    },
    /// The shapes do not fit.
    #[error("shape mismatch: a {rows}×{cols} matrix with a right-hand side of {rhs_rows} rows")]
    Shape {
        /// Rows of the matrix.
        rows: usize,
        /// Columns of the matrix.
        cols: usize,
        /// Rows of the right-hand side.
        rhs_rows: usize,
    },
}

impl Matrix {
    /// A matrix from its rows; `None` when the rows have different lengths.
    pub fn from_rows(rows: Vec<Vec<Expr>>) -> Option<Matrix> {
        let r = rows.len();
        let c = rows.first().map_or(0, Vec::len);
        if rows.iter().any(|row| row.len() != c) {
            return None;
        }
        Some(Matrix {
            rows: r,
            cols: c,
            entries: rows.into_iter().flatten().collect(),
        })
    }

    /// The `rows × cols` matrix of zeros.
    pub fn zeros(rows: usize, cols: usize) -> Matrix {
        Matrix {
            rows,
            cols,
            entries: vec![Expr::zero(); rows * cols],
        }
    }

    /// A column vector.
    pub fn column(entries: Vec<Expr>) -> Matrix {
        Matrix {
            rows: entries.len(),
            cols: 1,
            entries,
        }
    }

    /// The Jacobian `∂f_i/∂x_j`.
    pub fn jacobian(f: &[Expr], x: &[Symbol]) -> Matrix {
        let entries = f
            .iter()
            .flat_map(|fi| x.iter().map(move |xj| fi.diff(*xj)))
            .collect();
        Matrix {
            rows: f.len(),
            cols: x.len(),
            entries,
        }
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// The entry at `(i, j)`; `None` out of range.
    pub fn get(&self, i: usize, j: usize) -> Option<Expr> {
        (i < self.rows && j < self.cols).then(|| self.entries[i * self.cols + j])
    }

    /// Sets the entry at `(i, j)`; returns `false` (and changes nothing) out of range.
    pub fn set(&mut self, i: usize, j: usize, value: Expr) -> bool {
        if i < self.rows && j < self.cols {
            self.entries[i * self.cols + j] = value;
            true
        } else {
            false
        }
    }

    /// The rows as vectors.
    pub fn to_rows(&self) -> Vec<Vec<Expr>> {
        self.entries
            .chunks(self.cols.max(1))
            .map(<[Expr]>::to_vec)
            .collect()
    }

    /// Every entry in normal form.
    pub fn normal(&self) -> Matrix {
        Matrix {
            rows: self.rows,
            cols: self.cols,
            entries: self.entries.iter().map(|e| e.normal()).collect(),
        }
    }

    /// Solves `self · X = rhs` exactly. `self` must be square.
    pub fn solve(&self, rhs: &Matrix) -> Result<Matrix, SolveError> {
        self.solve_within(rhs, usize::MAX)
    }

    /// [`Matrix::solve`], giving up with [`SolveError::TooLarge`] as soon as an intermediate
    /// entry (numerator and denominator) has more than `budget` terms, or an elimination
    /// product would have more before cancellation (checked before it is formed: its gcds are
    /// where the time goes, seconds for the four-bar's 5×5): elimination over rational
    /// functions can grow without bound, and past a size the closed form is of no use.
    ///
    /// # Errors
    /// As [`Matrix::solve`], or [`SolveError::TooLarge`].
    pub fn solve_within(&self, rhs: &Matrix, budget: usize) -> Result<Matrix, SolveError> {
        let n = self.rows;
        if self.cols != n || rhs.rows != n {
            return Err(SolveError::Shape {
                rows: self.rows,
                cols: self.cols,
                rhs_rows: rhs.rows,
            });
        }
        let m = rhs.cols;
        let mut a: Vec<Vec<Rf>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| to_rf(self.entries[i * n + j]))
                    .chain((0..m).map(|j| to_rf(rhs.entries[i * m + j])))
                    .collect()
            })
            .collect();
        for col in 0..n {
            let pivot = (col..n)
                .filter(|&r| !a[r][col].is_zero())
                .min_by_key(|&r| a[r][col].num.terms.len() + a[r][col].den.terms.len())
                .ok_or(SolveError::Singular { column: col })?;
            a.swap(col, pivot);
            let inv = a[col][col]
                .recip()
                .ok_or(SolveError::Singular { column: col })?;
            for x in a[col][col..].iter_mut() {
                *x = x.mul(&inv);
            }
            let pivot_row = a[col].clone();
            for (r, row) in a.iter_mut().enumerate() {
                if r == col || row[col].is_zero() {
                    continue;
                }
                let factor = row[col].clone();
                for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                    // The product's terms before cancellation bound what its gcds work on,
                    // which is where the time goes: refuse before paying for them.
                    let product = |a: &Rf, b: &Rf| {
                        let (na, da) = (a.num.terms.len(), a.den.terms.len());
                        let (nb, db) = (b.num.terms.len(), b.den.terms.len());
                        na.saturating_mul(nb).saturating_add(da.saturating_mul(db))
                    };
                    let estimate = product(p, &factor);
                    if estimate > budget {
                        return Err(SolveError::TooLarge {
                            terms: estimate,
                            budget,
                        });
                    }
                    *x = x.sub(&p.mul(&factor));
                    let terms = x.num.terms.len() + x.den.terms.len();
                    if terms > budget {
                        return Err(SolveError::TooLarge { terms, budget });
                    }
                }
            }
        }
        let entries = (0..n)
            .flat_map(|i| (0..m).map(move |j| (i, j)))
            .map(|(i, j)| from_rf(&a[i][n + j]))
            .collect();
        Ok(Matrix {
            rows: n,
            cols: m,
            entries,
        })
    }

    /// The determinant (exact, by elimination); zero for a singular matrix.
    pub fn determinant(&self) -> Option<Expr> {
        let n = self.rows;
        if self.cols != n {
            return None;
        }
        let mut a: Vec<Vec<Rf>> = (0..n)
            .map(|i| (0..n).map(|j| to_rf(self.entries[i * n + j])).collect())
            .collect();
        let mut det = Rf::one();
        for col in 0..n {
            let Some(pivot) = (col..n).find(|&r| !a[r][col].is_zero()) else {
                return Some(Expr::zero());
            };
            if pivot != col {
                a.swap(col, pivot);
                det = det.neg();
            }
            det = det.mul(&a[col][col]);
            let inv = a[col][col].recip()?;
            let pivot_row = a[col].clone();
            for row in a.iter_mut().skip(col + 1) {
                if row[col].is_zero() {
                    continue;
                }
                let factor = row[col].mul(&inv);
                for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                    *x = x.sub(&p.mul(&factor));
                }
            }
        }
        Some(from_rf(&det))
    }
}

impl std::fmt::Debug for Matrix {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.to_rows()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_symbolic_3x3_system() {
        let a = Expr::symbol("a");
        let b = Expr::symbol("b");
        let c = Expr::symbol("c");
        let m = Matrix::from_rows(vec![
            vec![a, Expr::one(), Expr::zero()],
            vec![Expr::one(), b, Expr::one()],
            vec![Expr::zero(), Expr::one(), c],
        ])
        .unwrap();
        let rhs = Matrix::column(vec![Expr::one(), Expr::zero(), Expr::zero()]);
        let x = m.solve(&rhs).unwrap();
        // Check A x = rhs exactly.
        for i in 0..3 {
            let row: Expr = (0..3)
                .map(|j| m.get(i, j).unwrap() * x.get(j, 0).unwrap())
                .sum();
            assert!(row.equals(rhs.get(i, 0).unwrap()), "row {i}");
        }
        let det = m.determinant().unwrap();
        assert!(det.equals(a * b * c - a - c));
    }

    #[test]
    fn singular_matrix_is_reported() {
        let x = Expr::symbol("x");
        let m = Matrix::from_rows(vec![vec![x, 2 * x], vec![Expr::one(), Expr::int(2)]]).unwrap();
        let rhs = Matrix::column(vec![Expr::one(), Expr::one()]);
        assert_eq!(m.solve(&rhs), Err(SolveError::Singular { column: 1 }));
    }
}
