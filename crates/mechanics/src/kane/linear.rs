//! Small dense linear algebra over any [`Scalar`]: the solves inside the reduction must carry
//! derivatives, so they cannot use the `f64` routines of `numeric`.

use super::scalar::Scalar;

/// Solves `a x = r` for each right-hand side `r` in `rhs` (Gaussian elimination, pivots chosen
/// by the values' size); `None` when `a` is singular at its values or not square.
pub fn solve<T: Scalar>(mut a: Vec<Vec<T>>, mut rhs: Vec<Vec<T>>) -> Option<Vec<Vec<T>>> {
    let n = a.len();
    if a.iter().any(|row| row.len() != n) || rhs.iter().any(|r| r.len() != n) {
        return None;
    }
    let scale = a
        .iter()
        .flatten()
        .fold(0.0_f64, |m, x| m.max(x.value().abs()));
    for col in 0..n {
        let pivot = (col..n).max_by(|i, j| {
            a[*i][col]
                .value()
                .abs()
                .total_cmp(&a[*j][col].value().abs())
        })?;
        if a[pivot][col].value().abs() <= 1e-13 * scale || scale == 0.0 {
            return None;
        }
        a.swap(col, pivot);
        for r in &mut rhs {
            r.swap(col, pivot);
        }
        let (upper, lower) = a.split_at_mut(col + 1);
        let pivot_row = &upper[col];
        for (offset, target) in lower.iter_mut().enumerate() {
            let row = col + 1 + offset;
            let f = target[col] / pivot_row[col];
            for (x, p) in target.iter_mut().zip(pivot_row).skip(col) {
                *x = *x - f * *p;
            }
            for r in &mut rhs {
                let d = f * r[col];
                r[row] = r[row] - d;
            }
        }
    }
    for r in &mut rhs {
        for row in (0..n).rev() {
            let s = (row + 1..n).fold(r[row], |acc, k| acc - a[row][k] * r[k]);
            r[row] = s / a[row][row];
        }
    }
    Some(rhs)
}

/// `tᵀ m` for `t` n×p and `m` n×n.
pub fn transpose_times<T: Scalar>(t: &[Vec<T>], m: &[Vec<T>]) -> Vec<Vec<T>> {
    let n = t.len();
    let p = t.first().map_or(0, Vec::len);
    (0..p)
        .map(|i| {
            (0..n)
                .map(|j| (0..n).fold(T::constant(0.0), |acc, k| acc + t[k][i] * m[k][j]))
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_with_row_exchange() {
        let a = vec![vec![0.0, 2.0], vec![3.0, 1.0]];
        let x = solve(a, vec![vec![4.0, 5.0]]).unwrap_or_default();
        assert_eq!(x, vec![vec![1.0, 2.0]]);
        assert!(solve(vec![vec![1.0, 2.0], vec![2.0, 4.0]], vec![vec![1.0, 1.0]]).is_none());
    }
}
