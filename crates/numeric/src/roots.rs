//! Root finding for systems `F(x) = 0` over a box: a dense scan with bisection in one
//! dimension, Newton from a grid of starts in several. Neither *guarantees* completeness (the
//! caller says so); the scan finds every root where `F` changes sign between grid points or
//! touches zero at a local minimum of `|F|` on the grid.

/// A residual or Jacobian that may fail to evaluate at a point (outside its domain).
pub type Residual<'a> = dyn Fn(&[f64]) -> Option<Vec<f64>> + 'a;

/// Options of the search.
#[derive(Clone, Debug)]
pub struct Search {
    /// Lower and upper bound per unknown.
    pub bounds: Vec<(f64, f64)>,
    /// Whether unknown `i` is an angle (values identified modulo 2π).
    pub periodic: Vec<bool>,
    /// Grid points in the one-dimensional scan.
    pub scan_points: usize,
    /// Upper bound on the number of Newton starts in several dimensions.
    pub max_starts: usize,
    /// Residual tolerance for accepting a root.
    pub tolerance: f64,
}

impl Search {
    /// Defaults for a box.
    #[must_use]
    pub fn new(bounds: Vec<(f64, f64)>, periodic: Vec<bool>) -> Search {
        Search {
            bounds,
            periodic,
            scan_points: 4000,
            max_starts: 600,
            tolerance: 1e-9,
        }
    }
}

