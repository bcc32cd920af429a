//! Conditions `P > 0` on the parameters, read the way a course states them: with the
//! parameters whose values are positive (masses, lengths, `g`) taken positive, a factor that
//! cannot change sign is dropped (`m (2 a g − Ω²) > 0` → `2 a g − Ω² > 0`), a polynomial
//! whose terms all have one sign holds always or never, and the rest is written as its
//! positive terms against its negative ones (`Ω² < 2 a g`). Of several conditions, one
//! implied by another is left out: `X > 0` follows from `Y > 0` when `X − Y` has no negative
//! term (`C² ω² − 2 A m g ℓ > 0` from `C² ω² − 4 A m g ℓ > 0`).
//!
//! Nothing here changes the value of a condition for positive values of those parameters;
//! it only decides which part of it can be read off without numbers.

use cas::{Expr, Node, Symbol};

/// What the sign of an expression is for every positive value of the positive parameters
/// and every value of the others.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Sign {
    /// Identically zero.
    Zero,
    /// Strictly positive.
    Positive,
    /// Positive or zero (an even power of a symbol of unknown sign: `ω²`).
    NonNegative,
    /// Strictly negative.
    Negative,
    /// Negative or zero.
    NonPositive,
    /// Either.
    Unknown,
}

impl Sign {
    fn negate(self) -> Sign {
        match self {
            Sign::Positive => Sign::Negative,
            Sign::NonNegative => Sign::NonPositive,
            Sign::Negative => Sign::Positive,
            Sign::NonPositive => Sign::NonNegative,
            s => s,
        }
    }

    fn times(self, other: Sign) -> Sign {
        use Sign::{Negative, NonNegative, NonPositive, Positive, Unknown, Zero};
        match (self, other) {
            (Zero, _) | (_, Zero) => Zero,
            (Unknown, _) | (_, Unknown) => Unknown,
            (Positive, s) | (s, Positive) => s,
            (Negative, s) | (s, Negative) => s.negate(),
            (NonNegative, NonNegative) | (NonPositive, NonPositive) => NonNegative,
            (NonNegative, NonPositive) | (NonPositive, NonNegative) => NonPositive,
        }
    }

    fn plus(self, other: Sign) -> Sign {
        use Sign::{Negative, NonNegative, NonPositive, Positive, Unknown, Zero};
        match (self, other) {
            (Zero, s) | (s, Zero) => s,
            (Positive, Positive | NonNegative) | (NonNegative, Positive) => Positive,
            (NonNegative, NonNegative) => NonNegative,
            (Negative, Negative | NonPositive) | (NonPositive, Negative) => Negative,
            (NonPositive, NonPositive) => NonPositive,
            _ => Unknown,
        }
    }

    /// Whether the value is never negative.
    pub(crate) fn never_negative(self) -> bool {
        matches!(self, Sign::Zero | Sign::Positive | Sign::NonNegative)
    }
}

/// A condition `greater > less` between two sums of terms with positive coefficients.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Inequality {
    /// The larger side.
    pub greater: Expr,
    /// The smaller side.
    pub less: Expr,
}

impl Inequality {
    /// `greater − less`, the polynomial that must be positive.
    #[must_use]
    pub fn difference(&self) -> Expr {
        (self.greater - self.less).normal()
    }

    /// The two sides in reading order, with the relation between them (`"<"` or `">"`): the
    /// side that holds the highest power of one symbol (a speed squared, `Ω²`, `v²`) comes
    /// first, as a course writes `Ω² < 2 a g` and `C² ω² > 4 A m g ℓ`.
    #[must_use]
    pub fn reading_order(&self) -> (Expr, &'static str, Expr) {
        if highest_power(self.less) > highest_power(self.greater) {
            (self.less, "<", self.greater)
        } else {
            (self.greater, ">", self.less)
        }
    }

    /// The inequality written with `print` (`Ω² < 2 a g`).
    #[must_use]
    pub fn text(&self, print: fn(Expr) -> String) -> String {
        let (left, relation, right) = self.reading_order();
        format!("{} {relation} {}", print(left), print(right))
    }
}

/// What `P > 0` says for positive values of the positive parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Reading {
    /// It holds for every value.
    Always,
    /// It holds for no value.
    Never,
    /// It holds exactly when the inequality does.
    When(Inequality),
}

