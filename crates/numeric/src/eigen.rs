//! Eigenproblems of linearized mechanics, on `nalgebra`: the symmetric generalized problem
//! `K x = ω² M x` (Cholesky of `M`), the eigenvalues of a general real state matrix (damped or
//! gyroscopic systems), the state matrix itself and the controllability rank.

use nalgebra::DMatrix;

/// What can go wrong.
#[derive(Debug, thiserror::Error, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum EigenError {
    /// The mass matrix is not symmetric positive definite.
    #[error("the mass matrix is not positive definite")]
    MassNotPositiveDefinite,
    /// The matrices' shapes do not agree.
    #[error("matrix shapes do not agree")]
    Shape,
    /// An entry is infinite or not a number (the values overflow, or are undefined there).
    #[error("a matrix entry is not finite (row {row}, column {column}): the values overflow or are undefined")]
    NonFinite {
        /// Its row, from 0.
        row: usize,
        /// Its column, from 0.
        column: usize,
    },
    /// The iteration did not converge within its cap.
    #[error("the eigenvalue iteration did not converge in {iterations} iterations")]
    NoConvergence {
        /// The cap.
        iterations: usize,
    },
}

/// A dense row-major square matrix as `Vec<Vec<f64>>` → `DMatrix`, every entry finite.
fn to_matrix(rows: &[Vec<f64>]) -> Result<DMatrix<f64>, EigenError> {
    let n = rows.len();
    if rows.iter().any(|r| r.len() != n) {
        return Err(EigenError::Shape);
    }
    let m = DMatrix::from_fn(n, n, |i, j| rows[i][j]);
    finite(&m)?;
    Ok(m)
}

/// Every entry of `m` is finite: an iteration on an infinite or NaN entry never converges.
fn finite(m: &DMatrix<f64>) -> Result<(), EigenError> {
    match m.iter().position(|x| !x.is_finite()) {
        // Column-major storage: index = column · rows + row.
        Some(k) => Err(EigenError::NonFinite {
            row: k % m.nrows().max(1),
            column: k / m.nrows().max(1),
        }),
        None => Ok(()),
    }
}

/// A cap on the QR (or SVD) sweeps of an `n×n` problem: a few per eigenvalue is the rule, so
/// this is only reached when the iteration cannot converge.
fn iteration_cap(n: usize) -> usize {
    200 * (n + 1)
}

/// `m` divided by its largest entry's magnitude, and that scale (1 for a zero matrix):
/// eigenvalues scale with the matrix, and entries near the top of the floating-point range
/// would overflow inside the iteration.
fn scaled(m: DMatrix<f64>) -> (DMatrix<f64>, f64) {
    let scale = m.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if scale > 0.0 {
        (m / scale, scale)
    } else {
        (m, 1.0)
    }
}

/// Solutions of `K x = λ M x` for symmetric `K` and symmetric positive definite `M`:
/// eigenvalues `λ = ω²` in increasing order, and modes (columns) normalized to `xᵀ M x = 1`.
#[derive(Clone, Debug)]
pub struct GeneralizedEigen {
    /// `λ_i`, increasing.
    pub values: Vec<f64>,
    /// `modes[i]` is the mode of `values[i]`.
    pub modes: Vec<Vec<f64>>,
}

