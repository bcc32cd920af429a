//! Complete numerical equilibria of one unknown whose rest equation is a polynomial: in the
//! coordinate itself, or in `sin q`, `cos q`, `tan q` of an angle. The tangent half-angle
//! substitution `u = tan(q/2)` (`sin q = 2u/(1+u²)`, `cos q = (1−u²)/(1+u²)`) turns a
//! trigonometric polynomial into a polynomial in `u`; every real root is then found as an
//! eigenvalue of the companion matrix, so no equilibrium is missed (`q = π`, `u = ∞`, is
//! checked on its own).

use cas::{Expr, Symbol};

/// A rest equation as a polynomial, with coefficients symbolic in the parameters.
#[derive(Clone, Debug)]
pub struct RestPolynomial {
    /// Which coordinate (index).
    pub coordinate: usize,
    /// Coefficients of `u⁰, u¹, …` where `u = tan(q/2)` for an angle, `u = q` otherwise.
    pub coefficients: Vec<Expr>,
    /// Whether `u` is the tangent of the half angle.
    pub half_angle: bool,
}

/// The largest degree tried.
const MAX_DEGREE: u32 = 24;

/// Coefficients of `e` as a polynomial in the atom `u`, free of `x`; `None` otherwise.
fn coefficients(e: Expr, u: Expr, x: Symbol) -> Option<Vec<Expr>> {
    let mut c = Vec::new();
    let mut rebuilt = Expr::zero();
    for k in 0..=MAX_DEGREE {
        let ck = e.coeff(u, k)?;
        if !ck.diff(x).is_zero() {
            return None;
        }
        rebuilt += ck * u.powi(i64::from(k));
        c.push(ck);
        if (rebuilt - e).is_zero() {
            while c.last().is_some_and(|v| v.is_zero()) {
                c.pop();
            }
            return Some(c);
        }
    }
    None
}

/// The polynomial form of `residual = 0` in coordinate `index` (symbol `x`), if it has one.
pub(crate) fn rest_polynomial(
    residual: Expr,
    index: usize,
    x: Symbol,
    periodic: bool,
) -> Option<RestPolynomial> {
    let (numerator, _) = residual.normal().numer_denom();
    if numerator.is_zero() {
        return None;
    }
    let q = Expr::from_symbol(x);
    if periodic {
        let u = Expr::symbol("__half_angle_u");
        let one_plus = Expr::one() + u.powi(2);
        let s = 2 * u / one_plus;
        let c = (Expr::one() - u.powi(2)) / one_plus;
        let t = 2 * u / (Expr::one() - u.powi(2));
        let substituted = numerator.subs(&[(q.sin(), s), (q.cos(), c), (q.tan(), t)]);
        if !substituted.diff(x).is_zero() {
            return None;
        }
        let (poly, _) = substituted.normal().numer_denom();
        let coefficients = coefficients(poly, u, x)?;
        Some(RestPolynomial {
            coordinate: index,
            coefficients,
            half_angle: true,
        })
    } else {
        let coefficients = coefficients(numerator, q, x)?;
        Some(RestPolynomial {
            coordinate: index,
            coefficients,
            half_angle: false,
        })
    }
}

/// The real roots of `Σ c_k u^k` (coefficients numeric), by the companion matrix. `None`
/// when the polynomial vanishes identically for these numbers.
pub(crate) fn real_roots(c: &[f64]) -> Option<Vec<f64>> {
    let scale = c.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    if scale == 0.0 || !scale.is_finite() {
        return None;
    }
    let mut c: Vec<f64> = c.to_vec();
    while c.last().is_some_and(|v| v.abs() <= 1e-14 * scale) {
        c.pop();
    }
    let degree = c.len().saturating_sub(1);
    if degree == 0 {
        return Some(Vec::new());
    }
    let lead = c[degree];
    let mut companion = vec![vec![0.0; degree]; degree];
    for (i, row) in companion.iter_mut().enumerate().skip(1) {
        row[i - 1] = 1.0;
    }
    for (k, ck) in c.iter().take(degree).enumerate() {
        companion[k][degree - 1] = -ck / lead;
    }
    let eig = numeric::eigen::eigenvalues(&companion).ok()?;
    Some(
        eig.into_iter()
            // Double roots split into pairs with imaginary parts of order √ε.
            .filter(|(re, im)| im.abs() <= 1e-6 * (1.0 + re.abs()))
            .map(|(re, _)| re)
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn companion_roots_of_a_cubic() {
        // (u − 1)(u + 2)(u − 3) = u³ − 2u² − 5u + 6.
        let mut r = real_roots(&[6.0, -5.0, -2.0, 1.0]).unwrap();
        r.sort_by(f64::total_cmp);
        assert!((r[0] + 2.0).abs() < 1e-12 && (r[1] - 1.0).abs() < 1e-12);
        assert!((r[2] - 3.0).abs() < 1e-12);
        assert!(real_roots(&[1.0, 0.0, 1.0]).unwrap().is_empty());
    }

    #[test]
    fn half_angle_form_of_a_trigonometric_equation() {
        let th = Expr::coordinate("th");
        let x = th.as_symbol().unwrap();
        // sin θ (2 cos θ − 1) with cos³ to push the degree past the exact solver.
        let e = th.sin() * (2 * th.cos() - 1) + th.cos().powi(3) - th.cos();
        let p = rest_polynomial(e, 0, x, true).unwrap();
        assert!(p.half_angle);
        let c: Vec<f64> = p
            .coefficients
            .iter()
            .map(|c| c.eval(&|_| None).unwrap())
            .collect();
        for u in real_roots(&c).unwrap() {
            let t = 2.0 * u.atan();
            let v = t.sin() * (2.0 * t.cos() - 1.0) + t.cos().powi(3) - t.cos();
            assert!(v.abs() < 1e-9, "{t}: {v}");
        }
    }
}
