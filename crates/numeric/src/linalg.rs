//! Small dense linear solves in place, for the systems met at every step: `M q̈ = f` and the
//! KKT system of constrained motion. No allocation: the caller owns the buffers.

/// Why a linear system could not be solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum LinearError {
    /// A pivot vanished (relative to the matrix's scale): the matrix is singular there.
    #[error("singular matrix (no usable pivot in column {column})")]
    Singular {
        /// The column, from 0.
        column: usize,
    },
}

/// Solves `A x = b` for square `A` (row-major, `n×n`, overwritten by its LU factors) by
/// Gaussian elimination with partial pivoting; `b` is overwritten by `x`.
///
/// # Errors
/// [`LinearError::Singular`] when a pivot is below `n·ε` times the largest entry, or not finite.
pub fn solve_in_place(n: usize, a: &mut [f64], b: &mut [f64]) -> Result<(), LinearError> {
    debug_assert!(a.len() >= n * n && b.len() >= n);
    let scale = a[..n * n].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let tiny = scale * f64::EPSILON * (n as f64);
    for col in 0..n {
        let mut pivot = col;
        let mut best = a[col * n + col].abs();
        for row in col + 1..n {
            let v = a[row * n + col].abs();
            if v > best {
                best = v;
                pivot = row;
            }
        }
        if best.is_nan() || best <= tiny || best.is_infinite() {
            return Err(LinearError::Singular { column: col });
        }
        if pivot != col {
            for k in 0..n {
                a.swap(col * n + k, pivot * n + k);
            }
            b.swap(col, pivot);
        }
        let p = a[col * n + col];
        for row in col + 1..n {
            let factor = a[row * n + col] / p;
            if factor != 0.0 {
                for k in col + 1..n {
                    a[row * n + k] -= factor * a[col * n + k];
                }
                b[row] -= factor * b[col];
            }
            a[row * n + col] = 0.0;
        }
    }
    for row in (0..n).rev() {
        let mut acc = b[row];
        for k in row + 1..n {
            acc -= a[row * n + k] * b[k];
        }
        b[row] = acc / a[row * n + row];
    }
    Ok(())
}

/// Solves `A x = b` for symmetric positive definite `A` (row-major `n×n`, its lower triangle
/// overwritten by the unit lower factor `L` of `A = L D Lᵀ`, with `1/D_ii` on the diagonal) —
/// a mass matrix: half the work of LU and no pivot search. `b` is overwritten by `x`.
///
/// The square-root-free form of Cholesky: one division per row and no square root, which
/// for the small matrices of mechanics is most of the time on the critical path.
///
/// # Errors
/// [`LinearError::Singular`] when a pivot `D_ii` is not positive (relative to the diagonal's
/// scale): the matrix is singular or not positive definite there; the caller may fall back to
/// [`solve_in_place`] on a fresh copy.
pub fn cholesky_solve_in_place(n: usize, a: &mut [f64], b: &mut [f64]) -> Result<(), LinearError> {
    debug_assert!(a.len() >= n * n && b.len() >= n);
    let scale = (0..n).fold(0.0f64, |m, i| m.max(a[i * n + i].abs()));
    let tiny = scale * f64::EPSILON * (n as f64);
    let dot = |x: &[f64], y: &[f64]| -> f64 { x.iter().zip(y).map(|(p, q)| p * q).sum() };
    let a = &mut a[..n * n];
    let b = &mut b[..n];
    // Row by row: row i first holds W_ik = L_ik D_k (k < i), from the rows above (already L),
    // then D_i = A_ii − Σ W_ik L_ik, and W becomes L. Rows are walked as slices so that the
    // inner products run without bounds checks.
    for i in 0..n {
        let (above, rest) = a.split_at_mut(i * n);
        let row_i = &mut rest[..n];
        for (j, row_j) in above.chunks_exact(n).enumerate() {
            row_i[j] -= dot(&row_i[..j], &row_j[..j]);
        }
        let mut d = row_i[i];
        for (k, row_k) in above.chunks_exact(n).enumerate() {
            let w = row_i[k];
            let l = w * row_k[k];
            d -= w * l;
            row_i[k] = l;
        }
        if d.is_nan() || d <= tiny || d.is_infinite() {
            return Err(LinearError::Singular { column: i });
        }
        row_i[i] = 1.0 / d;
    }
    for (i, row) in a.chunks_exact(n).enumerate() {
        b[i] -= dot(&row[..i], &b[..i]);
    }
    for i in (0..n).rev() {
        let s = b[i] * a[i * n + i] - (i + 1..n).map(|k| a[k * n + i] * b[k]).sum::<f64>();
        b[i] = s;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_and_leaves_a_small_residual() {
        let a0 = [4.0, 1.0, 2.0, 1.0, 3.0, 0.5, 2.0, 0.5, 5.0];
        let b0 = [1.0, -2.0, 3.0];
        let (mut a, mut x) = (a0, b0);
        solve_in_place(3, &mut a, &mut x).unwrap();
        for i in 0..3 {
            let r: f64 = (0..3).map(|k| a0[i * 3 + k] * x[k]).sum::<f64>() - b0[i];
            assert!(r.abs() < 1e-14);
        }
    }

    #[test]
    fn cholesky_agrees_with_lu_and_refuses_indefinite_matrices() {
        let a0 = [4.0, 1.0, 2.0, 1.0, 3.0, 0.5, 2.0, 0.5, 5.0];
        let b0 = [1.0, -2.0, 3.0];
        let (mut a, mut x) = (a0, b0);
        cholesky_solve_in_place(3, &mut a, &mut x).unwrap();
        let (mut a, mut y) = (a0, b0);
        solve_in_place(3, &mut a, &mut y).unwrap();
        for i in 0..3 {
            assert!((x[i] - y[i]).abs() < 1e-14);
        }
        let mut a = [1.0, 2.0, 2.0, 1.0];
        let mut b = [1.0, 1.0];
        assert!(cholesky_solve_in_place(2, &mut a, &mut b).is_err());
    }

    #[test]
    fn needs_pivoting_and_detects_singularity() {
        let mut a = [0.0, 1.0, 1.0, 0.0];
        let mut b = [2.0, 3.0];
        solve_in_place(2, &mut a, &mut b).unwrap();
        assert_eq!(b, [3.0, 2.0]);
        let mut a = [1.0, 2.0, 2.0, 4.0];
        let mut b = [1.0, 1.0];
        assert_eq!(
            solve_in_place(2, &mut a, &mut b),
            Err(LinearError::Singular { column: 1 })
        );
    }
}