/// Solves `K x = λ M x` (symmetric parts of `K` and `M` are used).
pub fn symmetric_generalized(
    stiffness: &[Vec<f64>],
    mass: &[Vec<f64>],
) -> Result<GeneralizedEigen, EigenError> {
    let k = to_matrix(stiffness)?;
    let m = to_matrix(mass)?;
    if k.nrows() != m.nrows() {
        return Err(EigenError::Shape);
    }
    // Halved before adding, so that entries near the top of the range do not overflow.
    let k = &k * 0.5 + k.transpose() * 0.5;
    let m = &m * 0.5 + m.transpose() * 0.5;
    let chol = m.cholesky().ok_or(EigenError::MassNotPositiveDefinite)?;
    let l = chol.l();
    let l_inv = l
        .clone()
        .try_inverse()
        .ok_or(EigenError::MassNotPositiveDefinite)?;
    let s = &l_inv * k * l_inv.transpose();
    let s = &s * 0.5 + s.transpose() * 0.5;
    finite(&s)?;
    let n = s.nrows();
    let (s, scale) = scaled(s);
    let mut eig = nalgebra::SymmetricEigen::try_new(s, f64::EPSILON, iteration_cap(n)).ok_or(
        EigenError::NoConvergence {
            iterations: iteration_cap(n),
        },
    )?;
    eig.eigenvalues *= scale;
    if let Some(k) = eig.eigenvalues.iter().position(|x| !x.is_finite()) {
        return Err(EigenError::NonFinite { row: k, column: k });
    }
    let mut order: Vec<usize> = (0..eig.eigenvalues.len()).collect();
    order.sort_by(|a, b| eig.eigenvalues[*a].total_cmp(&eig.eigenvalues[*b]));
    let back = l_inv.transpose();
    let mut values = Vec::new();
    let mut modes = Vec::new();
    for i in order {
        values.push(eig.eigenvalues[i]);
        let x = &back * eig.eigenvectors.column(i);
        // A sign convention so modes are reproducible: the largest entry is positive.
        let big = x
            .iter()
            .copied()
            .fold(0.0_f64, |a, v| if v.abs() > a.abs() { v } else { a });
        let sign = if big < 0.0 { -1.0 } else { 1.0 };
        modes.push(x.iter().map(|v| v * sign).collect());
    }
    Ok(GeneralizedEigen { values, modes })
}

/// The first-order state matrix `A = [[0, I], [−M⁻¹K, −M⁻¹C]]` of `M q̈ + C q̇ + K q = 0`.
pub fn state_matrix(
    mass: &[Vec<f64>],
    damping: &[Vec<f64>],
    stiffness: &[Vec<f64>],
) -> Result<Vec<Vec<f64>>, EigenError> {
    let m = to_matrix(mass)?;
    let c = to_matrix(damping)?;
    let k = to_matrix(stiffness)?;
    let n = m.nrows();
    if c.nrows() != n || k.nrows() != n {
        return Err(EigenError::Shape);
    }
    let lu = m.lu();
    let mk = lu.solve(&k).ok_or(EigenError::MassNotPositiveDefinite)?;
    let mc = lu.solve(&c).ok_or(EigenError::MassNotPositiveDefinite)?;
    finite(&mk)?;
    finite(&mc)?;
    let mut a = vec![vec![0.0; 2 * n]; 2 * n];
    for i in 0..n {
        a[i][n + i] = 1.0;
        for j in 0..n {
            a[n + i][j] = -mk[(i, j)];
            a[n + i][n + j] = -mc[(i, j)];
        }
    }
    Ok(a)
}

