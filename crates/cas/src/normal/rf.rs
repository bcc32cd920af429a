//! [`Rf`], a fraction of polynomials in canonical form: its arithmetic, and the canonical
//! denominator (integer-primitive, positive leading term, rationalised while small).

use crate::expr::Expr;
use crate::limits;
use crate::number::Number;
use crate::poly::{self, gcd, AtomId, AtomKind, Poly};

use super::{monomial_to_expr, poly_to_expr};

/// A fraction of polynomials in canonical form (see the module documentation).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct Rf {
    pub(crate) num: Poly,
    pub(crate) den: Poly,
}

impl Rf {
    pub(crate) fn from_poly(p: Poly) -> Rf {
        Rf {
            num: p,
            den: Poly::one(),
        }
    }

    pub(crate) fn constant(c: Number) -> Rf {
        Rf::from_poly(Poly::constant(c))
    }

    pub(crate) fn zero() -> Rf {
        Rf::from_poly(Poly::zero())
    }

    pub(crate) fn one() -> Rf {
        Rf::from_poly(Poly::one())
    }

    pub(crate) fn atom(id: AtomId) -> Rf {
        Rf::from_poly(Poly::atom(id))
    }

    pub(crate) fn is_zero(&self) -> bool {
        self.num.is_zero()
    }

    pub(crate) fn as_constant(&self) -> Option<Number> {
        if self.den.is_one() {
            self.num.as_constant()
        } else {
            None
        }
    }

    /// `num / den` brought to canonical form; `None` when `den` is zero.
    pub(crate) fn new(num: Poly, den: Poly) -> Option<Rf> {
        if den.is_zero() {
            return None;
        }
        if num.is_zero() {
            return Some(Rf::zero());
        }
        if den.is_one() {
            return Some(Rf::from_poly(num));
        }
        let (num, den) = rationalize(num, den);
        if let Some(c) = den.as_constant() {
            return Some(Rf::from_poly(num.scale(&c.recip()?)));
        }
        let g = gcd(&num, &den);
        let (num, den) = if g.is_one() || g.as_constant().is_some() {
            (num, den)
        } else {
            match (num.div_exact(&g), den.div_exact(&g)) {
                (Some(n), Some(d)) => (n, d),
                _ => (num, den),
            }
        };
        if let Some(c) = den.as_constant() {
            return Some(Rf::from_poly(num.scale(&c.recip()?)));
        }
        let unit = denominator_unit(&den);
        let inv = unit.recip()?;
        Some(Rf {
            num: num.scale(&inv),
            den: den.scale(&inv),
        })
    }

    pub(crate) fn add(&self, other: &Rf) -> Rf {
        if self.den.is_one() && other.den.is_one() {
            return Rf::from_poly(self.num.add(&other.num));
        }
        if self.is_zero() {
            return other.clone();
        }
        if other.is_zero() {
            return self.clone();
        }
        // P + N/D = (P D + N)/D is already reduced: a common factor of `P D + N` and `D`
        // would divide `N`, and `N/D` is reduced. That holds in `ℚ[atoms]`, so only when the
        // product `P D` rewrites nothing (a plain, exact `D`); no GCD of the large sum.
        if self.den.is_one() && other.den.is_plain_exact() {
            return Rf::reduced(self.num.mul(&other.den).add(&other.num), other.den.clone());
        }
        if other.den.is_one() && self.den.is_plain_exact() {
            return Rf::reduced(other.num.mul(&self.den).add(&self.num), self.den.clone());
        }
        if self.den == other.den {
            return Rf::new(self.num.add(&other.num), self.den.clone()).unwrap_or_else(Rf::zero);
        }
        let g = gcd(&self.den, &other.den);
        let split = if g.as_constant().is_some() {
            None
        } else {
            self.den.div_exact(&g).zip(other.den.div_exact(&g))
        };
        let (num, den) = match split {
            // n1/(g a) + n2/(g b) = (n1 b + n2 a) / (g a b)
            Some((a, b)) => (self.num.mul(&b).add(&other.num.mul(&a)), self.den.mul(&b)),
            None => {
                let num = self.num.mul(&other.den).add(&other.num.mul(&self.den));
                let den = self.den.mul(&other.den);
                // Coprime reduced fractions: a factor of `n1 d2 + n2 d1` and `d1` divides
                // `n1 d2`, so none is common (again in `ℚ[atoms]`, plain exact denominators).
                if self.den.is_plain_exact() && other.den.is_plain_exact() {
                    return Rf::reduced(num, den);
                }
                (num, den)
            }
        };
        Rf::new(num, den).unwrap_or_else(Rf::zero)
    }