/// Wraps an angle into (−π, π].
#[must_use]
pub fn wrap_angle(x: f64) -> f64 {
    let two_pi = std::f64::consts::TAU;
    let mut y = x.rem_euclid(two_pi);
    if y > std::f64::consts::PI {
        y -= two_pi;
    }
    y
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Solves `J d = −F` by Gaussian elimination with partial pivoting; `None` when singular.
/// `a` is work space for the augmented matrix `[J | −F]` (row-major, `n + 1` columns), kept
/// by the caller between steps: a multistart search takes tens of thousands of steps, and a
/// row allocated per step was a fifth of its time (issue 20).
fn newton_step(j: &[f64], f: &[f64], a: &mut Vec<f64>) -> Option<Vec<f64>> {
    let n = f.len();
    let width = n + 1;
    a.clear();
    for i in 0..n {
        a.extend_from_slice(&j[i * n..(i + 1) * n]);
        a.push(-f[i]);
    }
    for col in 0..n {
        // The last of equal candidates, as `Iterator::max_by` picks it.
        let pivot = (col..n).max_by(|x, y| {
            a[x * width + col]
                .abs()
                .total_cmp(&a[y * width + col].abs())
        })?;
        if a[pivot * width + col].abs() < 1e-300 {
            return None;
        }
        if pivot != col {
            for k in 0..width {
                a.swap(col * width + k, pivot * width + k);
            }
        }
        let (upper, lower) = a.split_at_mut((col + 1) * width);
        let pivot_row = &upper[col * width..];
        for row in lower.chunks_exact_mut(width) {
            let factor = row[col] / pivot_row[col];
            for (r, p) in row.iter_mut().zip(pivot_row).skip(col) {
                *r -= factor * p;
            }
        }
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n).map(|k| a[i * width + k] * x[k]).sum();
        x[i] = (a[i * width + n] - s) / a[i * width + i];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Newton's method (damped by halving when the residual grows); the root, if it converges.
pub fn newton(
    f: &Residual<'_>,
    jacobian: &Residual<'_>,
    start: &[f64],
    tolerance: f64,
) -> Option<Vec<f64>> {
    let mut x = start.to_vec();
    let mut fx = f(&x)?;
    let (mut work, mut trial) = (Vec::new(), Vec::with_capacity(x.len()));
    for _ in 0..60 {
        let r = norm(&fx);
        if r < tolerance {
            return Some(x);
        }
        let j = jacobian(&x)?;
        let d = newton_step(&j, &fx, &mut work)?;
        let mut step = 1.0;
        loop {
            trial.clear();
            trial.extend(x.iter().zip(&d).map(|(a, b)| a + step * b));
            if let Some(ft) = f(&trial) {
                if norm(&ft) < r || step < 1e-3 {
                    std::mem::swap(&mut x, &mut trial);
                    fx = ft;
                    break;
                }
            }
            step *= 0.5;
            if step < 1e-4 {
                return None;
            }
        }
    }
    (norm(&fx) < tolerance).then_some(x)
}

/// Whether two points are the same root (angles modulo 2π).
fn same(a: &[f64], b: &[f64], periodic: &[bool]) -> bool {
    a.iter().zip(b).zip(periodic).all(|((x, y), p)| {
        let d = if *p { wrap_angle(x - y) } else { x - y };
        d.abs() < 1e-6 * (1.0 + x.abs().max(y.abs()))
    })
}

/// Adds a root (angles wrapped) when it is inside the box and new.
fn push_root(roots: &mut Vec<Vec<f64>>, mut x: Vec<f64>, search: &Search) {
    for (i, v) in x.iter_mut().enumerate() {
        if search.periodic[i] {
            *v = wrap_angle(*v);
        } else {
            let (lo, hi) = search.bounds[i];
            let slack = 1e-9 * (1.0 + lo.abs().max(hi.abs()));
            if *v < lo - slack || *v > hi + slack {
                return;
            }
        }
    }
    if !roots.iter().any(|r| same(r, &x, &search.periodic)) {
        roots.push(x);
    }
}

/// All roots found in the box (see the module doc for what "all" means here).
pub fn find_roots(f: &Residual<'_>, jacobian: &Residual<'_>, search: &Search) -> Vec<Vec<f64>> {
    let n = search.bounds.len();
    let mut roots = Vec::new();
    if n == 0 {
        return roots;
    }
    if n == 1 {
        let (mut lo, hi) = search.bounds[0];
        let steps = search.scan_points.max(8);
        let h = (hi - lo) / steps as f64;
        if search.periodic[0] {
            // A full turn, shifted by an irrational fraction of a step so that symmetric
            // roots (0, ±π) do not sit on a sample or on the seam.
            let shift = std::f64::consts::FRAC_1_PI * h;
            lo += shift;
        }
        let value = |x: f64| f(&[x]).and_then(|v| v.first().copied());
        let samples: Vec<(f64, Option<f64>)> = (0..=steps)
            .map(|i| lo + h * i as f64)
            .map(|x| (x, value(x)))
            .collect();
        for w in samples.windows(3) {
            let [(x0, f0), (x1, f1), (_, f2)] = [w[0], w[1], w[2]];
            let (Some(f0), Some(f1), Some(f2)) = (f0, f1, f2) else {
                continue;
            };
            // A sign change on [x0, x1] (each interval is the first of one window, plus the
            // last interval below): bisect, then polish with Newton.
            if f0 == 0.0 {
                push_root(&mut roots, vec![x0], search);
            }
            if f0 * f1 < 0.0 {
                if let Some(r) = bisect(&value, x0, x1, f0) {
                    let polished = newton(f, jacobian, &[r], search.tolerance).unwrap_or(vec![r]);
                    push_root(&mut roots, polished, search);
                }
            }
            // A local minimum of |F| without a sign change: a double root is possible.
            if f1.abs() <= f0.abs() && f1.abs() <= f2.abs() && f0 * f2 > 0.0 && f0 * f1 > 0.0 {
                if let Some(r) = newton(f, jacobian, &[x1], search.tolerance) {
                    if (r[0] - x1).abs() <= 2.0 * h {
                        push_root(&mut roots, r, search);
                    }
                }
            }
        }
        if let [.., (xa, Some(fa)), (xb, Some(fb))] = samples[..] {
            if fb == 0.0 {
                push_root(&mut roots, vec![xb], search);
            }
            if fa * fb < 0.0 {
                if let Some(r) = bisect(&value, xa, xb, fa) {
                    push_root(&mut roots, vec![r], search);
                }
            }
        }
    } else {
        for start in starts(search) {
            if let Some(r) = newton(f, jacobian, &start, search.tolerance) {
                push_root(&mut roots, r, search);
            }
        }
    }
    roots.sort_by(|a, b| {
        a.iter()
            .zip(b)
            .map(|(x, y)| x.total_cmp(y))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    roots
}

/// Newton starts in several dimensions, at most `max_starts` of them: a grid while one with
/// at least two points per axis fits, else the first points of a Halton sequence (a grid of
/// 2ⁿ points grows without bound). Angles are shifted by an irrational fraction of a cell, so
/// that no start sits where symmetric models have a singular Jacobian (`cos q = 0` at ±π/2).
fn starts(search: &Search) -> Vec<Vec<f64>> {
    let n = search.bounds.len();
    let budget = search.max_starts.max(1);
    let per_axis = (budget as f64).powf(1.0 / n as f64).floor() as usize;
    let place = |i: usize, u: f64, cell: f64| {
        let (lo, hi) = search.bounds[i];
        let shift = if search.periodic[i] {
            std::f64::consts::FRAC_1_PI * cell
        } else {
            0.0
        };
        lo + (hi - lo) * (u + shift).rem_euclid(1.0)
    };
    if per_axis >= 2 {
        let cell = 1.0 / per_axis as f64;
        let total = per_axis.pow(n as u32);
        return (0..total)
            .map(|index| {
                let mut rest = index;
                (0..n)
                    .map(|i| {
                        let k = rest % per_axis;
                        rest /= per_axis;
                        place(i, (k as f64 + 0.5) * cell, cell)
                    })
                    .collect()
            })
            .collect();
    }
    let primes = first_primes(n);
    (1..=budget)
        .map(|index| {
            (0..n)
                .map(|i| place(i, radical_inverse(index, primes[i]), 1.0 / budget as f64))
                .collect()
        })
        .collect()
}

/// The first `n` primes (the bases of a Halton sequence).
fn first_primes(n: usize) -> Vec<usize> {
    let mut primes: Vec<usize> = Vec::with_capacity(n);
    let mut candidate = 2;
    while primes.len() < n {
        if primes.iter().all(|p| candidate % p != 0) {
            primes.push(candidate);
        }
        candidate += 1;
    }
    primes
}

/// The van der Corput radical inverse of `index` in `base`, in `[0, 1)`.
fn radical_inverse(mut index: usize, base: usize) -> f64 {
    let mut result = 0.0;
    let mut scale = 1.0 / base as f64;
    while index > 0 {
        result += (index % base) as f64 * scale;
        index /= base;
        scale /= base as f64;
    }
    result
}

/// Bisection of a sign change of `value` on `[a, b]` (`fa = value(a)`).
fn bisect(value: &dyn Fn(f64) -> Option<f64>, mut a: f64, mut b: f64, mut fa: f64) -> Option<f64> {
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        let fm = value(m)?;
        if fm == 0.0 {
            return Some(m);
        }
        if fa * fm < 0.0 {
            b = m;
        } else {
            a = m;
            fa = fm;
        }
    }
    Some(0.5 * (a + b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn newton_starts_stay_within_budget_and_off_the_symmetric_points() {
        let half = std::f64::consts::FRAC_PI_2;
        for n in [2, 9, 10, 20] {
            let search = Search::new(
                vec![(-std::f64::consts::PI, std::f64::consts::PI); n],
                vec![true; n],
            );
            let starts = starts(&search);
            assert!(
                !starts.is_empty() && starts.len() <= search.max_starts,
                "n = {n}"
            );
            for x in starts.iter().flatten() {
                assert!((x.abs() - half).abs() > 1e-9, "n = {n}: a start at ±π/2");
            }
        }
    }

    #[test]
    fn finds_every_root_of_a_trigonometric_equation_in_one_angle() {
        // sin θ (cos θ − 0.3) = 0: θ = 0, π, ±acos 0.3.
        let f = |x: &[f64]| Some(vec![x[0].sin() * (x[0].cos() - 0.3)]);
        let j = |x: &[f64]| Some(vec![x[0].cos() * (x[0].cos() - 0.3) - x[0].sin().powi(2)]);
        let search = Search::new(
            vec![(-std::f64::consts::PI, std::f64::consts::PI)],
            vec![true],
        );
        let roots = find_roots(&f, &j, &search);
        assert_eq!(roots.len(), 4, "{roots:?}");
        assert!(roots.iter().any(|r| (r[0] - 0.3_f64.acos()).abs() < 1e-9));
    }

    #[test]
    fn finds_a_double_root() {
        let f = |x: &[f64]| Some(vec![(x[0] - 0.123_456).powi(2)]);
        let j = |x: &[f64]| Some(vec![2.0 * (x[0] - 0.123_456)]);
        let search = Search::new(vec![(-1.0, 1.0)], vec![false]);
        let roots = find_roots(&f, &j, &search);
        assert_eq!(roots.len(), 1);
        assert!((roots[0][0] - 0.123_456).abs() < 1e-4);
    }

    #[test]
    fn newton_grid_in_two_dimensions() {
        // x² + y² = 1, y = x: two roots.
        let f = |v: &[f64]| Some(vec![v[0] * v[0] + v[1] * v[1] - 1.0, v[1] - v[0]]);
        let j = |v: &[f64]| Some(vec![2.0 * v[0], 2.0 * v[1], -1.0, 1.0]);
        let search = Search::new(vec![(-2.0, 2.0), (-2.0, 2.0)], vec![false, false]);
        let roots = find_roots(&f, &j, &search);
        assert_eq!(roots.len(), 2, "{roots:?}");
    }
}
