//! Presentation for people, beyond the compact form: how the course writes a result whose
//! normal form is one big fraction, and with the names a model gave to its constants.
//!
//! The normal form of `Ĩ θ̈ + m g b sin θ` with `b = d cos² α`, `R = d sin α` is a single
//! fraction over `sin² α` with the constants expanded; the course writes it term by term,
//! each coefficient as short as it can be, and in the model's own names. Two value-preserving
//! rewrites do that:
//!
//! * [`spread_denominator`] — when the denominator does not depend on time, divide it into the
//!   numerator group by group: by the time-dependent part of each term (`θ̈`, `θ̇²`, `sin θ`),
//!   and, when that prints shorter, also by the parameters each term carries
//!   (`I_y cos² α + m d² cos⁴ α + I_x cos⁴ α/sin² α` rather than one fraction). The shortest
//!   printed candidate wins, the original included.
//! * [`fold_names`] — a product that contains the value of a named constant (a monomial such as
//!   `d cos² α`) is written with the name (`b`), as often as it divides the product.
//!
//! Both return trees for the printers (not normal forms); the printers' compact pass still runs.

use rustc_hash::FxHashMap;

use crate::expr::{split_coefficient, split_power, Expr, Node};
use crate::number::Number;

use super::order::has_time;

/// Above this many numerator terms the candidates are not tried (printing them all to compare
/// would cost more than it is worth on the n-link pendulum's equations).
const SPREAD_MAX_TERMS: usize = 400;

/// `e` with a time-independent denominator divided into its numerator group by group, if that
/// prints shorter (see the module documentation); otherwise `e` itself.
#[must_use]
pub fn spread_denominator(e: Expr) -> Expr {
    spread_and_fold(e, &[])
}

/// `e` written with the named constants `names` (pairs of the constant's symbol and its value
/// in the symbols `e` uses): every product containing a value's factors shows the name instead.
/// Values that are a number or one symbol times a number are never folded (every `r` shown as
/// `R/2` would help nobody).
#[must_use]
pub fn fold_names(e: Expr, names: &[(Expr, Expr)]) -> Expr {
    let folds = Folds::new(names);
    if folds.monomials.is_empty() && folds.sums.is_empty() {
        return e;
    }
    folds.apply(e, &mut FxHashMap::default())
}

/// [`spread_denominator`] and [`fold_names`] together, the shortest printed candidate after
/// folding: what the reports show.
#[must_use]
pub fn spread_and_fold(e: Expr, names: &[(Expr, Expr)]) -> Expr {
    let folds = Folds::new(names);
    let mut memo = FxHashMap::default();
    let mut fold = |x: Expr| {
        if folds.monomials.is_empty() && folds.sums.is_empty() {
            x
        } else {
            folds.apply(x, &mut memo)
        }
    };
    let mut best = fold(e);
    let Some(candidates) = spread_candidates(e) else {
        return best;
    };
    let mut best_len = printed_len(best);
    for c in candidates {
        let c = fold(c);
        let len = printed_len(c);
        if len < best_len {
            best = c;
            best_len = len;
        }
    }
    best
}

fn printed_len(e: Expr) -> usize {
    super::to_unicode(e).chars().count()
}

/// The two spread forms of `e` (by time-dependent part; by time-dependent part and
/// parameters), or `None` when the denominator is one or depends on time.
fn spread_candidates(e: Expr) -> Option<[Expr; 2]> {
    let (den, num) = e
        .normal()
        .denom_then_numer(|den| !den.is_literal_one() && !has_time(den));
    let num = num?;
    let terms: Vec<Expr> = match num.node() {
        Node::Add(t) => t.to_vec(),
        _ => vec![num],
    };
    if terms.len() > SPREAD_MAX_TERMS {
        return None;
    }
    let by_time = spread(&terms, den, false);
    let by_parameters = spread(&terms, den, true);
    Some([by_time, by_parameters])
}