/// The sign of `e` (see [`Sign`]), read off the terms of its normal form.
pub(crate) fn sign(e: Expr, positive: &dyn Fn(Symbol) -> bool) -> Sign {
    let (numerator, denominator) = e.normal().numer_denom();
    sum_sign(numerator, positive).times(sum_sign(denominator, positive))
}

/// `P > 0` read for positive parameters (see the module documentation).
pub(crate) fn read_positive(p: Expr, positive: &dyn Fn(Symbol) -> bool) -> Reading {
    let (numerator, denominator) = p.normal().numer_denom();
    // A denominator of one sign folds into the numerator; one of unknown sign multiplies it
    // (the product has the quotient's sign where the quotient is defined).
    let polynomial = match sum_sign(denominator, positive) {
        Sign::Positive => numerator,
        Sign::Negative => -numerator,
        _ => (numerator * denominator).normal(),
    };
    if polynomial.is_zero() {
        return Reading::Never;
    }
    let (factor, rest) = polynomial.common_factor();
    let (factor_sign, rest) = match sum_sign(factor, positive) {
        s @ (Sign::Positive | Sign::NonNegative | Sign::Negative | Sign::NonPositive) => (s, rest),
        _ => (Sign::Positive, polynomial),
    };
    // A factor that is only non-negative (`ω²`) vanishes at one value, where the condition
    // fails; the rest is what decides elsewhere, and reads as the course writes it.
    let rest = if matches!(factor_sign, Sign::Negative | Sign::NonPositive) {
        -rest
    } else {
        rest
    };
    match sum_sign(rest, positive) {
        Sign::Positive | Sign::NonNegative => Reading::Always,
        Sign::Negative | Sign::NonPositive | Sign::Zero => Reading::Never,
        Sign::Unknown => Reading::When(split(rest)),
    }
}

/// The conditions `P_k > 0` all together, read for positive parameters: `None` when one never
/// holds, otherwise the inequalities that remain (empty: they always hold), none implied by
/// another.
pub(crate) fn read_all(
    conditions: &[Expr],
    positive: &dyn Fn(Symbol) -> bool,
) -> Option<Vec<Inequality>> {
    let mut kept: Vec<Inequality> = Vec::new();
    for p in conditions {
        match read_positive(*p, positive) {
            Reading::Always => {}
            Reading::Never => return None,
            Reading::When(i) => kept.push(i),
        }
    }
    let differences: Vec<Expr> = kept.iter().map(Inequality::difference).collect();
    let implied = |i: usize| {
        (0..kept.len()).any(|j| {
            let gap = (differences[i] - differences[j]).normal();
            // Equal conditions: the later one is the one left out.
            j != i && sign(gap, positive).never_negative() && (j < i || !gap.is_zero())
        })
    };
    let keep: Vec<bool> = (0..kept.len()).map(|i| !implied(i)).collect();
    Some(
        kept.into_iter()
            .zip(keep)
            .filter_map(|(k, keep)| keep.then_some(k))
            .collect(),
    )
}

/// The symbols of `e` (each once, in the order met).
pub(crate) fn symbols(e: Expr) -> Vec<Symbol> {
    let mut out = Vec::new();
    collect_symbols(e, &mut out);
    out
}

fn collect_symbols(e: Expr, out: &mut Vec<Symbol>) {
    match e.node() {
        Node::Symbol(s) => {
            if !out.contains(s) {
                out.push(*s);
            }
        }
        _ => {
            for c in e.children() {
                collect_symbols(*c, out);
            }
        }
    }
}

/// The terms of a polynomial (its normal form's numerator expanded).
fn terms(e: Expr) -> Vec<Expr> {
    let expanded = e.expand();
    match expanded.node() {
        Node::Add(terms) => terms.to_vec(),
        _ => vec![expanded],
    }
}

/// The sign of a sum from the signs of its terms.
fn sum_sign(e: Expr, positive: &dyn Fn(Symbol) -> bool) -> Sign {
    terms(e)
        .into_iter()
        .map(|t| term_sign(t, positive))
        .fold(Sign::Zero, Sign::plus)
}

