//! The canonical normal form: an expression as a fraction `N / D` of polynomials in atoms.
//!
//! Conversion to the normal form expands products and integer powers, expands `sin`, `cos` and
//! `tan` of sums and integer multiples into products of `sin`/`cos` of single angles (and
//! evaluates them exactly at multiples of π/6 and π/4; multiples above `MAX_EXPANDED_MULTIPLE`
//! are angles of their own), reduces `sin²` with `sin² + cos² = 1`,
//! reduces powers of roots, splits `exp` of sums, and brings everything over one denominator in
//! lowest terms (polynomial GCD). The denominator is kept free of `sin` atoms and square roots
//! (by multiplying with a conjugate), integer-primitive, with a positive leading term in the
//! structural order. Two expressions of the class mechanics produces are equal exactly when
//! their normal forms are the same [`Expr`]; `is_zero` is then exact.
//!
//! Zero tests ([`Expr::is_zero`], [`Expr::equals`]) are exact for the whole class: a fraction
//! is zero exactly when its numerator is, and the numerator is a canonical element of
//! `ℚ[atoms]/(sin² + cos² − 1)`. The *identity* of normal forms needs the denominator to be
//! rationalised, which is done while it is small; a fraction whose denominator is a long
//! trigonometric sum is kept as it is, still equal to its input. Outside the class (roots of
//! higher order in sums under a fraction bar, the same angle written as both `θ/2` and `θ`,
//! numeric angles such as `sin(1)` and `sin(1/2)`, which are independent atoms, even roots of
//! fractions, kept whole because `√(N/D) = √(N D)/D` needs `D > 0`) the normal form is still
//! *equal* to its input, but two equal inputs may differ.
//!
//! Cost: trigonometry of an angle with `k` terms expands into up to `2^k` products, and a
//! fraction whose denominator is a long trigonometric sum makes every later operation on it
//! expensive; a GCD gives up (leaving the fraction less reduced but equal) past a work budget.

use std::sync::{Arc, Mutex, OnceLock};

use rustc_hash::FxHashMap;
use smallvec::SmallVec;