/// `Σ terms / den`, the terms grouped by their time-dependent part (and, with `by_parameters`,
/// by the plain symbols they carry), each group's coefficient divided by `den` on its own.
fn spread(terms: &[Expr], den: Expr, by_parameters: bool) -> Expr {
    let mut groups: Vec<(Expr, Expr, Vec<Expr>)> = Vec::new();
    let mut slot: FxHashMap<(Expr, Expr), usize> = FxHashMap::default();
    for &t in terms {
        let (c, rest) = split_coefficient(t);
        let mut dynamic = Vec::new();
        let mut symbols = Vec::new();
        let mut others = vec![Expr::number(c)];
        for f in factors_of(rest) {
            if has_time(f) {
                dynamic.push(f);
            } else if by_parameters && is_symbol_power(f) {
                symbols.push(f);
            } else {
                others.push(f);
            }
        }
        let key = (Expr::mul_all(dynamic), Expr::mul_all(symbols));
        let part = Expr::mul_all(others);
        match slot.get(&key) {
            Some(&k) => groups[k].2.push(part),
            None => {
                slot.insert(key, groups.len());
                groups.push((key.0, key.1, vec![part]));
            }
        }
    }
    Expr::add_all(groups.into_iter().map(|(dynamic, symbols, parts)| {
        let coefficient = (Expr::add_all(parts) * symbols / den).normal();
        Expr::mul_all([coefficient, dynamic])
    }))
}

fn factors_of(e: Expr) -> Vec<Expr> {
    match e.node() {
        Node::Mul(f) => f.to_vec(),
        _ if e.is_literal_one() => Vec::new(),
        _ => vec![e],
    }
}

/// A parameter or a power of one: the factors a course keeps outside a coefficient.
fn is_symbol_power(f: Expr) -> bool {
    let (base, _) = split_power(f);
    matches!(base.node(), Node::Symbol(_))
}

/// A constant whose value is a monomial: its name, the value's numeric coefficient and its
/// factors `(base, exponent)`.
struct MonomialConstant {
    name: Expr,
    coefficient: Number,
    factors: Vec<(Expr, Number)>,
}

/// The constants that can be folded, ready to match.
struct Folds {
    /// Monomial values, largest first.
    monomials: Vec<MonomialConstant>,
    /// Values that are sums, matched as whole sub-expressions.
    sums: FxHashMap<Expr, Expr>,
}

impl Folds {
    fn new(names: &[(Expr, Expr)]) -> Folds {
        let mut monomials = Vec::new();
        let mut sums = FxHashMap::default();
        for &(name, value) in names {
            let value = value.normal();
            if has_time(value) {
                continue;
            }
            match value.node() {
                Node::Number(_) | Node::Symbol(_) | Node::Constant(_) => {}
                Node::Add(_) => {
                    sums.insert(value, name);
                }
                _ => {
                    let (c, rest) = split_coefficient(value);
                    if c.is_float() || c.is_zero() {
                        continue;
                    }
                    let factors: Option<Vec<(Expr, Number)>> = factors_of(rest)
                        .into_iter()
                        .map(|f| {
                            let (base, exp) = split_power(f);
                            exp.as_number()
                                .filter(|x| !x.is_float() && !x.is_zero())
                                .map(|x| (base, x.clone()))
                        })
                        .collect();
                    let Some(factors) = factors else { continue };
                    // One plain symbol, perhaps scaled or powered, is an alias, not a fold.
                    if factors.len() == 1 && matches!(factors[0].0.node(), Node::Symbol(_)) {
                        continue;
                    }
                    monomials.push(MonomialConstant {
                        name,
                        coefficient: c,
                        factors,
                    });
                }
            }
        }
        monomials.sort_by_key(|m| {
            std::cmp::Reverse(
                m.factors
                    .iter()
                    .map(|(_, x)| x.abs().to_i64().unwrap_or(1))
                    .sum::<i64>(),
            )
        });
        Folds { monomials, sums }
    }

