//! Structural operations on the normal form: coefficients, collection, expansion and common
//! factors.
//!
//! These are the tools the mechanics layer uses to read equations: the mass matrix is the
//! coefficient of each `q̈_j` in the equations of motion, the forcing is what remains.

use std::sync::Arc;

use rustc_hash::FxHashMap;

use crate::expr::Expr;
use crate::normal::{cached_rf, from_rf, monomial_to_expr, poly_to_expr, to_rf, Rf};
use crate::number::Number;
use crate::poly::{atom_index, AtomId, Monomial, Poly};

/// The atom id of an expression that is a single atom to the first power.
fn single_atom(x: Expr) -> Option<AtomId> {
    let r = to_rf(x);
    if !r.den.is_one() {
        return None;
    }
    match r.num.terms.as_slice() {
        [(m, c)] if c.is_one() && m.len() == 1 && m[0].1 == 1 => Some(m[0].0),
        _ => None,
    }
}

/// The atom ids of `atoms` and the normal form of `e`; `None` when an entry is not an atom
/// or occurs in the denominator (then nothing can be read off term by term).
fn atoms_and_normal_form(e: Expr, atoms: &[Expr]) -> Option<(Vec<AtomId>, Rf)> {
    let ids: Vec<AtomId> = atoms
        .iter()
        .map(|a| single_atom(*a))
        .collect::<Option<_>>()?;
    let r = to_rf(e);
    if ids.iter().any(|a| r.den.contains_atom(*a)) {
        return None;
    }
    Some((ids, r))
}

/// The coefficients and the remainder of a working form affine in `atoms` (see
/// [`Expr::affine_coefficients`]).
pub(crate) fn affine_split(r: &Rf, atoms: &[Expr]) -> Option<(Vec<Rf>, Rf)> {
    let ids: Vec<AtomId> = atoms
        .iter()
        .map(|a| single_atom(*a))
        .collect::<Option<_>>()?;
    if ids.iter().any(|a| r.den.contains_atom(*a)) {
        return None;
    }
    let position = AtomPositions::of(&ids);
    let mut buckets: Vec<Vec<(Monomial, Number)>> = vec![Vec::new(); ids.len()];
    let mut rest: Vec<(Monomial, Number)> = Vec::new();
    for (m, c) in &r.num.terms {
        let mut found: Option<(usize, usize)> = None;
        for (pos, (a, e)) in m.iter().enumerate() {
            if let Some(j) = position.of_atom(*a) {
                if *e != 1 || found.is_some() {
                    return None;
                }
                found = Some((j, pos));
            }
        }
        match found {
            Some((j, pos)) => {
                let mut reduced = m.clone();
                reduced.remove(pos);
                buckets[j].push((reduced, c.clone()));
            }
            None => rest.push((m.clone(), c.clone())),
        }
    }
    let finish = |terms: Vec<(Monomial, Number)>| {
        Rf::new(Poly::from_terms(terms), r.den.clone()).unwrap_or_else(Rf::zero)
    };
    let coefficients = buckets.into_iter().map(finish).collect();
    Some((coefficients, finish(rest)))
}

/// The position of each of a list of atoms in it, found through a table indexed by atom index:
/// an affine split asks for every factor of every term, and searching the list made the split
/// of `n` equations in the `n` accelerations O(n) per factor.
struct AtomPositions {
    low: u32,
    slots: Vec<u32>,
}

impl AtomPositions {
    fn of(ids: &[AtomId]) -> AtomPositions {
        let low = ids.iter().map(|&a| atom_index(a)).min().unwrap_or(0);
        let high = ids.iter().map(|&a| atom_index(a)).max().unwrap_or(0);
        let mut slots = vec![
            u32::MAX;
            if ids.is_empty() {
                0
            } else {
                (high - low + 1) as usize
            }
        ];
        // The first position of a repeated atom, as a search from the front finds it.
        for (j, &a) in ids.iter().enumerate().rev() {
            slots[(atom_index(a) - low) as usize] = j as u32;
        }
        AtomPositions { low, slots }
    }

    fn of_atom(&self, a: AtomId) -> Option<usize> {
        let slot = atom_index(a).checked_sub(self.low)?;
        match self.slots.get(slot as usize) {
            Some(&j) if j != u32::MAX => Some(j as usize),
            _ => None,
        }
    }
}

impl Expr {
    /// The coefficient of `x^k` in the normal form, where `x` is a symbol or another atom
    /// (`sin θ`, `θ̈`). `None` when `x` is not an atom or occurs in the denominator.
    pub fn coeff(self, x: Expr, k: u32) -> Option<Expr> {
        let a = single_atom(x)?;
        let r = to_rf(self);
        if r.den.contains_atom(a) {
            return None;
        }
        let c = r
            .num
            .coefficients_in(a)
            .into_iter()
            .find(|(d, _)| *d == k)
            .map(|(_, p)| p)
            .unwrap_or_default();
        Rf::new(c, r.den).map(|c| from_rf(&c))
    }