    /// `Σ parts`, equal to adding them one by one. The polynomial parts are
    /// gathered and sort-merged once: adding a long list one at a time copies the growing sum
    /// for every part (a chain's kinetic energy, one particle at a time, was O(n⁴) for the
    /// O(n³) terms of the n-link). Equal monomials are merged in the order of the parts, so
    /// even float coefficients add up as the fold would; fractions are added after them.
    pub(crate) fn sum<'a>(parts: impl IntoIterator<Item = &'a Rf>) -> Rf {
        let mut terms = Vec::new();
        let mut fractions: Vec<&Rf> = Vec::new();
        for r in parts {
            if r.den.is_one() {
                terms.extend(r.num.terms.iter().cloned());
            } else {
                fractions.push(r);
            }
        }
        if !limits::spend(terms.len() as u64) {
            return Rf::zero();
        }
        let polynomial = Rf::from_poly(Poly::from_terms(terms));
        fractions.into_iter().fold(polynomial, |s, r| s.add(r))
    }

    /// `num / den` known to have no common factor, with `den` plain, exact and not constant:
    /// only the canonical unit of the denominator is applied (no GCD, nothing to rationalise).
    fn reduced(num: Poly, den: Poly) -> Rf {
        if num.is_zero() {
            return Rf::zero();
        }
        let unit = denominator_unit(&den);
        match unit.recip() {
            Some(inv) if !unit.is_one() => Rf {
                num: num.scale(&inv),
                den: den.scale(&inv),
            },
            _ => Rf { num, den },
        }
    }

    pub(crate) fn neg(&self) -> Rf {
        Rf {
            num: self.num.neg(),
            den: self.den.clone(),
        }
    }

    pub(crate) fn sub(&self, other: &Rf) -> Rf {
        // Two polynomials: one merge, as `add` does, without a negated copy of `other`.
        if self.den.is_one() && other.den.is_one() {
            return Rf::from_poly(self.num.sub(&other.num));
        }
        self.add(&other.neg())
    }

    pub(crate) fn mul(&self, other: &Rf) -> Rf {
        if self.den.is_one() && other.den.is_one() {
            return Rf::from_poly(self.num.mul(&other.num));
        }
        Rf::new(self.num.mul(&other.num), self.den.mul(&other.den)).unwrap_or_else(Rf::zero)
    }

    pub(crate) fn scale(&self, c: &Number) -> Rf {
        Rf {
            num: self.num.scale(c),
            den: self.den.clone(),
        }
    }

    /// `1 / self`; `None` for zero.
    pub(crate) fn recip(&self) -> Option<Rf> {
        if self.num.is_zero() {
            return None;
        }
        Rf::new(self.den.clone(), self.num.clone())
    }

    pub(crate) fn div(&self, other: &Rf) -> Option<Rf> {
        Some(self.mul(&other.recip()?))
    }

    pub(crate) fn powi(&self, k: i64) -> Option<Rf> {
        let e = u32::try_from(k.unsigned_abs()).ok()?;
        let p = Rf::new(self.num.pow(e), self.den.pow(e))?;
        if k < 0 {
            p.recip()
        } else {
            Some(p)
        }
    }

    /// The expression tree of this normal form.
    pub(crate) fn to_expr(&self) -> Expr {
        let n = poly_to_expr(&self.num);
        if self.den.is_one() {
            return n;
        }
        n * poly_to_expr(&self.den).powi(-1)
    }
}