    fn apply(&self, e: Expr, memo: &mut FxHashMap<Expr, Expr>) -> Expr {
        if let Some(&r) = memo.get(&e) {
            return r;
        }
        if let Some(&name) = self.sums.get(&e) {
            return name;
        }
        let r = match e.node() {
            Node::Number(_) | Node::Symbol(_) | Node::Constant(_) => e,
            Node::Add(terms) => Expr::add_all(
                terms
                    .iter()
                    .map(|t| self.apply(*t, memo))
                    .collect::<Vec<_>>(),
            ),
            Node::Mul(f) => {
                let factors: Vec<Expr> = f.iter().map(|x| self.apply(*x, memo)).collect();
                self.fold_product(factors)
            }
            Node::Pow([b, x]) => {
                let b = self.apply(*b, memo);
                self.fold_product(vec![b.pow(*x)])
            }
            Node::Func(func, args) => {
                Expr::func(*func, args.iter().map(|a| self.apply(*a, memo)).collect())
            }
        };
        memo.insert(e, r);
        r
    }

    /// The product of `factors` with every monomial constant divided out as often as it goes.
    fn fold_product(&self, factors: Vec<Expr>) -> Expr {
        let mut coefficient = Number::ONE;
        let mut powers: Vec<(Expr, Number)> = Vec::new();
        let mut opaque: Vec<Expr> = Vec::new();
        for f in factors {
            if let Some(n) = f.as_number() {
                coefficient = coefficient.mul(n);
                continue;
            }
            let (base, exp) = split_power(f);
            match exp.as_number().filter(|x| !x.is_float()) {
                Some(x) => match powers.iter_mut().find(|(b, _)| *b == base) {
                    Some((_, y)) => *y = y.add(x),
                    None => powers.push((base, x.clone())),
                },
                None => opaque.push(f),
            }
        }
        let mut names: Vec<(Expr, i64)> = Vec::new();
        for constant in &self.monomials {
            let times = constant
                .factors
                .iter()
                .map(|(base, x)| {
                    powers
                        .iter()
                        .find(|(b, _)| b == base)
                        .map_or(0, |(_, y)| times_within(y, x))
                })
                .min()
                .unwrap_or(0);
            if times == 0 {
                continue;
            }
            for (base, x) in &constant.factors {
                if let Some((_, y)) = powers.iter_mut().find(|(b, _)| b == base) {
                    *y = y.sub(&x.mul(&Number::int(times)));
                }
            }
            // name^k = c^k · value^k, so the rest carries 1/c^k.
            let mut scale = Number::ONE;
            for _ in 0..times {
                scale = scale.mul(&constant.coefficient);
            }
            coefficient = coefficient.div(&scale).unwrap_or(coefficient);
            names.push((constant.name, times));
        }
        Expr::mul_all(
            std::iter::once(Expr::number(coefficient))
                .chain(
                    powers
                        .into_iter()
                        .filter(|(_, x)| !x.is_zero())
                        .map(|(b, x)| b.pow(Expr::number(x))),
                )
                .chain(names.into_iter().map(|(n, k)| n.powi(k)))
                .chain(opaque),
        )
    }
}