    /// Collects the normal form by powers of the given atoms: `Σ c_m · m` where `m` runs over
    /// the monomials in `atoms` and the coefficients `c_m` (in normal form) are free of them.
    /// Terms are ordered by decreasing total degree in `atoms`. `None` when an entry of
    /// `atoms` is not an atom or one occurs in the denominator.
    pub fn collect(self, atoms: &[Expr]) -> Option<Expr> {
        let (ids, r) = atoms_and_normal_form(self, atoms)?;
        let mut groups: FxHashMap<Monomial, Vec<(Monomial, Number)>> = FxHashMap::default();
        let mut order: Vec<Monomial> = Vec::new();
        for (m, c) in &r.num.terms {
            let key: Monomial = m.iter().filter(|(a, _)| ids.contains(a)).copied().collect();
            let rest: Monomial = m
                .iter()
                .filter(|(a, _)| !ids.contains(a))
                .copied()
                .collect();
            groups
                .entry(key.clone())
                .or_insert_with(|| {
                    order.push(key);
                    Vec::new()
                })
                .push((rest, c.clone()));
        }
        order.sort_by_key(|m| std::cmp::Reverse(m.iter().map(|(_, e)| *e).sum::<u32>()));
        let terms: Vec<Expr> = order
            .into_iter()
            .map(|key| {
                let coefficient = Rf::new(
                    Poly::from_terms(groups.remove(&key).unwrap_or_default()),
                    r.den.clone(),
                )
                .map(|c| from_rf(&c))
                .unwrap_or_else(Expr::zero);
                coefficient * monomial_to_expr(&key)
            })
            .collect();
        Some(Expr::add_all(terms))
    }

    /// The normal form with the denominator distributed over the terms of the numerator
    /// (`(x + 1)/m` → `x/m + 1/m`): a sum of monomial terms.
    pub fn expand(self) -> Expr {
        let r = to_rf(self);
        if r.den.is_one() {
            return from_rf(&r);
        }
        let inv = poly_to_expr(&r.den).powi(-1);
        Expr::add_all(
            r.num
                .terms
                .iter()
                .map(|(m, c)| Expr::number(c.clone()) * monomial_to_expr(m) * inv),
        )
    }

    /// Splits the normal form as `factor · rest`, where `factor` holds the rational content,
    /// the monomial common to every term and the denominator, and `rest` is a primitive
    /// polynomial (integer coefficients with gcd 1 and a positive leading term) — e.g.
    /// `m ℓ² θ̈ + m g ℓ sin θ` → `(m ℓ, ℓ θ̈ + g sin θ)`.
    pub fn common_factor(self) -> (Expr, Expr) {
        let r = to_rf(self);
        if r.num.is_zero() {
            return (Expr::one(), Expr::zero());
        }
        let mut mono: Monomial = r.num.terms[0].0.clone();
        for (m, _) in &r.num.terms {
            mono.retain(|(a, e)| {
                let d = m.iter().find(|(b, _)| b == a).map_or(0, |(_, d)| *d);
                *e = (*e).min(d);
                *e > 0
            });
        }
        let content = r.num.content();
        let mono_poly = Poly {
            terms: vec![(mono.clone(), content.clone())],
        };
        let rest = r.num.div_exact(&mono_poly).unwrap_or_else(|| r.num.clone());
        let factor = Rf::new(
            Poly {
                terms: vec![(mono, content)],
            },
            r.den,
        )
        .unwrap_or_else(Rf::one);
        (from_rf(&factor), from_rf(&Rf::from_poly(rest)))
    }

    /// Reads an expression that is affine in the given atoms, `Σ_j c_j x_j + r`, returning
    /// the coefficients `c_j` and the remainder `r` (all in normal form) in one pass. This is
    /// how the mass matrix comes out of the equations of motion (the atoms are the `q̈_j`).
    /// `None` when an entry of `atoms` is not an atom, occurs in the denominator, or occurs
    /// non-linearly (squared, or multiplied by another of them).
    pub fn affine_coefficients(self, atoms: &[Expr]) -> Option<(Vec<Expr>, Expr)> {
        let r = match cached_rf(self) {
            Some(r) => r,
            None => Arc::new(to_rf(self)),
        };
        let (coefficients, rest) = affine_split(&r, atoms)?;
        Some((coefficients.iter().map(from_rf).collect(), from_rf(&rest)))
    }

    /// The number of terms in the numerator of the normal form (a size measure).
    pub fn term_count(self) -> usize {
        to_rf(self).num.terms.len()
    }
}
