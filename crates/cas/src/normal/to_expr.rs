//! Normal form → expression: the canonical tree of a polynomial, built directly with its
//! operands already in structural order, or through the general constructors.

use smallvec::SmallVec;

use crate::expr::{intern_compound, Compound, Expr, Node};
use crate::number::Number;
use crate::poly::{atom_expr, atom_exprs, atom_index, AtomId, Monomial, Poly};

pub(crate) fn monomial_to_expr(m: &Monomial) -> Expr {
    Expr::mul_all(m.iter().map(|&(a, e)| atom_expr(a).powi(e as i64)))
}

pub(crate) fn poly_to_expr(p: &Poly) -> Expr {
    // Distinct monomials of atoms that are symbols, constants or function applications are
    // already what `add_all`/`mul_all` would make of them (no two share a base, no power
    // splits), so the canonical tree is built directly. Its operands must be sorted by
    // `Expr::cmp_structure`; rather than compare trees, the atoms are ranked once and every
    // factor and term is sorted by a key that orders exactly as `cmp_structure` would.
    // Anything else (roots, symbolic powers, absurd exponents) takes the general constructors.
    if p.terms.is_empty() {
        return Expr::zero();
    }
    let Some(atoms) = RankedAtoms::of(p) else {
        return general_poly_to_expr(p);
    };
    // Each term's operands counted from the last, packed in one flat buffer (see `TermKey`).
    let mut packed: Vec<u64> = Vec::with_capacity(p.terms.len() * 8);
    let mut keys: Vec<TermKey> = Vec::with_capacity(p.terms.len());
    for (index, (m, c)) in p.terms.iter().enumerate() {
        keys.push(atoms.term_key(index, m, c, &mut packed));
    }
    let operands_of = |k: &TermKey| &packed[k.start as usize..k.end as usize];
    // Distinct monomials have distinct keys, so an unstable sort gives the same order.
    keys.sort_unstable_by(|a, b| {
        a.rank
            .cmp(&b.rank)
            .then_with(|| operands_of(a).cmp(operands_of(b)))
            .then_with(|| {
                p.terms[a.index as usize]
                    .1
                    .total_cmp(&p.terms[b.index as usize].1)
            })
    });
    let terms: SmallVec<[Expr; 16]> = keys.iter().map(|k| k.term).collect();
    match terms.len() {
        1 => terms[0],
        _ => intern_compound(Compound::Add, &terms),
    }
}

/// The distinct atoms of a polynomial with their node class and rank in the structural order,
/// for [`poly_to_expr`]'s direct tree building.
struct RankedAtoms {
    /// The smallest atom index: `slot_of` is indexed by atom index minus this.
    low: u32,
    slot_of: Vec<u32>,
    exprs: Vec<Expr>,
    classes: Vec<u8>,
    ranks: Vec<u32>,
}

impl RankedAtoms {
    /// The atoms of `p`, or `None` when a term needs the general constructors.
    fn of(p: &Poly) -> Option<RankedAtoms> {
        // The distinct atoms, through a table indexed by atom index (atoms are few and densely
        // numbered, so this beats sorting every factor of every term).
        let (mut low, mut high) = (u32::MAX, 0u32);
        for (m, _) in &p.terms {
            for &(a, e) in m {
                if e >= MAX_PACKED_EXPONENT {
                    return None;
                }
                low = low.min(atom_index(a));
                high = high.max(atom_index(a));
            }
        }
        let mut slot_of: Vec<u32> = if low <= high {
            vec![u32::MAX; (high - low + 1) as usize]
        } else {
            Vec::new()
        };
        let mut ids: Vec<AtomId> = Vec::new();
        for (m, _) in &p.terms {
            for &(a, _) in m {
                let slot = &mut slot_of[(atom_index(a) - low) as usize];
                if *slot == u32::MAX {
                    *slot = ids.len() as u32;
                    ids.push(a);
                }
            }
        }
        let exprs = atom_exprs(&ids);
        let mut classes = Vec::with_capacity(exprs.len());
        // What each factor is ordered by: the atom, or a root's base (a power sorts by base).
        let mut bases = Vec::with_capacity(exprs.len());
        for e in &exprs {
            let (class, base) = match e.node() {
                Node::Symbol(_) => (1u8, *e),
                Node::Constant(_) => (2, *e),
                Node::Func(..) => (6, *e),
                // A root of a sum, `A^(1/q)`, is a power no other factor shares a base with
                // (the other atoms are symbols, constants and applications), so the
                // constructors keep it as it is; two roots of one sum would merge.
                Node::Pow([base, _]) if matches!(base.node(), Node::Add(_)) => {
                    if bases.contains(base) {
                        return None;
                    }
                    (ROOT_CLASS, *base)
                }
                _ => return None,
            };
            classes.push(class);
            bases.push(base);
        }
        if classes.contains(&ROOT_CLASS) {
            // A root appears to the first power only (`r^q = b` is applied); a higher power
            // would merge exponents in the constructors.
            let root_power = p.terms.iter().any(|(m, _)| {
                m.iter().any(|&(a, e)| {
                    e > 1 && classes[slot_of[(atom_index(a) - low) as usize] as usize] == ROOT_CLASS
                })
            });
            if root_power {
                return None;
            }
        }
        let mut by_structure: Vec<usize> = (0..ids.len()).collect();
        by_structure.sort_by(|&i, &j| bases[i].cmp_structure(bases[j]));
        let mut ranks = vec![0u32; ids.len()];
        for (rank, &i) in by_structure.iter().enumerate() {
            ranks[i] = rank as u32;
        }
        Some(RankedAtoms {
            low,
            slot_of,
            exprs,
            classes,
            ranks,
        })
    }

