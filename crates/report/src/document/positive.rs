//! What the parameters' signs let a report say more simply. A parameter whose value is
//! positive (a mass, a length, `g`, a stiffness) is taken positive in the symbolic statements:
//!
//! * a condition `−m_B g ℓ ≠ 0` or `−k ≠ 0` holds outright and is not written;
//! * `abs(C/(m_B g ℓ)) ≤ 1` is written `abs(C) ≤ m_B g ℓ`;
//! * a root of a fraction over a square of positive symbols is taken apart:
//!   `√((m_B² g² ℓ² − C²)/(m_B² g² ℓ²))` → `√(m_B² g² ℓ² − C²)/(m_B g ℓ)`.
//!
//! The value of an expression never changes for positive values of those parameters; the
//! numbers the report prints are computed from the unchanged expressions.

use cas::solve::Condition;
use cas::{Expr, Node, Symbol};

#[cfg(test)]
use super::Math;
use super::Notation;

/// The positive square root of a monomial of positive symbols with even powers and a square
/// positive number (`ℓ² sin⁰` → `ℓ`, `4 m²` → `2 m`); `None` otherwise.
#[must_use]
pub fn positive_root(e: Expr, positive: &dyn Fn(Symbol) -> bool) -> Option<Expr> {
    match e.node() {
        Node::Number(n) => {
            let root = |k: &cas::Number| {
                let k = k.to_i64().filter(|k| *k > 0)?;
                // The integer root, checked exactly (the float's root may be off by one).
                let r = (k as f64).sqrt().round() as i64;
                (r.checked_mul(r) == Some(k)).then_some(r)
            };
            Expr::rational(root(&n.numer())?, root(&n.denom())?)
        }
        Node::Pow([base, exponent]) => {
            let k = exponent.as_number()?.to_i64()?;
            let s = base.as_symbol()?;
            (k > 0 && k % 2 == 0 && positive(s)).then(|| base.powi(k / 2))
        }
        Node::Mul(factors) => factors
            .iter()
            .map(|f| positive_root(*f, positive))
            .collect::<Option<Vec<Expr>>>()
            .map(Expr::mul_all),
        _ => None,
    }
}

/// Whether `e` is a product of a non-zero number and powers of positive symbols.
fn nonzero_monomial(e: Expr, positive: &dyn Fn(Symbol) -> bool) -> bool {
    match e.node() {
        Node::Number(_) => !e.is_literal_zero(),
        Node::Symbol(s) => positive(*s),
        Node::Pow([base, exponent]) => {
            exponent.as_number().is_some() && base.as_symbol().is_some_and(positive)
        }
        Node::Mul(factors) => factors.iter().all(|f| nonzero_monomial(*f, positive)),
        _ => false,
    }
}

/// Whether `e` is a product of a positive number and powers of positive symbols.
fn positive_monomial(e: Expr, positive: &dyn Fn(Symbol) -> bool) -> bool {
    let factors: Vec<Expr> = match e.node() {
        Node::Mul(f) => f.to_vec(),
        _ => vec![e],
    };
    factors.iter().all(|f| match f.node() {
        Node::Number(n) => n.to_f64() > 0.0,
        _ => nonzero_monomial(*f, positive),
    })
}

/// `e` with every square root of a fraction over a square of positive symbols taken apart.
fn split_roots(e: Expr, positive: &dyn Fn(Symbol) -> bool) -> Expr {
    let map = |v: &[Expr]| -> Vec<Expr> { v.iter().map(|x| split_roots(*x, positive)).collect() };
    match e.node() {
        Node::Add(terms) => Expr::add_all(map(terms)),
        Node::Mul(factors) => Expr::mul_all(map(factors)),
        Node::Func(f, args) => Expr::func(*f, map(args)),
        Node::Pow([base, exponent]) => {
            let half = Expr::rational(1, 2).is_some_and(|h| h == *exponent);
            if half {
                let (numerator, denominator) = base.numer_denom();
                if !denominator.is_literal_one() {
                    if let Some(root) = positive_root(denominator, positive) {
                        return numerator.sqrt() * root.powi(-1);
                    }
                }
            }
            split_roots(*base, positive).pow(*exponent)
        }
        _ => e,
    }
}

impl Notation {
    /// Whether the parameter named by `s` has a positive value.
    pub(crate) fn is_positive(&self, s: Symbol) -> bool {
        self.positive.iter().any(|p| p == s.name())
    }