/// How many whole times the exponent `x` of a constant's factor fits in the exponent `y` of a
/// product's factor (same sign, not more than there is); 0 when it does not.
fn times_within(y: &Number, x: &Number) -> i64 {
    if y.is_negative() != x.is_negative() {
        return 0;
    }
    let (Some(y), Some(x)) = (y.abs().to_i64(), x.abs().to_i64()) else {
        return 0;
    };
    if x == 0 {
        0
    } else {
        y / x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::print::to_unicode;

    fn s(name: &str) -> Expr {
        Expr::symbol(name)
    }

    #[test]
    fn a_constant_monomial_is_written_with_its_name() {
        let (m, g, d, alpha) = (s("m"), s("g"), s("d"), s("alpha"));
        let th = Expr::coordinate("theta");
        let b = d * alpha.cos().powi(2);
        let e = (m * g * d * alpha.cos().powi(2) * th.sin()).normal();
        let folded = fold_names(e, &[(s("b"), b)]);
        assert_eq!(to_unicode(folded), "m b g sin θ");
        // Twice: m d² cos⁴ α = m b².
        let e2 = (m * d.powi(2) * alpha.cos().powi(4)).normal();
        assert_eq!(to_unicode(fold_names(e2, &[(s("b"), b)])), "m b²");
        // The value is kept: substituting the name back gives the original.
        let back = fold_names(e2, &[(s("b"), b)]).subs(&[(s("b"), b)]);
        assert!(back.equals(e2));
    }

    #[test]
    fn a_ratio_constant_folds_with_negative_powers() {
        let (r1, r2, i2) = (s("R1"), s("R2"), s("I2"));
        let e = (i2 * r1.powi(2) / r2.powi(2)).normal();
        let folded = fold_names(e, &[(s("r"), r1 / r2)]);
        assert_eq!(to_unicode(folded), "I2 r²");
    }

    #[test]
    fn aliases_and_numbers_are_not_folded() {
        let (m, l) = (s("m"), s("l"));
        let e = (m * l.powi(2)).normal();
        let names = [(s("L2"), l * 2), (s("c"), Expr::int(3)), (s("mm"), m)];
        assert_eq!(fold_names(e, &names), e);
    }

    #[test]
    fn a_parameter_denominator_is_spread_over_the_terms() {
        // (I1 R2² + I2 R1²) φ̈/R2² prints as (I1 + I2 R1²/R2²) φ̈.
        let (i1, i2, r1, r2) = (s("I1"), s("I2"), s("R1"), s("R2"));
        let phi = Expr::rate("phi1", 2);
        let e = ((i1 * r2.powi(2) + i2 * r1.powi(2)) * phi / r2.powi(2)).normal();
        let spread = spread_denominator(e);
        assert!(spread.equals(e));
        assert_eq!(to_unicode(spread), "(I1 + I2 R1²/R2²) φ̈1");
        let folded = spread_and_fold(e, &[(s("r"), r1 / r2)]);
        assert_eq!(to_unicode(folded), "(I1 + I2 r²) φ̈1");
    }

    #[test]
    fn the_rolling_cone_reads_as_the_course_writes_it() {
        // Ĩ θ̈ + m g b sin θ with Ĩ = m b² + I_x (b/R)² + I_z cos² α, all expanded in d and α.
        let (m, g, d, alpha, ix, iz) = (s("m"), s("g"), s("d"), s("alpha"), s("I_x"), s("I_z"));
        let th = Expr::coordinate("theta");
        let (b, r) = (d * alpha.cos().powi(2), d * alpha.sin());
        let inertia = m * b.powi(2) + ix * (b / r).powi(2) + iz * alpha.cos().powi(2);
        let e = (inertia * Expr::rate("theta", 2) + m * g * b * th.sin()).normal();
        let names = [(s("R"), r), (s("b"), b)];
        let shown = spread_and_fold(e, &names);
        assert!(shown.subs(&[(s("b"), b), (s("R"), r)]).equals(e));
        let text = to_unicode(shown);
        assert_eq!(
            text,
            "(m b² + I_z cos² α + I_x cos⁴ α/sin² α) θ̈ + m b g sin θ"
        );
        assert!(text.contains("m b²"), "{text}");
        assert!(
            !text.contains('/') || text.contains("cos⁴ α/sin² α"),
            "{text}"
        );
    }

    #[test]
    fn a_denominator_with_time_is_left_alone() {
        let th = Expr::coordinate("theta");
        let e = (s("a") / (th.cos() + 2)).normal();
        assert_eq!(spread_denominator(e), e);
    }
}