use crate::expr::{intern_compound, Compound, Constant, Expr, Func, Node};
use crate::limits::{self, WorkLimitError};
use crate::number::Number;
use crate::poly::{
    self, atom_expr, atom_exprs, atom_index, gcd, plain_atom, root_atom, trig_atoms, AtomId,
    AtomKind, Monomial, Poly,
};

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
            None => (
                self.num.mul(&other.den).add(&other.num.mul(&self.den)),
                self.den.mul(&other.den),
            ),
        };
        Rf::new(num, den).unwrap_or_else(Rf::zero)
    }

    pub(crate) fn neg(&self) -> Rf {
        Rf {
            num: self.num.neg(),
            den: self.den.clone(),
        }
    }

    pub(crate) fn sub(&self, other: &Rf) -> Rf {
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
    // The distinct atoms, through a table indexed by atom index (atoms are few and densely
    // numbered, so this beats sorting every factor of every term).
    let (mut low, mut high) = (u32::MAX, 0u32);
    for (m, _) in &p.terms {
        for &(a, e) in m {
            if e >= MAX_PACKED_EXPONENT {
                return general_poly_to_expr(p);
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
    for e in &exprs {
        classes.push(match e.node() {
            Node::Symbol(_) => 1u8,
            Node::Constant(_) => 2,
            Node::Func(..) => 6,
            _ => return general_poly_to_expr(p),
        });
    }
    let mut by_structure: Vec<usize> = (0..ids.len()).collect();
    by_structure.sort_by(|&i, &j| exprs[i].cmp_structure(exprs[j]));
    let mut ranks = vec![0u32; ids.len()];
    for (rank, &i) in by_structure.iter().enumerate() {
        ranks[i] = rank as u32;
    }
    // Each term's operands counted from the last, packed in one flat buffer (see `TermKey`).
    let mut packed: Vec<u64> = Vec::with_capacity(p.terms.len() * 8);
    let mut keys: Vec<TermKey> = Vec::with_capacity(p.terms.len());
    for (index, (m, c)) in p.terms.iter().enumerate() {
        let mut factors: SmallVec<[(u64, Expr); 8]> = m
            .iter()
            .map(|&(a, e)| {
                let i = slot_of[(atom_index(a) - low) as usize] as usize;
                let base = exprs[i];
                if e == 1 {
                    (pack_factor(classes[i], ranks[i], 1), base)
                } else {
                    let power = intern_compound(Compound::Pow, &[base, Expr::int(i64::from(e))]);
                    (pack_factor(3, ranks[i], e), power)
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
        keys.push(TermKey {
            rank,
            start,
            end: packed.len() as u32,
            index: index as u32,
            term,
        });
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

// ---------------------------------------------------------------------------------------------
// Expression → normal form.

/// Converts expressions to normal form, remembering the nodes it has seen (expressions are
/// DAGs: a shared sub-expression is converted once).
#[derive(Default)]
pub(crate) struct Normalizer {
    memo: FxHashMap<Expr, Rf>,
}

impl Normalizer {
    pub(crate) fn rf(&mut self, e: Expr) -> Rf {
        if let Some(r) = self.memo.get(&e) {
            return r.clone();
        }
        if let Some(r) = cached_rf(e) {
            return Rf::clone(&r);
        }
        let r = self.convert(e);
        self.memo.insert(e, r.clone());
        r
    }

    fn convert(&mut self, e: Expr) -> Rf {
        match e.node() {
            Node::Number(n) => Rf::constant(n.clone()),
            Node::Symbol(_) | Node::Constant(_) => Rf::atom(plain_atom(e)),
            Node::Add(terms) => {
                // Adding terms one by one into a sorted accumulator is quadratic; gather the
                // polynomial parts and sort-merge them once, and add the fractions after.
                let mut polynomial_terms = Vec::new();
                let mut fractions = Rf::zero();
                for t in terms.iter() {
                    let r = self.rf(*t);
                    if r.den.is_one() {
                        polynomial_terms.extend(r.num.terms);
                    } else {
                        fractions = fractions.add(&r);
                    }
                }
                Rf::from_poly(Poly::from_terms(polynomial_terms)).add(&fractions)
            }
            Node::Mul(factors) => {
                let mut acc = Rf::one();
                for f in factors.iter() {
                    acc = acc.mul(&self.rf(*f));
                    if acc.is_zero() {
                        break;
                    }
                }
                acc
            }
            Node::Pow([base, exp]) => self.power(*base, *exp),
            Node::Func(f, args) => self.function(*f, args),
        }
    }

    /// An application the algebra does not rewrite, as an atom of its own. The constructors
    /// fold literal arguments (`ln 1 = 0`, `tan 0 = 0`), and a number must never become an
    /// atom: its printed tree would be the number while the polynomial kept a variable.
    fn opaque(&mut self, e: Expr) -> Rf {
        match e.node() {
            Node::Number(n) => Rf::constant(n.clone()),
            _ => Rf::atom(plain_atom(e)),
        }
    }

    fn power(&mut self, base: Expr, exp: Expr) -> Rf {
        let b = self.rf(base);
        let x = self.rf(exp);
        if let Some(k) = x.as_constant() {
            if let Some(k) = k.to_i64() {
                return b
                    .powi(k)
                    .unwrap_or_else(|| self.opaque(Expr::pow(b.to_expr(), Expr::int(k))));
            }
            if let Some((p, q)) = k.to_small_ratio() {
                if let Ok(q) = u32::try_from(q) {
                    if let Some(r) = self.rational_power(&b, p, q) {
                        return r;
                    }
                }
            }
            if k.is_float() {
                if let Some(c) = b.as_constant() {
                    let v = c.to_f64().powf(k.to_f64());
                    if v.is_finite() {
                        return Rf::constant(Number::Float(v));
                    }
                }
            }
        }
        if let Some(c) = b.as_constant() {
            if c.is_zero() || c.is_one() {
                return Rf::constant(c);
            }
        }
        // A symbolic exponent: keep `b^x` as an atom of normalised parts.
        let atom = Expr::pow(b.to_expr(), x.to_expr());
        match atom.node() {
            Node::Pow(..) => self.opaque(atom),
            _ => self.rf(atom),
        }
    }

    /// `b^(p/q)` for `q ≥ 2`, through the root atom `(N D^(q−1))^(1/q)`.
    fn rational_power(&mut self, b: &Rf, p: i64, q: u32) -> Option<Rf> {
        if let Some(c) = b.as_constant() {
            if c.is_float() {
                let v = c.to_f64().powf(p as f64 / q as f64);
                return v.is_finite().then(|| Rf::constant(Number::Float(v)));
            }
        }
        // (N/D)^(1/q) = (N D^(q−1))^(1/q) / D holds for odd q, and for even q only where
        // D > 0, which the algebra cannot know: an even root of a fraction stays an atom.
        if q % 2 == 0 && !b.den.is_one() {
            let atom = Expr::pow(b.to_expr(), Expr::number(Number::rational(1, q as i64)?));
            return Rf::atom(plain_atom(atom)).powi(p);
        }
        let radicand = b.num.mul(&b.den.pow(q - 1));
        let root = self.root_of_poly(&radicand, q)?;
        let root = root.div(&Rf::from_poly(b.den.clone()))?;
        root.powi(p)
    }

    /// `P^(1/q)` for a polynomial `P`: the rational content's exact part comes out, the rest
    /// becomes root atoms of a number and of a primitive polynomial.
    fn root_of_poly(&mut self, p: &Poly, q: u32) -> Option<Rf> {
        if p.is_zero() {
            return Some(Rf::zero());
        }
        // Only a positive content may leave the root: `√(3 − c²)` is not `√−1 · √(c² − 3)`
        // over the reals.
        let content = p.content().abs();
        let primitive = p.scale(&content.recip()?);
        let mut result = self.root_of_number(&content, q)?;
        if !primitive.is_one() {
            let expr = Expr::pow(
                poly_to_expr(&primitive),
                Expr::number(Number::rational(1, q as i64)?),
            );
            let id = root_atom(expr, primitive, q);
            result = result.mul(&Rf::atom(id));
        }
        Some(result)
    }

    fn root_of_number(&mut self, c: &Number, q: u32) -> Option<Rf> {
        if let Some(r) = c.exact_root(q) {
            return Some(Rf::constant(r));
        }
        // Split c = s^q · r with r free of q-th powers: integers by trial division.
        let (n, d) = c.to_small_ratio()?;
        // c = n/d; write as (n d^(q−1)) / d^q so only an integer is under the root.
        let mut radicand = (n as i128).checked_mul((d as i128).checked_pow(q - 1)?)?;
        let mut outside: i128 = 1;
        let negative = radicand < 0;
        radicand = radicand.abs();
        let mut f: i128 = 2;
        while f * f <= radicand && f < 10_000 {
            let fq = f.checked_pow(q)?;
            while radicand % fq == 0 {
                radicand /= fq;
                outside *= f;
            }
            f += 1;
        }
        if negative {
            radicand = -radicand;
        }
        let scale = Number::rational(i64::try_from(outside).ok()?, d)?;
        if radicand == 1 {
            return Some(Rf::constant(scale));
        }
        let r = Number::int(i64::try_from(radicand).ok()?);
        let expr = Expr::pow(
            Expr::number(r.clone()),
            Expr::number(Number::rational(1, q as i64)?),
        );
        let id = root_atom(expr, Poly::constant(r), q);
        Some(Rf::atom(id).scale(&scale))
    }

    fn function(&mut self, f: Func, args: &[Expr]) -> Rf {
        let normal_args: Vec<Rf> = args.iter().map(|a| self.rf(*a)).collect();
        match (f, normal_args.as_slice()) {
            (Func::Sin, [a]) => self.trig(a).1,
            (Func::Cos, [a]) => self.trig(a).0,
            (Func::Tan, [a]) => {
                let (c, s) = self.trig(a);
                s.div(&c)
                    .unwrap_or_else(|| self.opaque(Expr::func(Func::Tan, vec![a.to_expr()])))
            }
            (Func::Exp, [a]) => self.exponential(a),
            (Func::Ln, [a]) => {
                // ln(exp(u)) = u for real u.
                let e = a.to_expr();
                if let Node::Func(Func::Exp, inner) = e.node() {
                    return self.rf(inner[0]);
                }
                if let Some(c) = a.as_constant() {
                    if c.is_float() && c.signum() > 0 {
                        return Rf::constant(Number::Float(c.to_f64().ln()));
                    }
                }
                self.opaque(Expr::func(Func::Ln, vec![e]))
            }
            (Func::Abs | Func::Sign, [a]) => {
                if let Some(c) = a.as_constant() {
                    return Rf::constant(if f == Func::Abs {
                        c.abs()
                    } else {
                        Number::int(c.signum() as i64)
                    });
                }
                // |−u| = |u|, sign(−u) = −sign(u): choose the sign of the argument so that its
                // leading term is positive.
                let flip = self.negative_lead(a);
                let arg = if flip { a.neg() } else { a.clone() };
                let r = self.opaque(Expr::func(f, vec![arg.to_expr()]));
                if flip && f == Func::Sign {
                    r.neg()
                } else {
                    r
                }
            }
            _ => {
                let constants: Option<Vec<f64>> = normal_args
                    .iter()
                    .map(|a| a.as_constant().filter(|c| c.is_float()).map(|c| c.to_f64()))
                    .collect();
                if let Some(v) = constants {
                    if let Some(x) = eval_float(f, &v) {
                        return Rf::constant(Number::Float(x));
                    }
                }
                let e = Expr::func(f, normal_args.iter().map(|a| a.to_expr()).collect());
                match e.node() {
                    Node::Func(..) => self.opaque(e),
                    _ => self.rf(e),
                }
            }
        }
    }

    fn negative_lead(&self, a: &Rf) -> bool {
        a.num
            .terms
            .iter()
            .max_by(|x, y| monomial_to_expr(&x.0).cmp_structure(monomial_to_expr(&y.0)))
            .is_some_and(|(_, c)| c.is_negative())
    }

    /// `(cos a, sin a)` of a normalised angle, expanded over the terms of the angle.
    pub(crate) fn trig(&mut self, angle: &Rf) -> (Rf, Rf) {
        let mut cos = Rf::one();
        let mut sin = Rf::zero();
        let den = angle.den.clone();
        let den_expr = if den.is_one() {
            None
        } else {
            Some(poly_to_expr(&den))
        };
        for (m, c) in &angle.num.terms {
            let (ct, st) = self.trig_of_term(m, c, den_expr);
            let new_cos = cos.mul(&ct).sub(&sin.mul(&st));
            let new_sin = sin.mul(&ct).add(&cos.mul(&st));
            cos = new_cos;
            sin = new_sin;
        }
        (cos, sin)
    }

    /// `(cos, sin)` of one term `c m / den` of an angle.
    fn trig_of_term(&mut self, m: &Monomial, c: &Number, den: Option<Expr>) -> (Rf, Rf) {
        let unit = match den {
            Some(d) => monomial_to_expr(m) * d.powi(-1),
            None => monomial_to_expr(m),
        };
        if c.is_float() {
            if m.is_empty() && den.is_none() {
                let x = c.to_f64();
                return (
                    Rf::constant(Number::Float(x.cos())),
                    Rf::constant(Number::Float(x.sin())),
                );
            }
            let (s, k) = trig_atoms(Expr::number(c.clone()) * unit);
            return (Rf::atom(k), Rf::atom(s));
        }
        let is_pi = unit == Expr::pi();
        let (n, q) = c.to_small_ratio().unwrap_or((1, 1));
        if is_pi {
            if let Some(exact) = exact_trig_of_pi_multiple(self, n, q) {
                return exact;
            }
        }
        // A numeric angle (`cos(3/10)`) is its own atom: writing it as a multiple of 1/10 is
        // as canonical but prints a triple-angle polynomial nobody wants to read.
        if m.is_empty() && den.is_none() {
            let (s_id, c_id) = trig_atoms(Expr::number(c.abs()));
            let sign = if c.is_negative() { -1 } else { 1 };
            return multiple_angle(&Rf::atom(c_id), &Rf::atom(s_id), sign);
        }
        // c = n/q: the angle unit is m/q, taken `n` times. A large multiple stays an angle of its
        // own (see `MAX_EXPANDED_MULTIPLE`); a negative one keeps the parity rule.
        let small = c.to_small_ratio().is_some() && n.unsigned_abs() <= MAX_EXPANDED_MULTIPLE;
        let (angle_unit, multiple) = if !small {
            (
                Expr::number(c.abs()) * unit,
                if c.is_negative() { -1 } else { 1 },
            )
        } else if q == 1 {
            (unit, n)
        } else {
            (unit * Expr::rational(1, q).unwrap_or_else(Expr::one), n)
        };
        let (s_id, c_id) = trig_atoms(angle_unit);
        let base_cos = Rf::atom(c_id);
        let base_sin = Rf::atom(s_id);
        multiple_angle(&base_cos, &base_sin, multiple)
    }

    /// `exp` of a normalised argument: `exp(Σ c_k m_k) = Π exp(m_k)^c_k` for integer `c_k`.
    fn exponential(&mut self, a: &Rf) -> Rf {
        if let Some(c) = a.as_constant() {
            if c.is_float() {
                return Rf::constant(Number::Float(c.to_f64().exp()));
            }
        }
        if !a.den.is_one() {
            return self.opaque(Expr::func(Func::Exp, vec![a.to_expr()]));
        }
        let mut acc = Rf::one();
        for (m, c) in &a.num.terms {
            let unit = monomial_to_expr(m);
            let r = match c.to_i64() {
                Some(k) if !m.is_empty() => {
                    let atom = Rf::atom(plain_atom(Expr::func(Func::Exp, vec![unit])));
                    atom.powi(k).unwrap_or_else(Rf::one)
                }
                _ => {
                    let e = Expr::number(c.clone()) * unit;
                    Rf::atom(plain_atom(Expr::func(Func::Exp, vec![e])))
                }
            };
            acc = acc.mul(&r);
        }
        acc
    }
}

/// The largest multiple `n` for which `sin nθ` and `cos nθ` are expanded into polynomials in
/// `sin θ`, `cos θ`. Beyond it `sin nθ` is an atom of its own: the expansion has degree `n` and
/// coefficients up to `2^(n−1)`, so it costs work growing with `n` (`sin(1000000 x)` never
/// finished) and evaluates with a cancellation error near `2^n ε` (a potential `1 − cos 60x`
/// evaluated to noise). Identities between `sin nθ` and `sin θ` are promised up to this bound.
pub(crate) const MAX_EXPANDED_MULTIPLE: u64 = 12;

/// `(cos nθ, sin nθ)` from `(cos θ, sin θ)` by binary powering of `cos θ + i sin θ`.
fn multiple_angle(c: &Rf, s: &Rf, n: i64) -> (Rf, Rf) {
    let (mut bc, mut bs) = (c.clone(), if n < 0 { s.neg() } else { s.clone() });
    let mut k = n.unsigned_abs();
    let (mut rc, mut rs) = (Rf::one(), Rf::zero());
    while k > 0 {
        if k & 1 == 1 {
            let nc = rc.mul(&bc).sub(&rs.mul(&bs));
            let ns = rs.mul(&bc).add(&rc.mul(&bs));
            rc = nc;
            rs = ns;
        }
        k >>= 1;
        if k > 0 {
            let nc = bc.mul(&bc).sub(&bs.mul(&bs));
            let ns = bs.mul(&bc).scale(&Number::int(2));
            bc = nc;
            bs = ns;
        }
    }
    (rc, rs)
}

/// Exact `(cos, sin)` of `n π / q` for `q` dividing 12 (multiples of π/6 and π/4).
fn exact_trig_of_pi_multiple(nz: &mut Normalizer, n: i64, q: i64) -> Option<(Rf, Rf)> {
    if 12 % q != 0 {
        return None;
    }
    // Angle in twelfths of π, reduced to [0, 24).
    let k = (n.checked_mul(12 / q)?).rem_euclid(24);
    let half = Number::rational(1, 2)?;
    let sqrt = |nz: &mut Normalizer, v: i64| nz.root_of_number(&Number::int(v), 2);
    let s3_2 = sqrt(nz, 3)?.scale(&half);
    let s2_2 = sqrt(nz, 2)?.scale(&half);
    let h = Rf::constant(half.clone());
    let table = |k: i64| -> Option<(Rf, Rf)> {
        Some(match k {
            0 => (Rf::one(), Rf::zero()),
            2 => (s3_2.clone(), h.clone()),
            3 => (s2_2.clone(), s2_2.clone()),
            4 => (h.clone(), s3_2.clone()),
            6 => (Rf::zero(), Rf::one()),
            _ => return None,
        })
    };
    // Use symmetries to bring k into [0, 6].
    let (kk, cos_sign, sin_sign) = match k {
        0..=6 => (k, 1, 1),
        7..=12 => (12 - k, -1, 1),
        13..=18 => (k - 12, -1, -1),
        _ => (24 - k, 1, -1),
    };
    let (c, s) = table(kk)?;
    let c = if cos_sign < 0 { c.neg() } else { c };
    let s = if sin_sign < 0 { s.neg() } else { s };
    Some((c, s))
}

/// Numeric values of the functions at float arguments.
pub(crate) fn eval_float(f: Func, args: &[f64]) -> Option<f64> {
    let v = match (f, args) {
        (Func::Sin, [x]) => x.sin(),
        (Func::Cos, [x]) => x.cos(),
        (Func::Tan, [x]) => x.tan(),
        (Func::Asin, [x]) => x.asin(),
        (Func::Acos, [x]) => x.acos(),
        (Func::Atan, [x]) => x.atan(),
        (Func::Atan2, [y, x]) => y.atan2(*x),
        (Func::Exp, [x]) => x.exp(),
        (Func::Ln, [x]) => x.ln(),
        (Func::Abs, [x]) => x.abs(),
        (Func::Sign, [x]) => {
            if *x > 0.0 {
                1.0
            } else if *x < 0.0 {
                -1.0
            } else {
                0.0
            }
        }
        _ => return None,
    };
    v.is_finite().then_some(v)
}

// ---------------------------------------------------------------------------------------------
// Public entry points (through `Expr` methods).

fn normal_memo() -> &'static Mutex<FxHashMap<Expr, Expr>> {
    static MEMO: OnceLock<Mutex<FxHashMap<Expr, Expr>>> = OnceLock::new();
    MEMO.get_or_init(|| Mutex::new(FxHashMap::default()))
}

/// The working form of every expression [`from_rf`] has built. Mechanics differentiates the same
/// large normal forms many times (the Lagrangian once per rate and per coordinate); without this
/// each call would convert the whole tree back to polynomials.
fn rf_memo() -> &'static Mutex<FxHashMap<Expr, Arc<Rf>>> {
    static MEMO: OnceLock<Mutex<FxHashMap<Expr, Arc<Rf>>>> = OnceLock::new();
    MEMO.get_or_init(|| Mutex::new(FxHashMap::default()))
}

/// The remembered working form of a canonical expression, if [`from_rf`] built it.
pub(crate) fn cached_rf(e: Expr) -> Option<Arc<Rf>> {
    rf_memo()
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .get(&e)
        .cloned()
}

/// The normal form of `e` as an [`Rf`]; past a work limit, `e` itself as an opaque atom
/// (equal to its input, not canonical: see [`try_to_rf`]).
pub(crate) fn to_rf(e: Expr) -> Rf {
    try_to_rf(e).unwrap_or_else(|_| Rf::atom(plain_atom(e)))
}

/// The normal form of `e` as an [`Rf`], or the work limit it ran into.
pub(crate) fn try_to_rf(e: Expr) -> Result<Rf, WorkLimitError> {
    limits::guarded(|| Normalizer::default().rf(e))
}

/// The canonical expression of a normal form, remembered as its own normal form.
pub(crate) fn from_rf(r: &Rf) -> Expr {
    remember(r, || Arc::new(r.clone()))
}

/// [`from_rf`] of a shared working form, which is remembered without a copy.
pub(crate) fn from_shared_rf(r: &Arc<Rf>) -> Expr {
    remember(r, || Arc::clone(r))
}

fn remember(r: &Rf, shared: impl FnOnce() -> Arc<Rf>) -> Expr {
    let e = r.to_expr();
    normal_memo()
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .insert(e, e);
    // Small forms are cheap to rebuild; remembering only the large ones bounds the memory.
    if r.num.terms.len() + r.den.terms.len() > CACHED_RF_MIN_TERMS {
        rf_memo()
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .entry(e)
            .or_insert_with(shared);
    }
    e
}

/// `a ± b` in normal form when both are large normal forms with a remembered working form.
///
/// Adding two long sums as trees re-interns and re-sorts every term, and the next `normal()`
/// converts them all back; the equations of motion are built from such differences
/// (`d/dt ∂L/∂q̇ − ∂L/∂q`), so the operators take this shortcut. The result is the normal
/// form of the sum, which is also a canonical tree for it.
pub(crate) fn combine_normal_forms(a: Expr, b: Expr, subtract: bool) -> Option<Expr> {
    let ra = cached_rf(a)?;
    let rb = cached_rf(b)?;
    let sum = if subtract { ra.sub(&rb) } else { ra.add(&rb) };
    Some(from_rf(&sum))
}

/// Normal forms with more terms than this keep their working form (see [`rf_memo`]).
const CACHED_RF_MIN_TERMS: usize = 8;

impl Expr {
    /// The canonical normal form (see the module documentation of `normal`): equal
    /// expressions of the mechanics class give the identical `Expr`.
    ///
    /// Past a work limit ([`crate::WorkLimits`]) the expression is returned as it is: equal to
    /// its input but not canonical ([`Expr::try_normal`] reports the limit instead).
    pub fn normal(self) -> Expr {
        // Past a work limit the expression is its own (non-canonical) normal form; that is not
        // remembered, so raising the limits lets a later call finish.
        self.try_normal().unwrap_or(self)
    }

    /// The normal form, or the work limit ([`crate::WorkLimits`]) its expansion ran into.
    ///
    /// ```
    /// use cas::{Expr, WorkLimitError};
    /// let angle = Expr::add_all((0..21).map(|i| Expr::coordinate(&format!("q{i}"))));
    /// // 2²¹ products: past the default limit of 500 000 terms.
    /// assert!(matches!(angle.sin().try_normal(), Err(WorkLimitError::Terms { .. })));
    /// ```
    pub fn try_normal(self) -> Result<Expr, WorkLimitError> {
        if let Some(&n) = normal_memo()
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .get(&self)
        {
            return Ok(n);
        }
        let n = from_rf(&try_to_rf(self)?);
        normal_memo()
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .insert(self, n);
        Ok(n)
    }

    /// Whether the expression is identically zero (exact for the mechanics class). Past a work
    /// limit this is `false` unless the expression is literally zero; [`Expr::try_is_zero`]
    /// tells the two apart.
    pub fn is_zero(self) -> bool {
        to_rf(self).is_zero()
    }

    /// Whether the expression is identically zero, or the work limit its expansion ran into.
    pub fn try_is_zero(self) -> Result<bool, WorkLimitError> {
        Ok(try_to_rf(self)?.is_zero())
    }

    /// Whether two expressions are equal (exact for the mechanics class).
    pub fn equals(self, other: Expr) -> bool {
        self == other || (self - other).is_zero()
    }

    /// Numerator and denominator of the normal form.
    pub fn numer_denom(self) -> (Expr, Expr) {
        let r = to_rf(self);
        (
            from_rf(&Rf::from_poly(r.num.clone())),
            from_rf(&Rf::from_poly(r.den)),
        )
    }

    /// Whether the expression is the literal `π`.
    pub fn is_pi(self) -> bool {
        matches!(self.node(), Node::Constant(Constant::Pi))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
