//! The course's order of terms in a sum and of factors in a product, used by the printers for
//! people (the exact SymPy printer keeps the tree's own order).
//!
//! Terms: second derivatives first, then first derivatives, then coordinates, then terms of
//! parameters only, numbers last; among equals, terms with fewer function factors first (the
//! diagonal `m ℓ² θ̈` before the coupling `m ℓ ẍ cos θ`), then Latin coordinates before Greek.
//! Factors: the coefficient, parameters (masses first), sums of parameters, then the
//! time-dependent factors (rates and coordinates, functions, sums).

use std::cell::RefCell;
use std::cmp::Ordering;

use rustc_hash::FxHashMap;

use crate::expr::{split_coefficient, Expr, Node, SymbolKind};
use crate::number::Number;

use super::names::is_greek;

/// A term with what the order of terms looks at, computed once: the comparison walks every
/// factor of a term, and a sort of `T` terms compares `O(T log T)` times.
struct SortKey {
    info: TermInfo,
    coefficient: Number,
    rest: Expr,
    term: Expr,
}

impl SortKey {
    fn of(term: Expr) -> SortKey {
        let (coefficient, rest) = split_coefficient(term);
        SortKey {
            info: TermInfo::of(term),
            coefficient,
            rest,
            term,
        }
    }

    fn negative(&self) -> bool {
        self.coefficient.is_negative()
    }
}

/// Orders the terms of a sum for people.
fn cmp_terms(a: &SortKey, b: &SortKey) -> Ordering {
    let (ia, ib) = (&a.info, &b.info);
    ib.class
        .cmp(&ia.class)
        .then(ia.funcs.cmp(&ib.funcs))
        .then_with(|| name_key(ia.lead).cmp(&name_key(ib.lead)))
        .then_with(|| {
            a.rest
                .cmp_structure(b.rest)
                .then_with(|| a.coefficient.total_cmp(&b.coefficient))
        })
}

/// Sorts the terms of a sum for people. A sum does not open with a minus when a positive term
/// of the same rank can lead instead (`θ2 − θ1`, not `−θ1 + θ2`).
pub(super) fn sort_terms(terms: &mut [Expr]) {
    let mut keys: Vec<SortKey> = terms.iter().map(|t| SortKey::of(*t)).collect();
    keys.sort_by(cmp_terms);
    if keys.first().is_some_and(SortKey::negative) {
        let first = &keys[0].info;
        let lead = keys.iter().position(|k| {
            !k.negative() && k.info.class == first.class && k.info.funcs == first.funcs
        });
        if let Some(k) = lead {
            keys[..=k].rotate_right(1);
        }
    }
    for (t, k) in terms.iter_mut().zip(keys) {
        *t = k.term;
    }
}

/// Orders the factors of a product for people.
pub(super) fn cmp_factors(a: Expr, b: Expr) -> Ordering {
    let (ga, gb) = (factor_group(a), factor_group(b));
    ga.cmp(&gb)
        .then_with(|| match (atom_symbol(a), atom_symbol(b)) {
            (Some(x), Some(y)) => symbol_key(x)
                .cmp(&symbol_key(y))
                .then_with(|| a.cmp_structure(b)),
            _ => a.cmp_structure(b),
        })
}

/// Whether `e` depends on time (contains time, a coordinate or a rate).
///
/// The printers ask this of every factor of every term, and a factor is often a large
/// time-independent sum (a denominator in the parameters) asked about once per term it divides:
/// the answer for each compound node is remembered (nodes never change), so each is visited once
/// per thread, and a shared node once per walk (a tree walk of a DAG such as the derivative of a
/// power tower is exponential).
pub(super) fn has_time(e: Expr) -> bool {
    if let Some(leaf) = leaf_has_time(e) {
        return leaf;
    }
    HAS_TIME.with(|memo| {
        let mut memo = memo.borrow_mut();
        if let Some(&known) = memo.get(&e) {
            return known;
        }
        // Post-order without recursion (expressions can be deep): a node is decided once all
        // its compound children are.
        let mut stack = vec![(e, false)];
        while let Some((x, children_done)) = stack.pop() {
            if memo.contains_key(&x) {
                continue;
            }
            if children_done {
                let answer = x
                    .children()
                    .iter()
                    .any(|c| leaf_has_time(*c).unwrap_or_else(|| memo[c]));
                memo.insert(x, answer);
                continue;
            }
            stack.push((x, true));
            for c in x.children() {
                if leaf_has_time(*c).is_none() && !memo.contains_key(c) {
                    stack.push((*c, false));
                }
            }
        }
        memo[&e]
    })
}