    /// `e` with its roots taken apart where the parameters' signs allow (see the module
    /// documentation).
    pub(crate) fn split_roots(&self, e: Expr) -> Expr {
        if self.positive.is_empty() {
            return e;
        }
        split_roots(e, &|s| self.is_positive(s))
    }

    /// The conditions an equilibrium exists under, as people read them: those that hold for
    /// every positive value of the parameters left out, `abs(u/d) ≤ 1` with a positive
    /// monomial `d` written `abs(u) ≤ d`.
    #[must_use]
    pub fn conditions(&self, conditions: &[Condition]) -> Vec<String> {
        let positive = |s: Symbol| self.is_positive(s);
        conditions
            .iter()
            .filter_map(|c| match c {
                Condition::NonZero(e) if nonzero_monomial(e.normal(), &positive) => None,
                Condition::AbsAtMostOne(e) => {
                    let (numerator, denominator) = e.numer_denom();
                    Some(
                        if positive_monomial(denominator, &positive)
                            && positive_monomial(numerator, &positive)
                        {
                            // `|g/(R Ω²)| ≤ 1` with all of them positive: `g ≤ R Ω²`.
                            format!(
                                "{} ≤ {}",
                                self.math(numerator).unicode,
                                self.math(denominator).unicode
                            )
                        } else if positive_monomial(denominator, &positive) {
                            format!(
                                "abs({}) ≤ {}",
                                self.math(numerator).unicode,
                                self.math(denominator).unicode
                            )
                        } else {
                            format!("abs({}) ≤ 1", self.math(*e).unicode)
                        },
                    )
                }
                Condition::NonNegative(e) => Some(format!("{} ≥ 0", self.math(*e).unicode)),
                Condition::NonZero(e) => Some(format!("{} ≠ 0", self.math(*e).unicode)),
                Condition::Zero(e) => Some(format!("{} = 0", self.math(*e).unicode)),
                _ => Some("a further condition".to_string()),
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn notation() -> Notation {
        Notation {
            positive: ["m_B", "g", "l", "k"].map(String::from).to_vec(),
            ..Notation::default()
        }
    }

    #[test]
    fn conditions_that_positive_parameters_meet_are_left_out() {
        let (m, g, l, k, c) = ["m_B", "g", "l", "k", "C"].map(Expr::symbol).into();
        let conditions = [
            Condition::AbsAtMostOne(c / (m * g * l)),
            Condition::NonZero(-(m * g * l)),
            Condition::NonZero(-k),
            Condition::NonZero(c),
            Condition::AbsAtMostOne(g / (k * l)),
        ];
        assert_eq!(
            notation().conditions(&conditions),
            ["abs(C) ≤ m_B g ℓ", "C ≠ 0", "g ≤ k ℓ"]
        );
        // Without positive parameters every condition stays.
        assert_eq!(Notation::default().conditions(&conditions).len(), 5);
    }

    #[test]
    fn roots_over_squares_of_positive_parameters_are_taken_apart() {
        let (m, g, l, c) = ["m_B", "g", "l", "C"].map(Expr::symbol).into();
        let u = c / (m * g * l);
        // cos(asin(u)) as the equilibria write it, times m_B g ℓ: K0 of 7.1.
        let k0 = m * g * l * (Expr::one() - u * u).normal().sqrt();
        let shaped = notation().shape(k0);
        assert_eq!(Math::expr(shaped).unicode, "√(m_B² g² ℓ² − C²)");
        assert_eq!(notation().math(k0).unicode, "√(m_B² g² ℓ² − C²)");
        // The same value for positive parameters, at a few points.
        for (mv, gv, lv, cv) in [(1.0, 9.81, 0.5, 0.3), (2.0, 1.5, 3.0, -1.0)] {
            let env = |s: Symbol| match s.name() {
                "m_B" => Some(mv),
                "g" => Some(gv),
                "l" => Some(lv),
                "C" => Some(cv),
                _ => None,
            };
            let (a, b) = (k0.eval(&env), shaped.eval(&env));
            assert!(matches!((a, b), (Ok(a), Ok(b)) if (a - b).abs() < 1e-12));
        }
        // A root over a square of a parameter of unknown sign stays whole.
        assert!(Math::expr(Notation::default().shape(k0))
            .unicode
            .contains("/(m_B² g² ℓ²)"));
    }
}
