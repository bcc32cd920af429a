//! Trigonometry in normal form: `sin`/`cos` of sums and integer multiples expanded into products
//! of single angles, with exact values at multiples of π/6 and π/4.

use crate::expr::Expr;
use crate::number::Number;
use crate::poly::{trig_atoms, Monomial};

use super::{monomial_to_expr, poly_to_expr, Normalizer, Rf};

/// The largest multiple `n` for which `sin nθ` and `cos nθ` are expanded into polynomials in
/// `sin θ`, `cos θ`. Beyond it `sin nθ` is an atom of its own: the expansion has degree `n` and
/// coefficients up to `2^(n−1)`, so it costs work growing with `n` (`sin(1000000 x)` never
/// finished) and evaluates with a cancellation error near `2^n ε` (a potential `1 − cos 60x`
/// evaluated to noise). Identities between `sin nθ` and `sin θ` are promised up to this bound.
pub(crate) const MAX_EXPANDED_MULTIPLE: u64 = 12;

/// `(cos nθ, sin nθ)` from `(cos θ, sin θ)` by binary powering of `cos θ + i sin θ`.
fn multiple_angle(c: &Rf, s: &Rf, n: i64) -> (Rf, Rf) {
    let (mut bc, mut bs) = (c.clone(), if n < 0 { s.neg() } else { s.clone() });
    let mut k = n.unsigned_abs();
    let (mut rc, mut rs) = (Rf::one(), Rf::zero());
    while k > 0 {
        if k & 1 == 1 {
            let nc = rc.mul(&bc).sub(&rs.mul(&bs));
            let ns = rs.mul(&bc).add(&rc.mul(&bs));
            rc = nc;
            rs = ns;
        }
        k >>= 1;
        if k > 0 {
            let nc = bc.mul(&bc).sub(&bs.mul(&bs));
            let ns = bs.mul(&bc).scale(&Number::int(2));
            bc = nc;
            bs = ns;
        }
    }
    (rc, rs)
}

/// Exact `(cos, sin)` of `n π / q` for `q` dividing 12 (multiples of π/6 and π/4).
fn exact_trig_of_pi_multiple(nz: &mut Normalizer, n: i64, q: i64) -> Option<(Rf, Rf)> {
    if 12 % q != 0 {
        return None;
    }
    // Angle in twelfths of π, reduced to [0, 24).
    let k = (n.checked_mul(12 / q)?).rem_euclid(24);
    let half = Number::rational(1, 2)?;
    let sqrt = |nz: &mut Normalizer, v: i64| nz.root_of_number(&Number::int(v), 2);
    let s3_2 = sqrt(nz, 3)?.scale(&half);
    let s2_2 = sqrt(nz, 2)?.scale(&half);
    let h = Rf::constant(half.clone());
    let table = |k: i64| -> Option<(Rf, Rf)> {
        Some(match k {
            0 => (Rf::one(), Rf::zero()),
            2 => (s3_2.clone(), h.clone()),
            3 => (s2_2.clone(), s2_2.clone()),
            4 => (h.clone(), s3_2.clone()),
            6 => (Rf::zero(), Rf::one()),
            _ => return None,
        })
    };
    // Use symmetries to bring k into [0, 6].
    let (kk, cos_sign, sin_sign) = match k {
        0..=6 => (k, 1, 1),
        7..=12 => (12 - k, -1, 1),
        13..=18 => (k - 12, -1, -1),
        _ => (24 - k, 1, -1),
    };
    let (c, s) = table(kk)?;
    let c = if cos_sign < 0 { c.neg() } else { c };
    let s = if sin_sign < 0 { s.neg() } else { s };
    Some((c, s))
}

impl Normalizer {
    /// `(cos a, sin a)` of a normalised angle, expanded over the terms of the angle.
    pub(crate) fn trig(&mut self, angle: &Rf) -> (Rf, Rf) {
        let mut cos = Rf::one();
        let mut sin = Rf::zero();
        let den = angle.den.clone();
        let den_expr = if den.is_one() {
            None
        } else {
            Some(poly_to_expr(&den))
        };
        for (m, c) in &angle.num.terms {
            let (ct, st) = self.trig_of_term(m, c, den_expr);
            let new_cos = cos.mul(&ct).sub(&sin.mul(&st));
            let new_sin = sin.mul(&ct).add(&cos.mul(&st));
            cos = new_cos;
            sin = new_sin;
        }
        (cos, sin)
    }

    /// `(cos, sin)` of one term `c m / den` of an angle.
    fn trig_of_term(&mut self, m: &Monomial, c: &Number, den: Option<Expr>) -> (Rf, Rf) {
        let unit = match den {
            Some(d) => monomial_to_expr(m) * d.powi(-1),
            None => monomial_to_expr(m),
        };
        if c.is_float() {
            if m.is_empty() && den.is_none() {
                let x = c.to_f64();
                return (
                    Rf::constant(Number::Float(x.cos())),
                    Rf::constant(Number::Float(x.sin())),
                );
            }
            let (s, k) = trig_atoms(Expr::number(c.clone()) * unit);
            return (Rf::atom(k), Rf::atom(s));
        }
        let is_pi = unit == Expr::pi();
        let (n, q) = c.to_small_ratio().unwrap_or((1, 1));
        if is_pi {
            if let Some(exact) = exact_trig_of_pi_multiple(self, n, q) {
                return exact;
            }
        }
        // A numeric angle (`cos(3/10)`) is its own atom: writing it as a multiple of 1/10 is
        // as canonical but prints a triple-angle polynomial nobody wants to read.
        if m.is_empty() && den.is_none() {
            let (s_id, c_id) = trig_atoms(Expr::number(c.abs()));
            let sign = if c.is_negative() { -1 } else { 1 };
            return multiple_angle(&Rf::atom(c_id), &Rf::atom(s_id), sign);
        }
        // c = n/q: the angle unit is m/q, taken `n` times. A large multiple stays an angle of its
        // own (see `MAX_EXPANDED_MULTIPLE`); a negative one keeps the parity rule.
        let small = c.to_small_ratio().is_some() && n.unsigned_abs() <= MAX_EXPANDED_MULTIPLE;
        let (angle_unit, multiple) = if !small {
            (
                Expr::number(c.abs()) * unit,
                if c.is_negative() { -1 } else { 1 },
            )
        } else if q == 1 {
            (unit, n)
        } else {
            (unit * Expr::rational(1, q).unwrap_or_else(Expr::one), n)
        };
        let (s_id, c_id) = trig_atoms(angle_unit);
        let base_cos = Rf::atom(c_id);
        let base_sin = Rf::atom(s_id);
        multiple_angle(&base_cos, &base_sin, multiple)
    }
}
