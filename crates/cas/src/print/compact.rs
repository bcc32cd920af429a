//! The compact form for people: a value-preserving regrouping of an expression, bottom-up.
//!
//! In every sum, three passes run in turn:
//! 1. *trig folding* — a pair of terms `K cos a cos b ± K sin a sin b` becomes `K cos(a ∓ b)`,
//!    and `K sin a cos b ± K cos a sin b` becomes `K sin(a ± b)` (the normal form expands these);
//! 2. *collecting* — terms with the same time-dependent part share it:
//!    `m_A ẍ + m_B ẍ` → `(m_A + m_B) ẍ`;
//! 3. *common factors* — a numeric content and powers common to every term are pulled out:
//!    `m_B ℓ² θ̈ + m_B g ℓ sin θ` → `m_B ℓ (ℓ θ̈ + g sin θ)`.
//!
//! Each pass is an identity, so the result has the value of the input (the tests check this by
//! evaluation). The constructors keep sums inside products, so the regrouping survives as a tree.

use std::sync::{Mutex, OnceLock};

use rustc_hash::FxHashMap;

use crate::expr::{split_coefficient, split_power, Expr, Node};
use crate::number::Number;
use crate::Func;

use super::order::has_time;

pub(super) fn compact(e: Expr) -> Expr {
    // Reports print each expression in several dialects (Unicode and LaTeX), and the compact form
    // of a large equation is most of the printing time: it is computed once per process.
    if let Some(&c) = memo().lock().unwrap_or_else(|p| p.into_inner()).get(&e) {
        return c;
    }
    let c = Compactor {
        memo: FxHashMap::default(),
    }
    .run(e);
    memo()
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .insert(e, c);
    c
}

/// The compact forms computed so far (expressions are hash-consed and never freed, so this keeps
/// only two handles per entry).
fn memo() -> &'static Mutex<FxHashMap<Expr, Expr>> {
    static MEMO: OnceLock<Mutex<FxHashMap<Expr, Expr>>> = OnceLock::new();
    MEMO.get_or_init(|| Mutex::new(FxHashMap::default()))
}

struct Compactor {
    // Shared sub-expressions are regrouped once.
    memo: FxHashMap<Expr, Expr>,
}

impl Compactor {
    fn run(&mut self, e: Expr) -> Expr {
        if let Some(&r) = self.memo.get(&e) {
            return r;
        }
        let r = match e.node() {
            Node::Number(_) | Node::Symbol(_) | Node::Constant(_) => e,
            Node::Add(terms) => {
                let terms: Vec<Expr> = terms.iter().map(|t| self.run(*t)).collect();
                regroup_sum(terms)
            }
            Node::Mul(f) => {
                let factors: Vec<Expr> = f.iter().map(|x| self.run(*x)).collect();
                Expr::mul_all(balance_signs(factors))
            }
            Node::Pow([b, x]) => self.run(*b).pow(self.run(*x)),
            Node::Func(f, args) => {
                let args: Vec<Expr> = args.iter().map(|a| self.run(*a)).collect();
                even_odd(*f, args)
            }
        };
        self.memo.insert(e, r);
        r
    }
}

/// The sign normaliser of a product, so that a minus is written once: a sum factor whose terms
/// are all negative gives its sign to the product (`(−k1 − 2 k2) x` → `−(k1 + 2 k2) x`,
/// `/(−2 m − 3 M)` → `−…/(2 m + 3 M)`); then, if the product is negative, one sum factor that
/// would print with a leading minus takes the sign back (`−(−a + b)` → `(a − b)`).
fn balance_signs(factors: Vec<Expr>) -> Vec<Expr> {
    let mut negative = false;
    // A compacted factor may itself be a product (`m g (…)`): its factors are this product's.
    let mut out: Vec<Expr> = factors
        .into_iter()
        .flat_map(|f| match f.node() {
            Node::Mul(inner) => inner.to_vec(),
            _ => vec![f],
        })
        .map(|f| match signed_sum(f) {
            Some((terms, odd)) if terms.iter().all(|t| split_coefficient(*t).0.is_negative()) => {
                negative ^= odd;
                negate_sum(f, &terms)
            }
            _ => f,
        })
        .collect();
    let coefficient_negative = out
        .iter()
        .filter_map(|f| f.as_number())
        .fold(false, |n, c| n ^ c.is_negative());
    if negative ^ coefficient_negative {
        let leading = out
            .iter()
            .position(|f| signed_sum(*f).is_some_and(|(terms, odd)| odd && leads_negative(&terms)));
        if let Some(i) = leading {
            let terms = signed_sum(out[i]).map(|(t, _)| t).unwrap_or_default();
            out[i] = negate_sum(out[i], &terms);
            negative = !negative;
        }
    }
    if negative {
        out.push(Expr::number(Number::int(-1)));
    }
    out
}