/// The coefficient that makes a denominator canonical: integer-primitive with a positive
/// leading term, where "leading" is the largest monomial in the structural order (so the choice
/// does not depend on the order atoms were created in).
fn denominator_unit(den: &Poly) -> Number {
    let lead = den
        .terms
        .iter()
        .max_by(|a, b| monomial_to_expr(&a.0).cmp_structure(monomial_to_expr(&b.0)))
        .map(|(_, c)| c.clone())
        .unwrap_or(Number::ONE);
    if den.terms.iter().any(|(_, c)| c.is_float()) {
        return lead;
    }
    let content = den.terms.iter().fold(Number::ZERO, |g, (_, c)| g.gcd(c));
    if lead.is_negative() {
        content.neg()
    } else {
        content
    }
}

/// Multiplies numerator and denominator by conjugates until the denominator is free of `sin`
/// atoms and square roots, and of roots in single-term denominators.
///
/// Each conjugation roughly squares the denominator, so this is only done while the
/// denominator stays small (`RATIONALIZE_MAX_TERMS`); past that the fraction is left as it is.
/// Zero tests stay exact either way (the numerator alone decides them); only the identity of
/// two normal forms with large trigonometric denominators is then not guaranteed.
fn rationalize(num: Poly, den: Poly) -> (Poly, Poly) {
    const RATIONALIZE_MAX_TERMS: usize = 24;
    let (original_num, original_den) = (num.clone(), den.clone());
    let (mut num, mut den) = (num, den);
    for _ in 0..32 {
        if den.terms.len() > RATIONALIZE_MAX_TERMS {
            return (original_num, original_den);
        }
        let target = den
            .atoms()
            .into_iter()
            .find(|&a| match poly::atom_info(a).kind {
                AtomKind::Sin { .. } => true,
                AtomKind::Root { q, .. } => q == 2 || den.terms.len() == 1,
                _ => false,
            });
        let Some(a) = target else { break };
        let conj = match poly::atom_info(a).kind {
            AtomKind::Root { q, .. } if den.terms.len() == 1 => {
                let e = den.degree(a);
                Poly::atom_pow(a, q - (e % q))
            }
            _ => {
                // den = A + B a with `a` of degree one: multiply by A − B a.
                let mut conj = Poly::zero();
                for (d, c) in den.coefficients_in(a) {
                    let term = c.mul_raw(&Poly::atom_pow(a, d));
                    conj = if d % 2 == 1 {
                        conj.sub(&term)
                    } else {
                        conj.add(&term)
                    };
                }
                conj
            }
        };
        num = num.mul(&conj);
        den = den.mul(&conj);
    }
    (num, den)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::normal::to_rf;

    fn rf(text: &str) -> Rf {
        to_rf(
            crate::parse::parse(text, &crate::parse::ParseContext::new())
                .expect("a test expression"),
        )
    }

    /// The sum through the general path: one numerator over the product of denominators,
    /// reduced by a GCD.
    fn slow_sum(a: &Rf, b: &Rf) -> Rf {
        let num = a.num.mul(&b.den).add(&b.num.mul(&a.den));
        Rf::new(num, a.den.mul(&b.den)).expect("a non-zero denominator")
    }

    #[test]
    fn sums_that_skip_the_gcd_are_those_of_the_general_path() {
        // `Rf::add` skips the GCD for a polynomial plus a fraction and for coprime plain
        // denominators; the result must be the reduced, canonical form all the same.
        let cases = [
            ("x^2 + 3*y", "(x - 1)/(2*y + x^2)"),
            ("sin(t)*x", "cos(t)/(x*y + 3)"),
            ("(x + 1)/(y - 2)", "x/(x + y)"),
            ("(3*x + 1)/(-2*y - 4)", "(x*y)/(6*x + 3)"),
            ("1/(x + 1)", "-1/(x + 1)"),
            ("x/(cos(t) + 2)", "sin(t)/(x^2 + 1)"),
            ("x/(x + sin(t))", "y"),
        ];
        for (a, b) in cases {
            let (a, b) = (rf(a), rf(b));
            assert_eq!(a.add(&b), slow_sum(&a, &b), "{a:?} + {b:?}");
            assert_eq!(b.add(&a), slow_sum(&b, &a), "{b:?} + {a:?}");
        }
    }
}