/// The input matrix of the state form: `B = [[0], [M⁻¹ B0]]` (`B0` is n×p).
pub fn state_input(mass: &[Vec<f64>], input: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, EigenError> {
    let m = to_matrix(mass)?;
    let n = m.nrows();
    if input.len() != n {
        return Err(EigenError::Shape);
    }
    let p = input.first().map_or(0, Vec::len);
    if input.iter().any(|r| r.len() != p) {
        return Err(EigenError::Shape);
    }
    let b0 = DMatrix::from_fn(n, p, |i, j| input[i][j]);
    let mb = m
        .lu()
        .solve(&b0)
        .ok_or(EigenError::MassNotPositiveDefinite)?;
    finite(&mb)?;
    let mut b = vec![vec![0.0; p]; 2 * n];
    for i in 0..n {
        for j in 0..p {
            b[n + i][j] = mb[(i, j)];
        }
    }
    Ok(b)
}

/// Solves `M X = R` for a square `M` and a right-hand side with as many rows.
pub fn solve(m: &[Vec<f64>], rhs: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, EigenError> {
    let mm = to_matrix(m)?;
    let n = mm.nrows();
    if rhs.len() != n {
        return Err(EigenError::Shape);
    }
    let p = rhs.first().map_or(0, Vec::len);
    if rhs.iter().any(|r| r.len() != p) {
        return Err(EigenError::Shape);
    }
    let r = DMatrix::from_fn(n, p, |i, j| rhs[i][j]);
    finite(&r)?;
    let x = mm
        .lu()
        .solve(&r)
        .ok_or(EigenError::MassNotPositiveDefinite)?;
    finite(&x)?;
    Ok((0..n)
        .map(|i| (0..p).map(|j| x[(i, j)]).collect())
        .collect())
}

/// Eigenvalues `(re, im)` of a real square matrix, sorted by real part then imaginary part.
pub fn eigenvalues(a: &[Vec<f64>]) -> Result<Vec<(f64, f64)>, EigenError> {
    let (m, scale) = scaled(to_matrix(a)?);
    let n = m.nrows();
    let schur = nalgebra::Schur::try_new(m, f64::EPSILON, iteration_cap(n)).ok_or(
        EigenError::NoConvergence {
            iterations: iteration_cap(n),
        },
    )?;
    let mut out: Vec<(f64, f64)> = schur
        .complex_eigenvalues()
        .iter()
        .map(|z| (z.re * scale, z.im * scale))
        .collect();
    if let Some(k) = out
        .iter()
        .position(|(re, im)| !re.is_finite() || !im.is_finite())
    {
        return Err(EigenError::NonFinite { row: k, column: k });
    }
    out.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1)));
    Ok(out)
}