/// A factor that is a sum or an integer power of one: its terms, and whether the power is odd.
fn signed_sum(f: Expr) -> Option<(Vec<Expr>, bool)> {
    let (base, exp) = split_power(f);
    let k = exp.as_number().and_then(Number::to_i64)?;
    match base.node() {
        Node::Add(terms) => Some((terms.to_vec(), k % 2 != 0)),
        _ => None,
    }
}

/// The factor `f` (a sum `terms` or a power of it) with the sum negated.
fn negate_sum(f: Expr, terms: &[Expr]) -> Expr {
    let (_, exp) = split_power(f);
    let negated = Expr::add_all(terms.iter().map(|t| -*t).collect::<Vec<_>>());
    if exp.is_literal_one() {
        negated
    } else {
        negated.pow(exp)
    }
}

/// Whether a sum, in the order it is printed, begins with a negative term.
fn leads_negative(terms: &[Expr]) -> bool {
    let mut sorted = terms.to_vec();
    super::order::sort_terms(&mut sorted);
    sorted
        .first()
        .is_some_and(|t| split_coefficient(*t).0.is_negative())
}

/// `cos(−u) = cos u`, `sin(−u) = −sin u`, `tan(−u) = −tan u`: an angle is printed with a
/// positive leading coefficient, as people write it.
fn even_odd(f: Func, args: Vec<Expr>) -> Expr {
    if let (Func::Sin | Func::Cos | Func::Tan, [angle]) = (f, args.as_slice()) {
        let (c, _) = split_coefficient(*angle);
        if c.is_negative() {
            let positive = -*angle;
            return match f {
                Func::Cos => positive.cos(),
                _ => -Expr::func(f, vec![positive]),
            };
        }
    }
    Expr::func(f, args)
}

fn regroup_sum(terms: Vec<Expr>) -> Expr {
    let mut terms = prefer_sine_squares(terms);
    fold_trig(&mut terms);
    let terms = collect_by_time_part(terms);
    pull_common_factor(terms)
}

fn factors_of(e: Expr) -> Vec<Expr> {
    match e.node() {
        Node::Mul(f) => f.to_vec(),
        _ if e.is_literal_one() => Vec::new(),
        _ => vec![e],
    }
}

/// `sin`/`cos` of one argument, to the first power.
fn trig(e: Expr) -> Option<(Func, Expr)> {
    match e.node() {
        Node::Func(f @ (Func::Sin | Func::Cos), args) => Some((*f, args[0])),
        _ => None,
    }
}

/// Rewrites even powers of `cos a` with `cos² a = 1 − sin² a` when that leaves the sum with
/// fewer terms: the normal form keeps only cosines, so the seed's `−sin² α` arrives as
/// `cos² α − 1`.
fn prefer_sine_squares(mut terms: Vec<Expr>) -> Vec<Expr> {
    let mut angles: Vec<Expr> = Vec::new();
    for t in &terms {
        for f in factors_of(split_coefficient(*t).1) {
            let (base, exp) = split_power(f);
            if let (Some((Func::Cos, a)), Some(k)) = (trig(base), exp.as_number()) {
                if k.to_i64().is_some_and(|k| k >= 2) && !angles.contains(&a) {
                    angles.push(a);
                }
            }
        }
    }
    for angle in angles {
        let cos = angle.cos();
        // Most rewrites do not pay: count first, build only the ones that do.
        if rewritten_len(&terms, cos, angle.sin()) >= terms.len() {
            continue;
        }
        let sin_squared = angle.sin().powi(2);
        let mut rewritten = Vec::with_capacity(terms.len());
        for t in &terms {
            let mut power = 0;
            let mut rest = Vec::new();
            for f in factors_of(*t) {
                let (base, exp) = split_power(f);
                match exp.as_number().and_then(Number::to_i64) {
                    Some(k) if base == cos && k > 0 => power = k,
                    _ => rest.push(f),
                }
            }
            if power < 2 {
                // Nothing to rewrite: the term stays as it is (rebuilding it costs a product).
                rewritten.push(*t);
                continue;
            }
            let rest = Expr::mul_all(rest);
            // cos^p = cos^r (1 − sin²)^j with p = 2j + r.
            let (j, r) = (power / 2, power % 2);
            for (i, signed) in (0..).zip(alternating_binomials(j)) {
                rewritten.push(Expr::number(signed) * rest * cos.powi(r) * sin_squared.powi(i));
            }
        }
        let sum = Expr::add_all(rewritten);
        let new_terms = match sum.node() {
            Node::Add(t) => t.to_vec(),
            _ if sum.is_literal_zero() => Vec::new(),
            _ => vec![sum],
        };
        if new_terms.len() < terms.len() {
            terms = new_terms;
        }
    }
    terms
}

