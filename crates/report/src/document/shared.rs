//! Names for long shared sub-expressions: the course writes `ẍ = (…)/(ℓ Δ)` with
//! `Δ = m_B sin² θ + m_A` defined once, not the same long denominator under every acceleration
//! and every reaction component.
//!
//! [`Notation::name_shared`] takes the expressions of one display. When the display is too long
//! for a column, the sum in each denominator (its monomial content set apart: `ℓ` of
//! `ℓ (m_B sin² θ + m_A)`) that several of the expressions share, or that a single long
//! expression carries, is replaced by a symbol — `Δ`, then `Δ2`, `Δ3`, … skipping every name
//! the model or the display uses. A name is remembered by the [`Notation`] (and all its clones),
//! so a later display that meets the same sum reuses it without defining it again; the new
//! definitions come back as [`Equation`]s for the caller to put first in its display.
//!
//! The rewrite never changes a value: substituting each definition back gives the expression
//! it came from.

use std::collections::HashSet;

use cas::print::to_unicode;
use cas::{Expr, Node};

use super::{Equation, Math, Notation};

/// A display is too long for a column when one of its expressions prints longer than this many
/// glyphs (the text rendering wraps at 80, with room for the left-hand side).
const LONG_DISPLAY: usize = 60;

/// A sum is worth a name only when it prints at least this long (`m + M` reads as well as `Δ`).
const NAME_MIN: usize = 12;

/// The expressions of a display with their long shared denominators named.
#[derive(Clone, Debug)]
pub struct Named {
    /// `Δ = …` for each name the display introduces, in order of first use.
    pub definitions: Vec<Equation>,
    /// The expressions, in the order given, written with the names.
    pub exprs: Vec<Expr>,
    /// Each name used (symbol and definition), the new and the earlier ones: substituting them
    /// back gives the expressions given.
    pub used: Vec<(Expr, Expr)>,
}

/// An expression as `numerator / (content · sum)`, the sum in its sign-normalised form.
struct Split {
    numerator: Expr,
    content: Expr,
    sum: Expr,
}

impl Notation {
    /// The expressions of one display, with each long sum that their denominators share named
    /// (see the module documentation). Short displays come back as they are.
    #[must_use]
    pub fn name_shared(&self, exprs: &[Expr]) -> Named {
        let mut named = Named {
            definitions: Vec::new(),
            exprs: exprs.to_vec(),
            used: Vec::new(),
        };
        let long: Vec<bool> = exprs
            .iter()
            .map(|e| to_unicode(self.shape(*e)).chars().count() > LONG_DISPLAY)
            .collect();
        if !long.iter().any(|l| *l) {
            return named;
        }
        let splits: Vec<Option<Split>> = exprs.iter().map(|e| self.split(*e)).collect();
        let mut taken = self.taken_names(exprs);
        for (i, split) in splits.iter().enumerate() {
            let Some(split) = split else { continue };
            let known = self
                .shared
                .borrow()
                .iter()
                .find_map(|(symbol, definition)| {
                    monomial_ratio(split.sum, *definition)
                        .map(|ratio| (*symbol, *definition, ratio))
                });
            let (symbol, ratio) = match known {
                Some((symbol, definition, ratio)) => {
                    if !named.used.iter().any(|(s, _)| *s == symbol) {
                        named.used.push((symbol, definition));
                    }
                    (symbol, ratio)
                }
                None => {
                    let sharing = splits
                        .iter()
                        .flatten()
                        .filter(|s| monomial_ratio(s.sum, split.sum).is_some())
                        .count();
                    let short = to_unicode(self.shape(split.sum)).chars().count() < NAME_MIN;
                    if short || (sharing < 2 && !long[i]) {
                        continue;
                    }
                    (
                        self.new_name(split.sum, &mut taken, &mut named),
                        Expr::one(),
                    )
                }
            };
            if let Some(e) = named.exprs.get_mut(i) {
                *e = split.numerator * (split.content * ratio * symbol).powi(-1);
            }
        }
        named
    }

    /// A new symbol for `sum`, recorded by the notation, its definition added to `named`.
    fn new_name(&self, sum: Expr, taken: &mut HashSet<String>, named: &mut Named) -> Expr {
        let symbol = fresh_name(taken);
        self.shared.borrow_mut().push((symbol, sum));
        named
            .definitions
            .push(Equation::new(Math::expr(symbol), self.math(sum)));
        named.used.push((symbol, sum));
        symbol
    }

    /// Whether `e` has a named sum in a denominator: the shaping then leaves its fraction
    /// whole (spreading `1/(ℓ Δ)` over the terms would undo what the name is for).
    pub(super) fn has_shared_name(&self, e: Expr) -> bool {
        let shared = self.shared.borrow();
        if shared.is_empty() {
            return false;
        }
        let mut stack = vec![e];
        let mut seen = HashSet::new();
        while let Some(x) = stack.pop() {
            if !seen.insert(x) {
                continue;
            }
            if shared.iter().any(|(symbol, _)| *symbol == x) {
                return true;
            }
            stack.extend_from_slice(x.children());
        }
        false
    }

    /// `e` as `numerator / (content · sum)` when its denominator has a sum of two terms or
    /// more; the sum's sign is the one that prints fewer minus signs.
    fn split(&self, e: Expr) -> Option<Split> {
        let (numerator, denominator) = e.numer_denom();
        let (content, sum) = denominator.common_factor();
        if !matches!(sum.node(), Node::Add(_)) {
            return None;
        }
        let minus = |x: Expr| {
            let printed = to_unicode(self.shape(x));
            (
                printed.matches('−').count(),
                usize::from(printed.starts_with('−')),
            )
        };
        let negated = (-sum).normal();
        Some(if minus(negated) < minus(sum) {
            Split {
                numerator,
                content: -content,
                sum: negated,
            }
        } else {
            Split {
                numerator,
                content,
                sum,
            }
        })
    }

    /// The names a new symbol must not take: the model's, those already given, and every
    /// symbol in `exprs`.
    fn taken_names(&self, exprs: &[Expr]) -> HashSet<String> {
        let mut taken: HashSet<String> = self.taken.iter().cloned().collect();
        for (symbol, _) in self.shared.borrow().iter() {
            if let Some(s) = symbol.as_symbol() {
                taken.insert(s.name().to_string());
            }
        }
        let mut stack: Vec<Expr> = exprs.to_vec();
        let mut seen = HashSet::new();
        while let Some(e) = stack.pop() {
            if !seen.insert(e) {
                continue;
            }
            if let Some(s) = e.as_symbol() {
                taken.insert(s.name().to_string());
            }
            stack.extend_from_slice(e.children());
        }
        taken
    }
}

/// `a/b` when it is a monomial (a product of powers and a number, `−sin² α`): `a` is then
/// `b` up to a factor the named form keeps in front.
fn monomial_ratio(a: Expr, b: Expr) -> Option<Expr> {
    let ratio = (a / b).normal();
    let (numerator, denominator) = ratio.numer_denom();
    let sum = |x: Expr| matches!(x.node(), Node::Add(_));
    (!sum(numerator) && !sum(denominator)).then_some(ratio)
}

/// `Δ`, `Δ2`, `Δ3`, …: the first not in `taken` (which it joins).
fn fresh_name(taken: &mut HashSet<String>) -> Expr {
    let name = std::iter::once("Delta".to_string())
        .chain((2..).map(|k| format!("Delta{k}")))
        .find(|n| !taken.contains(n))
        .unwrap_or_else(|| "Delta".to_string());
    taken.insert(name.clone());
    Expr::symbol(&name)
}