/// The sign of one term: a number times powers of symbols (anything else is unknown).
fn term_sign(e: Expr, positive: &dyn Fn(Symbol) -> bool) -> Sign {
    match e.node() {
        Node::Number(n) => {
            let x = n.to_f64();
            if x > 0.0 {
                Sign::Positive
            } else if x < 0.0 {
                Sign::Negative
            } else {
                Sign::Zero
            }
        }
        Node::Symbol(s) if positive(*s) => Sign::Positive,
        Node::Constant(_) => Sign::Positive,
        Node::Pow([base, exponent]) => {
            let even = exponent
                .as_number()
                .and_then(cas::Number::to_i64)
                .is_some_and(|k| k % 2 == 0);
            // A root of even order (`√x`, `x^(3/2)`) is the principal one: never negative
            // where it is real.
            let even_root = exponent
                .as_number()
                .and_then(|n| n.denom().to_i64())
                .is_some_and(|d| d % 2 == 0);
            match term_sign(*base, positive) {
                Sign::Positive => Sign::Positive,
                _ if even || even_root => Sign::NonNegative,
                _ => Sign::Unknown,
            }
        }
        Node::Mul(factors) => factors
            .iter()
            .map(|f| term_sign(*f, positive))
            .fold(Sign::Positive, Sign::times),
        _ => Sign::Unknown,
    }
}

/// A polynomial of mixed signs as its positive terms against its negative ones.
fn split(p: Expr) -> Inequality {
    let mut greater = Vec::new();
    let mut less = Vec::new();
    for t in terms(p) {
        if coefficient(t) < 0.0 {
            less.push(-t);
        } else {
            greater.push(t);
        }
    }
    Inequality {
        greater: Expr::add_all(greater).normal(),
        less: Expr::add_all(less).normal(),
    }
}

/// The numeric coefficient of a term.
fn coefficient(t: Expr) -> f64 {
    match t.node() {
        Node::Number(n) => n.to_f64(),
        Node::Mul(factors) => factors
            .iter()
            .filter_map(|f| f.as_number().map(cas::Number::to_f64))
            .product(),
        _ => 1.0,
    }
}

/// The highest power of a single symbol in `e`.
fn highest_power(e: Expr) -> i64 {
    match e.node() {
        Node::Symbol(_) => 1,
        Node::Pow([base, exponent]) if base.as_symbol().is_some() => exponent
            .as_number()
            .and_then(cas::Number::to_i64)
            .unwrap_or(1),
        _ => e
            .children()
            .iter()
            .map(|c| highest_power(*c))
            .max()
            .unwrap_or(0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn positive_but(names: &'static [&'static str]) -> impl Fn(Symbol) -> bool {
        move |s: Symbol| !names.contains(&s.name())
    }

    #[test]
    fn a_positive_factor_is_dropped_and_the_speed_comes_first() {
        let (m, a, g, w) = (
            Expr::symbol("m"),
            Expr::symbol("a"),
            Expr::symbol("g"),
            Expr::symbol("Omega"),
        );
        let p = m * (2 * a * g - w.powi(2));
        let Reading::When(i) = read_positive(p, &positive_but(&[])) else {
            panic!("not a condition")
        };
        let (left, relation, right) = i.reading_order();
        assert!(
            left.equals(w.powi(2)) && relation == "<",
            "{left} {relation} {right}"
        );
        assert!(right.equals(2 * a * g));
    }

    #[test]
    fn one_signed_polynomials_hold_always_or_never() {
        let (m, g, w) = (Expr::symbol("m"), Expr::symbol("g"), Expr::symbol("w"));
        let free = positive_but(&["w"]);
        assert_eq!(read_positive(m * g + w.powi(2), &free), Reading::Always);
        assert_eq!(read_positive(-(m * g) - w.powi(2), &free), Reading::Never);
        // `w` has no known sign, so `w m` decides nothing.
        assert!(matches!(read_positive(w * m - g, &free), Reading::When(_)));
    }

    #[test]
    fn a_square_root_is_never_negative() {
        let (m, c) = (Expr::symbol("m"), Expr::symbol("C"));
        let root = (m.powi(2) - c.powi(2)).sqrt();
        let free = positive_but(&[]);
        assert_eq!(read_positive(m * root, &free), Reading::Always);
        assert_eq!(read_positive(-(m * root), &free), Reading::Never);
    }

    #[test]
    fn an_implied_condition_is_left_out() {
        let (c, w, p) = (Expr::symbol("C"), Expr::symbol("w"), Expr::symbol("p"));
        let s = c.powi(2) * w.powi(2);
        let weak = s - 2 * p;
        let strong = s * (s - 4 * p);
        let kept = read_all(&[weak, strong, p.powi(2)], &positive_but(&["w"])).unwrap();
        assert_eq!(kept.len(), 1);
        assert!(kept[0].difference().equals(s - 4 * p));
    }
}