/// `(−1)^i C(j, i)` for `i = 0..=j`: the coefficients of `(1 − sin²)^j`. Exact: C(j, i)
/// outgrows i64 from j = 67 on, and a wrapped coefficient once printed a `cos 150x` potential
/// as 6e45 where its value is 0.47.
fn alternating_binomials(j: i64) -> Vec<Number> {
    let mut binomial = Number::ONE;
    let mut out = Vec::new();
    for i in 0..=j {
        out.push(if i % 2 == 0 {
            binomial.clone()
        } else {
            binomial.neg()
        });
        binomial = binomial
            .mul(&Number::int(j - i))
            .div(&Number::int(i + 1))
            .unwrap_or(Number::ZERO);
    }
    out
}

/// The number of terms of the sum after `cos² a = 1 − sin² a` (`cos`, `sin` of one angle),
/// counted without building it: a term is keyed by its factors other than its coefficient and
/// its powers of `cos a` and `sin a`, with those two powers; terms with one key are like terms.
fn rewritten_len(terms: &[Expr], cos: Expr, sin: Expr) -> usize {
    let mut sums: FxHashMap<(Vec<Expr>, i64, i64), Number> = FxHashMap::default();
    let mut add = |key, c: Number| {
        let sum = sums.entry(key).or_insert(Number::ZERO);
        *sum = sum.add(&c);
    };
    for t in terms {
        let (c, rest) = split_coefficient(*t);
        let (mut p, mut s) = (0, 0);
        let mut others = Vec::new();
        for f in factors_of(rest) {
            let (base, exp) = split_power(f);
            match exp.as_number().and_then(Number::to_i64) {
                Some(k) if base == cos && k > 0 => p = k,
                Some(k) if base == sin && k > 0 => s = k,
                _ => others.push(f),
            }
        }
        if p < 2 {
            add((others, p, s), c);
            continue;
        }
        let (j, r) = (p / 2, p % 2);
        for (i, signed) in (0..).zip(alternating_binomials(j)) {
            add((others.clone(), r, s + 2 * i), c.mul(&signed));
        }
    }
    sums.values().filter(|c| !c.is_zero()).count()
}

/// Folds pairs of terms that are an expanded `cos(a ± b)` or `sin(a ± b)`, until none is left.
///
/// Each pass indexes the terms once and folds every pair it finds (a term changed in this pass
/// is neither folded again nor used as a partner until the next pass), so a sum of `T` terms
/// costs `O(T)` per pass rather than `O(T)` per fold.
fn fold_trig(terms: &mut Vec<Expr>) {
    // Each pass that changes something removes a term, so this terminates; the bound is a
    // second guarantee.
    for _ in 0..terms.len() {
        if !fold_pass(terms) {
            return;
        }
    }
}

fn fold_pass(terms: &mut Vec<Expr>) -> bool {
    let split: Vec<(Number, Vec<Expr>)> =
        terms.iter().map(|t| coefficient_and_factors(*t)).collect();
    let index = TermIndex::new(&split);
    // `None`: removed; `Some(true)`: changed in this pass.
    let mut state: Vec<Option<bool>> = vec![Some(false); terms.len()];
    let mut changed = false;
    for i in 0..terms.len() {
        if state[i] != Some(false) {
            continue;
        }
        if let Some((j, new)) = fold_partner(i, &split, &index, &state) {
            terms[i] = new;
            state[i] = Some(true);
            state[j] = None;
            changed = true;
        }
    }
    if changed {
        let mut k = 0;
        terms.retain(|_| {
            k += 1;
            state[k - 1].is_some()
        });
    }
    changed
}