thread_local! {
    /// [`has_time`] of the compound nodes asked about so far.
    static HAS_TIME: RefCell<FxHashMap<Expr, bool>> = RefCell::new(FxHashMap::default());
}

/// [`has_time`] of a leaf; `None` for a node with children.
fn leaf_has_time(e: Expr) -> Option<bool> {
    match e.node() {
        Node::Symbol(s) => Some(s.kind() != SymbolKind::Constant),
        Node::Number(_) | Node::Constant(_) => Some(false),
        _ => None,
    }
}

struct TermInfo {
    class: u32,
    funcs: usize,
    lead: Option<&'static str>,
}

impl TermInfo {
    fn of(t: Expr) -> TermInfo {
        let mut info = TermInfo {
            class: 0,
            funcs: 0,
            lead: None,
        };
        let mut best: Option<(u8, &'static str)> = None;
        let mut stack = vec![t];
        while let Some(e) = stack.pop() {
            match e.node() {
                Node::Symbol(s) => match s.kind() {
                    SymbolKind::TimeFunction { order } => {
                        let better = match best {
                            None => true,
                            Some((o, n)) => {
                                order > o
                                    || (order == o && name_key(Some(s.name())) < name_key(Some(n)))
                            }
                        };
                        if better {
                            best = Some((order, s.name()));
                        }
                    }
                    SymbolKind::Time => info.class = info.class.max(50),
                    _ => info.class = info.class.max(10),
                },
                Node::Constant(_) => info.class = info.class.max(10),
                Node::Func(..) => {
                    info.funcs += 1;
                    stack.extend_from_slice(e.children());
                }
                _ => stack.extend_from_slice(e.children()),
            }
        }
        if let Some((order, name)) = best {
            info.class = 100 + u32::from(order);
            info.lead = Some(name);
        }
        info
    }
}

/// Latin names before Greek ones (`x` before `θ`), then alphabetical.
fn name_key(name: Option<&str>) -> (bool, bool, &str) {
    match name {
        None => (true, false, ""),
        Some(n) => (false, is_greek(n), n),
    }
}

/// Parameters: masses first (`m_B g ℓ`, as the course writes), then Latin before Greek.
fn symbol_key(s: crate::expr::Symbol) -> (bool, bool, &'static str, std::cmp::Reverse<u8>) {
    let n = s.name();
    let mass = n == "m"
        || n == "M"
        || n.starts_with("m_")
        || n.starts_with("M_")
        || (n.len() > 1 && n.starts_with('m') && n[1..].bytes().all(|b| b.is_ascii_digit()));
    (!mass, is_greek(n), n, std::cmp::Reverse(s.order()))
}

/// The symbol a factor is a power of, if it is one.
fn atom_symbol(e: Expr) -> Option<crate::expr::Symbol> {
    match e.node() {
        Node::Symbol(s) => Some(*s),
        Node::Pow([b, _]) => b.as_symbol(),
        _ => None,
    }
}

fn factor_group(e: Expr) -> u8 {
    let base = match e.node() {
        Node::Pow([b, _]) => *b,
        _ => e,
    };
    let dynamic = has_time(e);
    let kind = match base.node() {
        Node::Number(_) => 0,
        Node::Constant(_) => 1,
        Node::Symbol(_) => 2,
        Node::Func(..) => 4,
        Node::Add(_) => 5,
        _ => 6,
    };
    match (dynamic, kind) {
        (false, 0..=2) => kind,
        (false, 5) => 3,
        (false, k) => k,
        (true, k) => 10 + k,
    }
}