/// The rank of the controllability matrix `[B, AB, …, A^{N−1}B]` (N = size of `A`), by
/// singular values above a relative tolerance.
pub fn controllability_rank(a: &[Vec<f64>], b: &[Vec<f64>]) -> Result<usize, EigenError> {
    let am = to_matrix(a)?;
    let n = am.nrows();
    if b.len() != n {
        return Err(EigenError::Shape);
    }
    let p = b.first().map_or(0, Vec::len);
    if p == 0 {
        return Ok(0);
    }
    if b.iter().any(|r| r.len() != p) {
        return Err(EigenError::Shape);
    }
    let mut block = DMatrix::from_fn(n, p, |i, j| b[i][j]);
    finite(&block)?;
    let mut blocks = DMatrix::zeros(n, n * p);
    for k in 0..n {
        blocks.view_mut((0, k * p), (n, p)).copy_from(&block);
        block = &am * block;
    }
    // Powers of A may overflow: an infinite entry would never let the SVD converge.
    finite(&blocks)?;
    let cap = iteration_cap(n * p);
    let sv = blocks
        .try_svd(false, false, f64::EPSILON, cap)
        .ok_or(EigenError::NoConvergence { iterations: cap })?
        .singular_values;
    let largest = sv.iter().copied().fold(0.0_f64, f64::max);
    let tol = largest * 1e-9 * n as f64;
    Ok(sv.iter().filter(|s| **s > tol).count())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 14: the eigenvalue step never ended when matrix entries overflowed (`g = 1e308`
    /// on an inverted pendulum). A non-finite matrix is an error; huge finite entries work.
    #[test]
    fn non_finite_matrices_are_errors_not_endless_iterations() {
        let inf = vec![vec![0.0, 1.0], vec![f64::INFINITY, 0.0]];
        assert_eq!(
            eigenvalues(&inf),
            Err(EigenError::NonFinite { row: 1, column: 0 })
        );
        let nan = vec![vec![f64::NAN, 1.0], vec![1.0, 0.0]];
        assert!(matches!(
            eigenvalues(&nan),
            Err(EigenError::NonFinite { .. })
        ));
        let m = vec![vec![1.0, 0.0], vec![0.0, 1.0]];
        assert!(matches!(
            symmetric_generalized(&inf, &m),
            Err(EigenError::NonFinite { .. })
        ));
        assert!(matches!(
            state_matrix(&m, &m, &inf),
            Err(EigenError::NonFinite { .. })
        ));
        assert!(matches!(
            controllability_rank(&inf, &[vec![0.0], vec![1.0]]),
            Err(EigenError::NonFinite { .. })
        ));
        // M⁻¹K overflows although every input is finite.
        let tiny = vec![vec![1e-300, 0.0], vec![0.0, 1e-300]];
        let huge = vec![vec![-1e308, 0.0], vec![0.0, 1.0]];
        assert!(matches!(
            state_matrix(&tiny, &m, &huge),
            Err(EigenError::NonFinite { .. })
        ));
    }

    #[test]
    fn huge_finite_entries_give_their_eigenvalues() {
        // An inverted pendulum's state matrix with g = 1e308: λ = ±√(g/l).
        let a = vec![vec![0.0, 1.0], vec![1e308, 0.0]];
        let e = eigenvalues(&a).unwrap();
        assert!((e[0].0 + 1e154).abs() < 1e140 && (e[1].0 - 1e154).abs() < 1e140);
        let e = symmetric_generalized(&[vec![1e308]], &[vec![1.0]]).unwrap();
        assert!((e.values[0] - 1e308).abs() < 1e294);
    }

    #[test]
    fn two_masses_three_springs() {
        // m = 1, k = 1: ω² = 1 and 3, modes (1, 1)/√2 and (1, −1)/√2.
        let k = vec![vec![2.0, -1.0], vec![-1.0, 2.0]];
        let m = vec![vec![1.0, 0.0], vec![0.0, 1.0]];
        let e = symmetric_generalized(&k, &m).unwrap();
        assert!((e.values[0] - 1.0).abs() < 1e-12 && (e.values[1] - 3.0).abs() < 1e-12);
        let r = 0.5_f64.sqrt();
        assert!((e.modes[0][0] - r).abs() < 1e-12 && (e.modes[0][1] - r).abs() < 1e-12);
        assert!((e.modes[1][0].abs() - r).abs() < 1e-12);
        assert!((e.modes[1][0] + e.modes[1][1]).abs() < 1e-12);
    }

    #[test]
    fn damped_oscillator_eigenvalues() {
        // q̈ + 2ζω q̇ + ω² q = 0 with ω = 2, ζ = 0.1: λ = −ζω ± iω√(1−ζ²).
        let a = state_matrix(&[vec![1.0]], &[vec![0.4]], &[vec![4.0]]).unwrap();
        let l = eigenvalues(&a).unwrap();
        let im = 2.0 * (1.0 - 0.01_f64).sqrt();
        assert!((l[0].0 + 0.2).abs() < 1e-12 && (l[0].1 + im).abs() < 1e-12);
        assert!((l[1].0 + 0.2).abs() < 1e-12 && (l[1].1 - im).abs() < 1e-12);
    }

    #[test]
    fn double_integrator_is_controllable_and_a_decoupled_mass_is_not() {
        let a = state_matrix(&[vec![1.0]], &[vec![0.0]], &[vec![0.0]]).unwrap();
        let b = state_input(&[vec![1.0]], &[vec![1.0]]).unwrap();
        assert_eq!(controllability_rank(&a, &b).unwrap(), 2);
        let m = vec![vec![1.0, 0.0], vec![0.0, 1.0]];
        let z = vec![vec![0.0; 2]; 2];
        let a = state_matrix(&m, &z, &z).unwrap();
        let b = state_input(&m, &[vec![1.0], vec![0.0]]).unwrap();
        assert_eq!(controllability_rank(&a, &b).unwrap(), 2);
    }
}