/// A term's numeric coefficient and its other factors (those of `split_coefficient`'s rest),
/// read off the term without building the rest.
fn coefficient_and_factors(t: Expr) -> (Number, Vec<Expr>) {
    match t.node() {
        Node::Number(n) => (n.clone(), Vec::new()),
        Node::Mul(f) => match f[0].node() {
            Node::Number(n) => (n.clone(), f[1..].to_vec()),
            _ => (Number::ONE, f.to_vec()),
        },
        _ => (Number::ONE, vec![t]),
    }
}

/// The partner of term `i` in an expanded `cos(a ± b)` or `sin(a ± b)`, and the folded term.
fn fold_partner(
    i: usize,
    split: &[(Number, Vec<Expr>)],
    index: &TermIndex,
    state: &[Option<bool>],
) -> Option<(usize, Expr)> {
    let (ci, factors) = &split[i];
    for p in 0..factors.len() {
        let Some((fp, a)) = trig(factors[p]) else {
            continue;
        };
        for q in 0..factors.len() {
            let Some((fq, b)) = trig(factors[q]) else {
                continue;
            };
            if p == q || a == b {
                continue;
            }
            // cos a cos b pairs with sin a sin b; sin a cos b pairs with cos a sin b.
            let (pa, pb) = match (fp, fq) {
                (Func::Cos, Func::Cos) if p < q => (a.sin(), b.sin()),
                (Func::Sin, Func::Cos) => (a.cos(), b.sin()),
                _ => continue,
            };
            let Some(j) = index.partner(i, factors, [p, q], [pa, pb]) else {
                continue;
            };
            if j == i || state[j] != Some(false) {
                continue;
            }
            let others = without(factors, [p, q]);
            let cj = &split[j].0;
            let same = cj == ci;
            if !same && *cj != ci.neg() {
                continue;
            }
            let folded = match (fp, same) {
                // cos a cos b + sin a sin b = cos(a − b); with − it is cos(a + b).
                (Func::Cos, true) => (a - b).cos(),
                (Func::Cos, false) => (a + b).cos(),
                // sin a cos b + cos a sin b = sin(a + b); with − it is sin(a − b).
                (_, true) => (a + b).sin(),
                (_, false) => (a - b).sin(),
            };
            // sin is odd: write `−K sin(b − a)` as `K sin(a − b)` with the arguments in
            // their canonical order, as people write `sin(θ1 − θ2)`.
            let (coefficient, folded) = match (fp, same) {
                (Func::Sin, false) if a.cmp_structure(b).is_gt() => (ci.neg(), (b - a).sin()),
                _ => (ci.clone(), folded),
            };
            let new = Expr::mul_all(
                [Expr::number(coefficient)]
                    .into_iter()
                    .chain(others)
                    .chain([folded]),
            );
            return Some((j, new));
        }
    }
    None
}

/// The terms of a sum by the set of their factors (coefficients aside), to find the partner of
/// a trigonometric fold without building it.
///
/// A canonical product is determined by the set of its factors, so a partner is found by that
/// set. Each set is keyed by the wrapping sum of a hash of each factor's handle: the key of a
/// partner is the term's key with two factors' hashes taken out and two put in, so looking up
/// the partner of each pair of factors costs a few additions, and a term's factors are compared
/// only on a hit. (Building each partner as a product, as this once did, was most of the compact
/// form's cost on a large result.)
struct TermIndex {
    by_key: FxHashMap<u64, Vec<usize>>,
    /// Each term's key.
    keys: Vec<u64>,
    /// Each term's factors in index order, for the comparison on a hit.
    sorted: Vec<Vec<Expr>>,
}

impl TermIndex {
    fn new(split: &[(Number, Vec<Expr>)]) -> TermIndex {
        let mut by_key: FxHashMap<u64, Vec<usize>> = FxHashMap::default();
        let mut keys = Vec::with_capacity(split.len());
        let mut sorted = Vec::with_capacity(split.len());
        for (i, (_, factors)) in split.iter().enumerate() {
            let key = set_key(factors);
            by_key.entry(key).or_default().push(i);
            keys.push(key);
            sorted.push(in_index_order(factors.clone()));
        }
        TermIndex {
            by_key,
            keys,
            sorted,
        }
    }