    /// The canonical tree of the term `c m` (number `index` of its polynomial) and its sort
    /// key, whose operands are appended to `packed`.
    fn term_key(&self, index: usize, m: &Monomial, c: &Number, packed: &mut Vec<u64>) -> TermKey {
        let mut factors: SmallVec<[(u64, Expr); 8]> = m
            .iter()
            .map(|&(a, e)| {
                let i = self.slot_of[(atom_index(a) - self.low) as usize] as usize;
                let base = self.exprs[i];
                if self.classes[i] == ROOT_CLASS {
                    (pack_factor(3, self.ranks[i], 1), base)
                } else if e == 1 {
                    (pack_factor(self.classes[i], self.ranks[i], 1), base)
                } else {
                    let power = intern_compound(Compound::Pow, &[base, Expr::int(i64::from(e))]);
                    (pack_factor(3, self.ranks[i], e), power)
                }
            })
            .collect();
        factors.sort_unstable_by_key(|f| f.0);
        let with_number = !c.is_exact_one() || factors.is_empty();
        let start = packed.len() as u32;
        packed.extend(factors.iter().rev().map(|f| f.0));
        let rank = match (with_number, factors.as_slice()) {
            (true, []) => 0,
            (false, [(f, _)]) => (f >> 56) as u8,
            _ => {
                if with_number {
                    packed.push(NUMBER_OPERAND);
                }
                4
            }
        };
        let mut operands: SmallVec<[Expr; 9]> = SmallVec::new();
        if with_number {
            operands.push(Expr::number(c.clone()));
        }
        operands.extend(factors.iter().map(|f| f.1));
        let term = match operands.len() {
            1 => operands[0],
            _ => intern_compound(Compound::Mul, &operands),
        };
        TermKey {
            rank,
            start,
            end: packed.len() as u32,
            index: index as u32,
            term,
        }
    }
}

/// The class [`RankedAtoms`] gives a root atom: a power (node rank 3), ranked by its base.
const ROOT_CLASS: u8 = 7;

/// Exponents from here on do not fit a packed factor key (and never occur in mechanics).
const MAX_PACKED_EXPONENT: u32 = 1 << 24;

/// The operand that stands for a product's coefficient: below every packed factor, as a number
/// sorts before every factor.
const NUMBER_OPERAND: u64 = 0;

/// A factor `atom^e` in the structural order, as one integer: the node's rank (symbol 1,
/// constant 2, power 3, function 6), then the atom's rank among the polynomial's atoms, then
/// the exponent (below [`MAX_PACKED_EXPONENT`]).
fn pack_factor(class: u8, rank: u32, exponent: u32) -> u64 {
    (u64::from(class) << 56) | (u64::from(rank) << 24) | u64::from(exponent)
}

/// A term in the structural order of [`Expr::cmp_structure`]: the rank of its node (a number
/// 0, a single factor its factor's rank, a product 4), then its operands from the last (the
/// most significant, as `cmp_slices` compares them), a product's coefficient being its first
/// operand ([`NUMBER_OPERAND`]); a shorter operand list that is a prefix of a longer one sorts
/// first, as in `cmp_slices`. Equal operand lists leave the coefficients to decide.
struct TermKey {
    rank: u8,
    start: u32,
    end: u32,
    index: u32,
    term: Expr,
}

fn general_poly_to_expr(p: &Poly) -> Expr {
    Expr::add_all(p.terms.iter().map(|(m, c)| {
        let mut factors = Vec::with_capacity(m.len() + 1);
        factors.push(Expr::number(c.clone()));
        factors.extend(m.iter().map(|&(a, e)| atom_expr(a).powi(e as i64)));
        Expr::mul_all(factors)
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::normal::to_rf;

    /// A small deterministic generator (xorshift), so the test needs no dependency.
    struct Rng(u64);

    impl Rng {
        fn below(&mut self, n: u64) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0 % n
        }
    }

    #[test]
    fn direct_tree_building_equals_the_general_constructors() {
        // The fast path of `poly_to_expr` sorts by keys that must order exactly as
        // `cmp_structure`; the general constructors sort by `cmp_structure` itself.
        let names = ["a", "b", "zeta", "x1", "x10", "x2"];
        let mut atoms: Vec<Expr> = names.iter().map(|n| Expr::symbol(n)).collect();
        atoms.push(Expr::coordinate("theta"));
        atoms.push(Expr::rate("theta", 1));
        atoms.push(Expr::rate("theta", 2));
        atoms.push(Expr::pi());
        atoms.push(Expr::coordinate("theta").sin());
        atoms.push(Expr::coordinate("phi").cos());
        atoms.push(Expr::symbol("a").exp());
        // Roots of sums (a spring's length): powers ranked by their base.
        let (a, b) = (Expr::symbol("a"), Expr::symbol("b"));
        let theta = Expr::coordinate("theta");
        atoms.push((a * a + theta.cos()).sqrt());
        atoms.push((b + Expr::int(2) * Expr::coordinate("phi").cos()).sqrt());
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for _ in 0..1000 {
            let terms = 1 + rng.below(9);
            let e = Expr::add_all((0..terms).map(|_| {
                let c = Expr::int(rng.below(7) as i64 - 3);
                let factors = rng.below(4);
                c * Expr::mul_all((0..factors).map(|_| {
                    let a = atoms[rng.below(atoms.len() as u64) as usize];
                    a.powi(1 + rng.below(3) as i64)
                }))
            }));
            let r = to_rf(e);
            assert_eq!(poly_to_expr(&r.num), general_poly_to_expr(&r.num), "{e:?}");
        }
    }
}
