//! Sorting a polynomial's terms into the monomial order by packed keys.
//!
//! [`Poly::from_terms`](crate::poly::Poly) sorts the terms that a derivative, a product or a
//! sum gathers, and that sort was a fifth of deriving a chain's equations: each comparison
//! walked two small vectors of `(atom, exponent)` pairs, and each move copied a 96-byte term,
//! about a dozen times per term. Here each monomial is packed once into a fixed-size key whose
//! plain lexicographic order is the monomial order ([`cmp_monomial`]), the keys are sorted,
//! and the terms are moved once into their places, equal monomials (equal keys) added up on
//! the way.

use crate::number::Number;
use crate::poly::{atom_index, cmp_monomial, Monomial};

/// The most factors a packed key holds (two per word).
const KEY_FACTORS: usize = 8;

/// A monomial packed so that comparing keys compares monomials: factor `i` is the 32-bit code
/// `(LIMIT − atom index) << 16 | exponent` in half a word, the first factor in the high half
/// of the first word, and an absent factor is `0`. Two monomials first differ at a factor
/// where either the atoms differ (the smaller atom, more significant, has the larger code)
/// or the exponents do (the larger is larger), or where one has run out of factors (the
/// shorter is smaller, as its `0` is below every code): exactly [`cmp_monomial`]'s cases.
type Key = [u64; KEY_FACTORS / 2];

/// Atom indices and exponents from here on do not fit a code.
const LIMIT: u32 = 0xFFFF;

fn pack(m: &Monomial) -> Option<Key> {
    if m.len() > KEY_FACTORS {
        return None;
    }
    let mut key = [0u64; KEY_FACTORS / 2];
    for (slot, &(atom, exponent)) in m.iter().enumerate() {
        let index = atom_index(atom);
        if index >= LIMIT || exponent > LIMIT {
            return None;
        }
        let code = (u64::from(LIMIT - index) << 16) | u64::from(exponent);
        let shift = if slot % 2 == 0 { 32 } else { 0 };
        key[slot / 2] |= code << shift;
    }
    Some(key)
}

/// Sorts terms by decreasing monomial and adds up the terms of equal monomials, in the order
/// they came (so that float coefficients add up in that order), as a stable sort by
/// [`cmp_monomial`] followed by merging neighbours would. Coefficients that add up to zero
/// are kept (as zero).
pub(crate) fn sort_and_merge(terms: &mut Vec<(Monomial, Number)>) {
    let Some(mut keys) = packed_keys(terms) else {
        terms.sort_by(|a, b| cmp_monomial(&b.0, &a.0));
        terms.dedup_by(|next, kept| {
            let same = next.0 == kept.0;
            if same {
                kept.1 = kept.1.add(&next.1);
            }
            same
        });
        return;
    };
    // Decreasing keys; the position breaks ties, so the unstable sort is stable in effect.
    keys.sort_unstable_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
    let mut slots: Vec<Option<(Monomial, Number)>> = terms.drain(..).map(Some).collect();
    let mut last: Option<Key> = None;
    for &(key, i) in &keys {
        let Some(term) = slots[i as usize].take() else {
            continue;
        };
        match terms.last_mut() {
            Some(kept) if last == Some(key) => kept.1 = kept.1.add(&term.1),
            _ => {
                terms.push(term);
                last = Some(key);
            }
        }
    }
}

/// Each term's key and position, or `None` when a monomial does not fit a key.
fn packed_keys(terms: &[(Monomial, Number)]) -> Option<Vec<(Key, u32)>> {
    let count = u32::try_from(terms.len()).ok()?;
    let mut keys = Vec::with_capacity(terms.len());
    for ((m, _), i) in terms.iter().zip(0..count) {
        keys.push((pack(m)?, i));
    }
    Some(keys)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expr::Expr;
    use crate::poly::plain_atom;

    /// Every pair of monomials from a small family (atoms of both orders, exponents, prefixes,
    /// the empty monomial, a monomial too long for a key) compares by key as by
    /// `cmp_monomial`, and a sort by keys is the stable sort.
    #[test]
    fn packed_keys_order_as_monomials() {
        let atoms: Vec<u32> = (0..10)
            .map(|i| plain_atom(Expr::symbol(&format!("term_order_x{i}"))))
            .collect();
        let mono = |factors: &[(usize, u32)]| -> Monomial {
            let mut m: Vec<(u32, u32)> = factors.iter().map(|&(a, e)| (atoms[a], e)).collect();
            m.sort_by_key(|&(a, _)| atom_index(a));
            m.into_iter().collect()
        };
        let family = vec![
            mono(&[]),
            mono(&[(0, 1)]),
            mono(&[(0, 2)]),
            mono(&[(1, 1)]),
            mono(&[(0, 1), (1, 1)]),
            mono(&[(0, 1), (2, 1)]),
            mono(&[(0, 1), (1, 2)]),
            mono(&[(1, 1), (2, 1), (3, 1)]),
            mono(&[
                (0, 1),
                (1, 1),
                (2, 1),
                (3, 1),
                (4, 1),
                (5, 1),
                (6, 1),
                (7, 1),
            ]),
            mono(&[
                (0, 1),
                (1, 1),
                (2, 1),
                (3, 1),
                (4, 1),
                (5, 1),
                (6, 1),
                (7, 2),
            ]),
            mono(&[
                (0, 1),
                (1, 1),
                (2, 1),
                (3, 1),
                (4, 1),
                (5, 1),
                (6, 1),
                (8, 1),
            ]),
            mono(&[(9, 70000)]),
        ];
        for a in &family {
            for b in &family {
                if let (Some(ka), Some(kb)) = (pack(a), pack(b)) {
                    assert_eq!(ka.cmp(&kb), cmp_monomial(a, b), "{a:?} vs {b:?}");
                }
            }
        }
        // Repeated monomials with distinct coefficients: the stable order is kept.
        let mut terms: Vec<(Monomial, Number)> = family
            .iter()
            .take(11)
            .enumerate()
            .flat_map(|(i, m)| {
                [
                    (m.clone(), Number::int(i as i64)),
                    (m.clone(), Number::int(100 + i as i64)),
                ]
            })
            .rev()
            .collect();
        let mut expected = terms.clone();
        stable_sort_and_merge(&mut expected);
        sort_and_merge(&mut terms);
        assert_eq!(terms, expected);
        assert_eq!(terms.len(), 11);
        // A monomial without a key sends the whole list to the general sort.
        let mut with_long = terms.clone();
        with_long.push((family[11].clone(), Number::ONE));
        with_long.push((family[3].clone(), Number::ONE));
        with_long.reverse();
        let mut expected = with_long.clone();
        stable_sort_and_merge(&mut expected);
        sort_and_merge(&mut with_long);
        assert_eq!(with_long, expected);
        assert_eq!(with_long.len(), 12);
    }

    /// The definition: a stable sort, then neighbours with equal monomials added up.
    fn stable_sort_and_merge(terms: &mut Vec<(Monomial, Number)>) {
        terms.sort_by(|a, b| cmp_monomial(&b.0, &a.0));
        let mut merged: Vec<(Monomial, Number)> = Vec::new();
        for (m, c) in terms.drain(..) {
            match merged.last_mut() {
                Some(last) if last.0 == m => last.1 = last.1.add(&c),
                _ => merged.push((m, c)),
            }
        }
        *terms = merged;
    }
}