    /// The term whose factors are those of term `i` (`factors`) without the two at `removed`
    /// and with the two functions `added` (merged into powers as `Expr::mul_all` merges them:
    /// `sin a · sin² a` = `sin³ a`). Of several terms with that set of factors, the last, as a
    /// map from the product to its term would give.
    fn partner(
        &self,
        i: usize,
        factors: &[Expr],
        removed: [usize; 2],
        added: [Expr; 2],
    ) -> Option<usize> {
        let mut key = removed.iter().fold(self.keys[i], |key, &k| {
            key.wrapping_sub(mix(factors[k].index()))
        });
        for f in added {
            let kept = |k: usize| !removed.contains(&k);
            let same_base = (0..factors.len()).find(|&k| kept(k) && split_power(factors[k]).0 == f);
            let plain = matches!(f.node(), Node::Func(..));
            match (plain, same_base) {
                (true, None) => key = key.wrapping_add(mix(f.index())),
                (true, Some(k)) => {
                    key = key.wrapping_sub(mix(factors[k].index()));
                    let Some(merged) = merged_power(f, factors[k]) else {
                        return self.partner_built(factors, removed, added);
                    };
                    if !merged.is_literal_one() {
                        key = key.wrapping_add(mix(merged.index()));
                    }
                }
                (false, _) => return self.partner_built(factors, removed, added),
            }
        }
        // Nearly every lookup misses: the partner's factors are listed only on a hit.
        let candidates = self.by_key.get(&key)?;
        let Some(partner) = merged_with(&without(factors, removed), added) else {
            return self.partner_built(factors, removed, added);
        };
        self.find_among(candidates, partner)
    }

    /// The last candidate whose factors are `partner`'s (in index order).
    fn find_among(&self, candidates: &[usize], partner: Vec<Expr>) -> Option<usize> {
        let partner = in_index_order(partner);
        candidates
            .iter()
            .rev()
            .copied()
            .find(|&j| self.sorted[j] == partner)
    }

    /// [`TermIndex::partner`] when an added factor is not a plain function (`sin` of a negative
    /// angle is `−sin`): the partner is built as a product.
    fn partner_built(
        &self,
        factors: &[Expr],
        removed: [usize; 2],
        added: [Expr; 2],
    ) -> Option<usize> {
        let others = without(factors, removed);
        let partner = factors_of(Expr::mul_all(others.into_iter().chain(added)));
        let candidates = self.by_key.get(&set_key(&partner))?;
        self.find_among(candidates, partner)
    }
}

/// `factors` without the two at `removed`, in their order.
fn without(factors: &[Expr], removed: [usize; 2]) -> Vec<Expr> {
    factors
        .iter()
        .enumerate()
        .filter(|(k, _)| !removed.contains(k))
        .map(|(_, f)| *f)
        .collect()
}

/// `f · factor` for a factor that is a power of `f`, as `Expr::mul_all` forms it; `None` when
/// the power is not a number.
fn merged_power(f: Expr, factor: Expr) -> Option<Expr> {
    let power = split_power(factor).1.as_number()?.add(&Number::ONE);
    Some(f.pow(Expr::number(power)))
}

/// The factors of the product of `others` (the factors of a canonical product) and the two
/// functions `added`, merged as `Expr::mul_all` merges them; `None` when a power is not a
/// number.
fn merged_with(others: &[Expr], added: [Expr; 2]) -> Option<Vec<Expr>> {
    let mut factors = others.to_vec();
    for f in added {
        match factors.iter().position(|g| split_power(*g).0 == f) {
            None => factors.push(f),
            Some(k) => {
                let merged = merged_power(f, factors[k])?;
                if merged.is_literal_one() {
                    factors.swap_remove(k);
                } else {
                    factors[k] = merged;
                }
            }
        }
    }
    Some(factors)
}

/// A set of factors in the order of their handles (a canonical product has each factor once).
fn in_index_order(mut factors: Vec<Expr>) -> Vec<Expr> {
    factors.sort_unstable_by_key(|f| f.index());
    factors
}

/// The key of a set of factors: the wrapping sum of a mixed hash of each handle, independent of
/// their order.
fn set_key(factors: &[Expr]) -> u64 {
    factors
        .iter()
        .fold(0u64, |key, f| key.wrapping_add(mix(f.index())))
}

/// The SplitMix64 finaliser: spreads a handle over 64 bits, so that sums of distinct handles'
/// hashes rarely agree (a hit is checked anyway).
fn mix(index: u32) -> u64 {
    let mut z = u64::from(index).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Collects terms that share their time-dependent factors: `m_A ẍ + m_B ẍ` → `(m_A + m_B) ẍ`.
///
/// Grouped by the list of time-dependent factors (canonically ordered, so equal parts give
/// equal lists); a term alone in its group is kept as it is, without rebuilding it.
fn collect_by_time_part(terms: Vec<Expr>) -> Vec<Expr> {
    let mut groups: Vec<(Vec<Expr>, Vec<Expr>)> = Vec::new();
    let mut slot: FxHashMap<Vec<Expr>, usize> = FxHashMap::default();
    for t in terms {
        let dynamic: Vec<Expr> = factors_of(split_coefficient(t).1)
            .into_iter()
            .filter(|f| has_time(*f))
            .collect();
        if dynamic.is_empty() {
            groups.push((dynamic, vec![t]));
            continue;
        }
        match slot.get(&dynamic) {
            Some(&k) => groups[k].1.push(t),
            None => {
                slot.insert(dynamic.clone(), groups.len());
                groups.push((dynamic, vec![t]));
            }
        }
    }
    groups
        .into_iter()
        .map(|(dynamic, members)| {
            if members.len() == 1 {
                return members[0];
            }
            let parts: Vec<Expr> = members
                .iter()
                .map(|t| {
                    let (c, rest) = split_coefficient(*t);
                    let parameters = factors_of(rest).into_iter().filter(|f| !has_time(*f));
                    Expr::mul_all([Expr::number(c)].into_iter().chain(parameters))
                })
                .collect();
            Expr::mul_all(balance_signs(vec![
                regroup_sum(parts),
                Expr::mul_all(dynamic),
            ]))
        })
        .collect()
}

/// Pulls the numeric content and the powers common to every term out of a sum.
fn pull_common_factor(terms: Vec<Expr>) -> Expr {
    if terms.len() < 2 {
        return Expr::add_all(terms);
    }
    let split: Vec<(Number, Vec<Expr>)> = terms
        .iter()
        .map(|t| {
            let (c, rest) = split_coefficient(*t);
            (c, factors_of(rest))
        })
        .collect();

    // The numeric content: the gcd of exact coefficients, negative when every term is.
    // Decimals (`9.81 x + 0.001`) read best as written: pulling `0.001` out of them would not.
    let exact = split
        .iter()
        .all(|(c, _)| !c.is_float() && c.to_decimal().is_none());
    let mut content = Number::ONE;
    if exact {
        content = split
            .iter()
            .skip(1)
            .fold(split[0].0.abs(), |g, (c, _)| g.gcd(c));
        if content.is_zero() {
            content = Number::ONE;
        }
    }

    // Powers common to every term, with exact exponents of one sign: the smallest in size.
    let mut common: Vec<(Expr, Number)> = Vec::new();
    for f in &split[0].1 {
        let (base, exp) = split_power(*f);
        let Some(e0) = exp.as_number().filter(|n| !n.is_float()) else {
            continue;
        };
        let mut best = e0.clone();
        let ok = split[1..].iter().all(|(_, fs)| {
            fs.iter().any(|g| {
                let (b, x) = split_power(*g);
                match x.as_number() {
                    Some(n) if b == base && !n.is_float() && n.signum() == e0.signum() => {
                        if n.abs().total_cmp(&best.abs()).is_lt() {
                            best = n.clone();
                        }
                        true
                    }
                    _ => false,
                }
            })
        });
        if ok {
            common.push((base, best));
        }
    }
    let all_negative = split.iter().all(|(c, _)| c.is_negative());
    if content.is_one() && common.is_empty() {
        return Expr::add_all(terms);
    }
    if all_negative {
        content = content.neg();
    }
    let divisor: Vec<Expr> = std::iter::once(Expr::number(content.clone()))
        .chain(common.iter().map(|(b, e)| b.pow(Expr::number(e.clone()))))
        .collect();
    let Some(inverse) = content.recip() else {
        return Expr::add_all(terms);
    };
    let inner: Vec<Expr> = terms
        .iter()
        .map(|t| {
            Expr::mul_all(
                [*t, Expr::number(inverse.clone())]
                    .into_iter()
                    .chain(common.iter().map(|(b, e)| b.pow(Expr::number(e.neg())))),
            )
        })
        .collect();
    // Without the common factor, `cos² α` may now be worth writing as `1 − sin² α`.
    let before = inner.len();
    let inner = prefer_sine_squares(inner);
    let inner = if inner.len() < before {
        regroup_sum(inner)
    } else {
        Expr::add_all(inner)
    };
    Expr::mul_all(balance_signs(divisor.into_iter().chain([inner]).collect()))
}
