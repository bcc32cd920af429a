//! Sparse multivariate polynomials over exact rationals in *atoms*, the working form behind the
//! normal form.
//!
//! An atom is an expression the polynomial treats as a variable: a symbol, `sin(a)` or `cos(a)`
//! of an angle `a`, a root `b^(1/q)`, or any other function application. Two rewriting rules
//! keep the representation canonical: `sin(a)^2 = 1 - cos(a)^2` (so `sin` never appears squared)
//! and `r^q = b` for a root `r = b^(1/q)`. With them, two equal polynomials of the class that
//! mechanics produces have identical term lists.
//!
//! Terms are kept sorted by a lexicographic monomial order on atom ids (the id of an atom is its
//! creation order, an implementation detail; printed output is ordered structurally elsewhere).
//! The module also provides exact division, pseudo-remainders and a recursive primitive-PRS
//! greatest common divisor, used to keep fractions in lowest terms.

use std::cmp::Ordering;
use std::sync::{Mutex, OnceLock, RwLock};

use rustc_hash::FxHashMap;
use smallvec::SmallVec;

use crate::expr::Expr;
use crate::limits;
use crate::number::Number;

/// An atom's id. The two high bits tell its kind, so the hot multiplication loop can tell
/// whether a rewriting rule applies without a table look-up.
pub(crate) type AtomId = u32;

const KIND_SHIFT: u32 = 30;
const KIND_PLAIN: u32 = 0;
const KIND_SIN: u32 = 1;
const KIND_ROOT: u32 = 2;
const INDEX_MASK: u32 = (1 << KIND_SHIFT) - 1;

/// What an atom is, for the rewriting rules and for differentiation.
#[derive(Clone, Debug)]
pub(crate) enum AtomKind {
    /// A variable with no rewriting rule.
    Plain,
    /// `sin(angle)`; `cos` is its partner for `sin² = 1 − cos²`.
    Sin { angle: Expr, cos: AtomId },
    /// `cos(angle)`.
    Cos { angle: Expr, sin: AtomId },
    /// `base^(1/q)` with `q ≥ 2`; `base` is a polynomial.
    Root { base: Poly, q: u32 },
}

#[derive(Clone, Debug)]
pub(crate) struct AtomInfo {
    pub(crate) expr: Expr,
    pub(crate) kind: AtomKind,
}

struct AtomTable {
    by_expr: FxHashMap<Expr, AtomId>,
    infos: Vec<AtomInfo>,
}

fn atom_table() -> &'static RwLock<AtomTable> {
    static TABLE: OnceLock<RwLock<AtomTable>> = OnceLock::new();
    TABLE.get_or_init(|| {
        RwLock::new(AtomTable {
            by_expr: FxHashMap::default(),
            infos: Vec::new(),
        })
    })
}

/// Serialises atom creation so that a `sin`/`cos` pair is made together.
fn creation_lock() -> &'static Mutex<()> {
    static LOCK: OnceLock<Mutex<()>> = OnceLock::new();
    LOCK.get_or_init(|| Mutex::new(()))
}

fn read_table() -> std::sync::RwLockReadGuard<'static, AtomTable> {
    atom_table().read().unwrap_or_else(|e| e.into_inner())
}

fn push_atom(table: &mut AtomTable, info: AtomInfo, kind_bits: u32) -> AtomId {
    let id = (table.infos.len() as u32) | (kind_bits << KIND_SHIFT);
    table.by_expr.insert(info.expr, id);
    table.infos.push(info);
    id
}

/// The atom whose expression is `expr`, made with `kind` (and the id's kind bits) the first
/// time it is asked for.
fn intern_atom(expr: Expr, kind: impl FnOnce() -> AtomKind, kind_bits: u32) -> AtomId {
    debug_assert!(
        expr.as_number().is_none(),
        "a number is not an atom: {expr:?}"
    );
    if let Some(&id) = read_table().by_expr.get(&expr) {
        return id;
    }
    let _g = creation_lock().lock().unwrap_or_else(|e| e.into_inner());
    let mut t = atom_table().write().unwrap_or_else(|e| e.into_inner());
    if let Some(&id) = t.by_expr.get(&expr) {
        return id;
    }
    push_atom(&mut t, AtomInfo { expr, kind: kind() }, kind_bits)
}

/// The atom for a plain variable (a symbol, a constant, an opaque function application).
pub(crate) fn plain_atom(expr: Expr) -> AtomId {
    intern_atom(expr, || AtomKind::Plain, KIND_PLAIN)
}

/// The atoms `(sin(angle), cos(angle))`.
pub(crate) fn trig_atoms(angle: Expr) -> (AtomId, AtomId) {
    let sin_expr = angle.sin();
    let cos_expr = angle.cos();
    {
        let t = read_table();
        if let (Some(&s), Some(&c)) = (t.by_expr.get(&sin_expr), t.by_expr.get(&cos_expr)) {
            return (s, c);
        }
    }
    let _g = creation_lock().lock().unwrap_or_else(|e| e.into_inner());
    let mut t = atom_table().write().unwrap_or_else(|e| e.into_inner());
    if let (Some(&s), Some(&c)) = (t.by_expr.get(&sin_expr), t.by_expr.get(&cos_expr)) {
        return (s, c);
    }
    let next = t.infos.len() as u32;
    let sin_id = next | (KIND_SIN << KIND_SHIFT);
    let cos_id = next + 1;
    push_atom(
        &mut t,
        AtomInfo {
            expr: sin_expr,
            kind: AtomKind::Sin { angle, cos: cos_id },
        },
        KIND_SIN,
    );
    push_atom(
        &mut t,
        AtomInfo {
            expr: cos_expr,
            kind: AtomKind::Cos { angle, sin: sin_id },
        },
        KIND_PLAIN,
    );
    (sin_id, cos_id)
}

/// The atom `base^(1/q)` whose expression is `expr`.
pub(crate) fn root_atom(expr: Expr, base: Poly, q: u32) -> AtomId {
    intern_atom(expr, || AtomKind::Root { base, q }, KIND_ROOT)
}

/// The information about an atom.
pub(crate) fn atom_info(id: AtomId) -> AtomInfo {
    read_table().infos[(id & INDEX_MASK) as usize].clone()
}

/// The position of an atom in creation order (its id without the kind bits).
pub(crate) fn atom_index(id: AtomId) -> u32 {
    id & INDEX_MASK
}

/// The expression of an atom.
pub(crate) fn atom_expr(id: AtomId) -> Expr {
    read_table().infos[(id & INDEX_MASK) as usize].expr
}

/// The expressions of several atoms, under one lock.
pub(crate) fn atom_exprs(ids: &[AtomId]) -> Vec<Expr> {
    let table = read_table();
    ids.iter()
        .map(|&id| table.infos[(id & INDEX_MASK) as usize].expr)
        .collect()
}

pub(crate) fn needs_rewrite(id: AtomId, exp: u32) -> bool {
    match id >> KIND_SHIFT {
        KIND_SIN => exp >= 2,
        KIND_ROOT => exp >= 2, // checked against q on the slow path
        _ => false,
    }
}

/// A monomial: `(atom, exponent)` pairs sorted by atom id, exponents positive. Eight pairs
/// inline: the terms of a chain's kinetic energy (`m l_j l_k q̇_j q̇_k cos θ_j cos θ_k`) have six
/// or seven atoms, and a spilled monomial costs an allocation per term in every operation.
pub(crate) type Monomial = SmallVec<[(AtomId, u32); 8]>;

/// A sparse polynomial: terms sorted by decreasing monomial (lexicographic on atom ids, the
/// smallest id most significant), no zero coefficients.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Default)]
pub(crate) struct Poly {
    pub(crate) terms: Vec<(Monomial, Number)>,
}

/// A monomial ordered by [`cmp_monomial`], as a key of ordered maps.
#[derive(PartialEq, Eq)]
struct Ordered(Monomial);

impl PartialOrd for Ordered {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Ordered {
    fn cmp(&self, other: &Self) -> Ordering {
        cmp_monomial(&self.0, &other.0)
    }
}

/// Lexicographic comparison of sparse exponent vectors (the smallest atom id is the most
/// significant variable).
pub(crate) fn cmp_monomial(a: &Monomial, b: &Monomial) -> Ordering {
    for (&(xa, ea), &(xb, eb)) in a.iter().zip(b.iter()) {
        if xa != xb {
            // The one holding the smaller (more significant) atom is larger.
            return if (xa & INDEX_MASK) < (xb & INDEX_MASK) {
                Ordering::Greater
            } else {
                Ordering::Less
            };
        }
        if ea != eb {
            return ea.cmp(&eb);
        }
    }
    // Equal on the shorter one's atoms: the one with more atoms is larger.
    a.len().cmp(&b.len())
}

fn key(id: AtomId) -> u32 {
    id & INDEX_MASK
}

pub(crate) fn mul_monomials(a: &Monomial, b: &Monomial) -> Monomial {
    if a.len() + b.len() <= MERGE_BUFFER {
        return mul_factor_slices(a, b);
    }
    let mut out = Monomial::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        let (xa, ea) = a[i];
        let (xb, eb) = b[j];
        match key(xa).cmp(&key(xb)) {
            Ordering::Less => {
                out.push((xa, ea));
                i += 1;
            }
            Ordering::Greater => {
                out.push((xb, eb));
                j += 1;
            }
            Ordering::Equal => {
                out.push((xa, ea + eb));
                i += 1;
                j += 1;
            }
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
    out
}

/// The longest product [`mul_factor_slices`] merges on the stack.
pub(crate) const MERGE_BUFFER: usize = 16;

/// [`mul_monomials`] of two factor lists with at most [`MERGE_BUFFER`] factors together,
/// merged into a buffer on the stack and copied once: pushing onto the small vector checked
/// its capacity and whether it had spilled at every factor, which made this merge of two
/// short lists cost hundreds of instructions (the derivatives of a chain's Lagrangian form one
/// product per factor of every term).
pub(crate) fn mul_factor_slices(a: &[(AtomId, u32)], b: &[(AtomId, u32)]) -> Monomial {
    let mut out = [(0u32, 0u32); MERGE_BUFFER];
    let (mut i, mut j, mut k) = (0, 0, 0);
    while i < a.len() && j < b.len() {
        let (xa, ea) = a[i];
        let (xb, eb) = b[j];
        out[k] = match key(xa).cmp(&key(xb)) {
            Ordering::Less => {
                i += 1;
                (xa, ea)
            }
            Ordering::Greater => {
                j += 1;
                (xb, eb)
            }
            Ordering::Equal => {
                i += 1;
                j += 1;
                (xa, ea + eb)
            }
        };
        k += 1;
    }
    for &f in a[i..].iter().chain(&b[j..]) {
        out[k] = f;
        k += 1;
    }
    Monomial::from_slice(&out[..k])
}

/// `a / b` when every exponent of `b` is at most the one in `a`.
fn div_monomials(a: &Monomial, b: &Monomial) -> Option<Monomial> {
    let mut out = Monomial::with_capacity(a.len());
    let mut j = 0;
    for &(x, e) in a {
        if j < b.len() && b[j].0 == x {
            let f = b[j].1;
            if f > e {
                return None;
            }
            if e > f {
                out.push((x, e - f));
            }
            j += 1;
        } else if j < b.len() && key(b[j].0) < key(x) {
            return None;
        } else {
            out.push((x, e));
        }
    }
    (j == b.len()).then_some(out)
}

fn degree_in(m: &Monomial, x: AtomId) -> u32 {
    m.iter().find(|(a, _)| *a == x).map_or(0, |(_, e)| *e)
}

impl Poly {
    /// The zero polynomial.
    pub(crate) fn zero() -> Poly {
        Poly { terms: Vec::new() }
    }

    /// A constant.
    pub(crate) fn constant(c: Number) -> Poly {
        if c.is_exact_zero() {
            Poly::zero()
        } else {
            Poly {
                terms: vec![(Monomial::new(), c)],
            }
        }
    }

    /// One.
    pub(crate) fn one() -> Poly {
        Poly::constant(Number::ONE)
    }

    /// A single atom.
    pub(crate) fn atom(id: AtomId) -> Poly {
        let mut m = Monomial::new();
        m.push((id, 1));
        Poly {
            terms: vec![(m, Number::ONE)],
        }
    }

    /// `atom^k`, with the rewriting rules applied.
    pub(crate) fn atom_pow(id: AtomId, k: u32) -> Poly {
        if k == 0 {
            return Poly::one();
        }
        let mut m = Monomial::new();
        m.push((id, k));
        if needs_rewrite(id, k) {
            rewrite_term(m, Number::ONE)
        } else {
            Poly {
                terms: vec![(m, Number::ONE)],
            }
        }
    }

    pub(crate) fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }

    /// The constant value when the polynomial has no atoms.
    pub(crate) fn as_constant(&self) -> Option<Number> {
        match self.terms.as_slice() {
            [] => Some(Number::ZERO),
            [(m, c)] if m.is_empty() => Some(c.clone()),
            _ => None,
        }
    }

    pub(crate) fn is_one(&self) -> bool {
        matches!(self.terms.as_slice(), [(m, c)] if m.is_empty() && c.is_exact_one())
    }

    /// Sorts and merges an unordered list of terms.
    pub(crate) fn from_terms(mut terms: Vec<(Monomial, Number)>) -> Poly {
        // Stable in effect, so that equal monomials add up in the order they came (float
        // coefficients); sorted by packed keys and merged as the terms move into place.
        crate::term_order::sort_and_merge(&mut terms);
        terms.retain(|(_, c)| !c.is_exact_zero());
        Poly { terms }
    }

    pub(crate) fn add(&self, other: &Poly) -> Poly {
        self.merge(other, false)
    }

    /// `self + other`, or `self − other` when `negate`: one merge of the sorted terms (the
    /// difference negated `other` into a copy first, and merged that).
    fn merge(&self, other: &Poly, negate: bool) -> Poly {
        let sign = |c: &Number| if negate { c.neg() } else { c.clone() };
        if self.is_zero() {
            return if negate { other.neg() } else { other.clone() };
        }
        if other.is_zero() {
            return self.clone();
        }
        limits::spend((self.terms.len() + other.terms.len()) as u64);
        let mut out = Vec::with_capacity(self.terms.len() + other.terms.len());
        let (mut i, mut j) = (0, 0);
        let (a, b) = (&self.terms, &other.terms);
        while i < a.len() && j < b.len() {
            match cmp_monomial(&a[i].0, &b[j].0) {
                Ordering::Greater => {
                    out.push(a[i].clone());
                    i += 1;
                }
                Ordering::Less => {
                    out.push((b[j].0.clone(), sign(&b[j].1)));
                    j += 1;
                }
                Ordering::Equal => {
                    let c = a[i].1.add(&sign(&b[j].1));
                    if !c.is_exact_zero() {
                        out.push((a[i].0.clone(), c));
                    }
                    i += 1;
                    j += 1;
                }
            }
        }
        out.extend_from_slice(&a[i..]);
        out.extend(b[j..].iter().map(|(m, c)| (m.clone(), sign(c))));
        Poly { terms: out }
    }

    pub(crate) fn neg(&self) -> Poly {
        Poly {
            terms: self
                .terms
                .iter()
                .map(|(m, c)| (m.clone(), c.neg()))
                .collect(),
        }
    }

    pub(crate) fn sub(&self, other: &Poly) -> Poly {
        self.merge(other, true)
    }

    pub(crate) fn scale(&self, c: &Number) -> Poly {
        if c.is_exact_zero() {
            return Poly::zero();
        }
        Poly {
            terms: self
                .terms
                .iter()
                .map(|(m, k)| (m.clone(), k.mul(c)))
                .collect(),
        }
    }

    /// The product with the rewriting rules (`sin² = 1 − cos²`, `r^q = b`) applied.
    pub(crate) fn mul(&self, other: &Poly) -> Poly {
        self.mul_with(other, true)
    }

    /// The product treating every atom as an independent variable (for GCD computations).
    pub(crate) fn mul_raw(&self, other: &Poly) -> Poly {
        self.mul_with(other, false)
    }

    fn mul_with(&self, other: &Poly, rewrite: bool) -> Poly {
        if self.is_zero() || other.is_zero() || limits::exceeded() {
            return Poly::zero();
        }
        if let Some(c) = self.as_constant() {
            return other.scale(&c);
        }
        if let Some(c) = other.as_constant() {
            return self.scale(&c);
        }
        let (small, large) = if self.terms.len() <= other.terms.len() {
            (self, other)
        } else {
            (other, self)
        };
        let weight = coefficient_weight(small) * coefficient_weight(large);
        let work = (small.terms.len() as u64)
            .saturating_mul(large.terms.len() as u64)
            .saturating_mul(weight);
        if !limits::spend(work) {
            return Poly::zero();
        }
        if let [(mono, coefficient)] = small.terms.as_slice() {
            if !limits::terms_ok(large.terms.len()) {
                return Poly::zero();
            }
            // Multiplying by one term keeps the lexicographic order of the other's terms, so
            // no hashing or sorting is needed unless a rewriting rule applies.
            let terms: Vec<(Monomial, Number)> = large
                .terms
                .iter()
                .map(|(m, c)| (mul_monomials(m, mono), c.mul(coefficient)))
                .collect();
            if !rewrite
                || !terms
                    .iter()
                    .any(|(m, _)| m.iter().any(|&(x, e)| needs_rewrite(x, e)))
            {
                return Poly { terms };
            }
        }
        // A product has at most |a| |b| terms; its work is bounded by a multiple of the limit.
        if !limits::terms_ok(small.terms.len().saturating_mul(large.terms.len()) / 64) {
            return Poly::zero();
        }
        let mut acc: FxHashMap<Monomial, Number> = FxHashMap::default();
        acc.reserve((small.terms.len() * large.terms.len()).min(1 << 16));
        // Products are gathered raw first and each distinct monomial is rewritten once: the
        // square of a velocity component has many products that share a monomial, and rewriting
        // each product (`sin²θ1 sin²θ2 → (1 − cos²θ1)(1 − cos²θ2)`) before merging multiplied the
        // work by the size of the rewritten form.
        // A square (`pow` squares its base; kinetic energies square velocity components) needs
        // each cross product once, doubled.
        let square = std::ptr::eq(self, other);
        let two = Number::int(2);
        for (i, (ma, ca)) in small.terms.iter().enumerate() {
            if square {
                accumulate(&mut acc, mul_monomials(ma, ma), ca.mul(ca));
                let twice = ca.mul(&two);
                for (mb, cb) in &large.terms[i + 1..] {
                    accumulate(&mut acc, mul_monomials(ma, mb), twice.mul(cb));
                }
            } else {
                for (mb, cb) in &large.terms {
                    accumulate(&mut acc, mul_monomials(ma, mb), ca.mul(cb));
                }
            }
            if !limits::terms_ok(acc.len()) {
                return Poly::zero();
            }
        }
        if !rewrite {
            return Poly::from_terms(acc.into_iter().collect());
        }
        let mut terms = Vec::with_capacity(acc.len());
        let mut rewritten: FxHashMap<Monomial, Number> = FxHashMap::default();
        for (m, c) in acc {
            if c.is_exact_zero() {
                continue;
            }
            if m.iter().any(|&(x, e)| needs_rewrite(x, e)) {
                for (rm, rc) in rewrite_term(m, c).terms {
                    accumulate(&mut rewritten, rm, rc);
                }
            } else {
                terms.push((m, c));
            }
        }
        terms.extend(rewritten);
        if !limits::terms_ok(terms.len()) {
            return Poly::zero();
        }
        Poly::from_terms(terms)
    }

    /// `self^k`.
    pub(crate) fn pow(&self, k: u32) -> Poly {
        // A single plain term stays one term; anything else (a sum, or a `sin` or root that the
        // rewriting rules turn into a sum) grows with the degree.
        let grows = self.terms.len() > 1
            || self
                .terms
                .iter()
                .any(|(m, _)| m.iter().any(|&(x, _)| needs_rewrite(x, 2)));
        if grows {
            let degree = self
                .terms
                .iter()
                .map(|(m, _)| m.iter().map(|&(_, e)| u64::from(e)).sum::<u64>())
                .max()
                .unwrap_or(0);
            if !limits::degree_ok(degree.saturating_mul(u64::from(k))) {
                return Poly::zero();
            }
        }
        if let Some(p) = self.binomial_pow(k) {
            return p;
        }
        if let [(m, c)] = self.terms.as_slice() {
            // One term: its power is one term, rewritten once (`sin^k` becomes
            // `sin^(k mod 2) (1 − cos²)^(k div 2)` by the binomial rule, not by squaring sums).
            // The coefficient's power has about `k` times its size.
            if !c.is_one() && !limits::spend(u64::from(k) * c.size_hint() as u64) {
                return Poly::zero();
            }
            let exponents: Option<Monomial> = m
                .iter()
                .map(|&(x, e)| Some((x, e.checked_mul(k)?)))
                .collect();
            if let (Some(m), Some(c)) = (exponents, c.powi(i64::from(k))) {
                return rewrite_term(m, c);
            }
        }
        let mut result = Poly::one();
        let mut base = self.clone();
        let mut e = k;
        while e > 0 {
            if e & 1 == 1 {
                result = result.mul(&base);
            }
            e >>= 1;
            if e > 0 {
                base = base.mul(&base);
            }
        }
        result
    }

    /// `(a + b)^k = Σ C(k, i) a^i b^(k−i)` for two terms free of rewriting rules: `k + 1`
    /// terms with `O(k)` coefficient products. Binary powering squares dense polynomials
    /// (`k²/2` products of coefficients with up to `k` bits; `sin(x)^10000`, that is
    /// `(1 − cos² x)^5000`, took minutes). `None` when the rule does not apply.
    fn binomial_pow(&self, k: u32) -> Option<Poly> {
        let [(ma, ca), (mb, cb)] = self.terms.as_slice() else {
            return None;
        };
        let plain = |m: &Monomial| m.iter().all(|&(x, _)| x >> KIND_SHIFT == KIND_PLAIN);
        if k < 3 || !plain(ma) || !plain(mb) || ca.is_float() || cb.is_float() {
            return None;
        }
        let top = ma.iter().chain(mb).map(|&(_, e)| e).max().unwrap_or(0);
        top.checked_mul(k)?;
        let power = |m: &Monomial, i: u32| -> Monomial {
            if i == 0 {
                return Monomial::new();
            }
            m.iter().map(|&(x, e)| (x, e * i)).collect()
        };
        // Coefficient powers of `cb` from the top down, so each term costs two products.
        let mut cb_powers = Vec::with_capacity(k as usize + 1);
        let mut c = Number::ONE;
        for _ in 0..=k {
            cb_powers.push(c.clone());
            c = c.mul(cb);
        }
        if !limits::spend(u64::from(k) * cb_powers[k as usize].size_hint() as u64) {
            return Some(Poly::zero());
        }
        let mut terms = Vec::with_capacity(k as usize + 1);
        let (mut binomial, mut ca_power) = (Number::ONE, Number::ONE);
        for i in 0..=k {
            let coefficient = binomial.mul(&ca_power).mul(&cb_powers[(k - i) as usize]);
            terms.push((mul_monomials(&power(ma, i), &power(mb, k - i)), coefficient));
            binomial = binomial
                .mul(&Number::int(i64::from(k - i)))
                .div(&Number::int(i64::from(i) + 1))?;
            ca_power = ca_power.mul(ca);
        }
        Some(Poly::from_terms(terms))
    }

    /// The atoms that occur, sorted by id.
    pub(crate) fn atoms(&self) -> Vec<AtomId> {
        let mut v: Vec<AtomId> = self
            .terms
            .iter()
            .flat_map(|(m, _)| m.iter().map(|(x, _)| *x))
            .collect();
        v.sort_unstable_by_key(|x| key(*x));
        v.dedup();
        v
    }

    /// Whether every atom is free of rewriting rules (no `sin`, no root) and every coefficient
    /// exact: a product with such a polynomial is the plain product of polynomials in
    /// `ℚ[atoms]`, where the usual divisibility arguments hold.
    pub(crate) fn is_plain_exact(&self) -> bool {
        self.terms
            .iter()
            .all(|(m, c)| !c.is_float() && m.iter().all(|&(x, _)| x >> KIND_SHIFT == KIND_PLAIN))
    }

    pub(crate) fn contains_atom(&self, x: AtomId) -> bool {
        self.terms
            .iter()
            .any(|(m, _)| m.iter().any(|(a, _)| *a == x))
    }

    pub(crate) fn degree(&self, x: AtomId) -> u32 {
        self.terms
            .iter()
            .map(|(m, _)| degree_in(m, x))
            .max()
            .unwrap_or(0)
    }

    /// The coefficients in `x`: `self = Σ c_k x^k`, as `(k, c_k)` with `c_k` free of `x`.
    pub(crate) fn coefficients_in(&self, x: AtomId) -> Vec<(u32, Poly)> {
        let mut by_degree: FxHashMap<u32, Vec<(Monomial, Number)>> = FxHashMap::default();
        for (m, c) in &self.terms {
            let d = degree_in(m, x);
            let rest: Monomial = m.iter().filter(|(a, _)| *a != x).copied().collect();
            by_degree.entry(d).or_default().push((rest, c.clone()));
        }
        let mut v: Vec<(u32, Poly)> = by_degree
            .into_iter()
            .map(|(d, t)| (d, Poly::from_terms(t)))
            .collect();
        v.sort_by_key(|(d, _)| std::cmp::Reverse(*d));
        v
    }

    /// The leading coefficient in `x` (the coefficient of its highest power).
    fn leading_coefficient_in(&self, x: AtomId) -> (u32, Poly) {
        self.coefficients_in(x)
            .into_iter()
            .next()
            .unwrap_or((0, Poly::zero()))
    }

    /// `self * x^k`.
    fn shift(&self, x: AtomId, k: u32) -> Poly {
        if k == 0 {
            return self.clone();
        }
        let mut xm = Monomial::new();
        xm.push((x, k));
        Poly {
            terms: self
                .terms
                .iter()
                .map(|(m, c)| (mul_monomials(m, &xm), c.clone()))
                .collect(),
        }
    }

    /// The exact quotient `self / divisor`, or `None` when the division leaves a remainder.
    pub(crate) fn div_exact(&self, divisor: &Poly) -> Option<Poly> {
        if divisor.is_zero() {
            return None;
        }
        if let Some(c) = divisor.as_constant() {
            return Some(self.scale(&c.recip()?));
        }
        let (lead_m, lead_c) = divisor.terms.first()?;
        let lead_inv = lead_c.recip()?;
        // The remainder in an ordered map: each quotient term updates only the terms it touches
        // (subtracting from the whole remainder at each step made a division quadratic in the
        // size of the dividend).
        let mut rem: std::collections::BTreeMap<Ordered, Number> = self
            .terms
            .iter()
            .map(|(m, c)| (Ordered(m.clone()), c.clone()))
            .collect();
        let mut quotient: Vec<(Monomial, Number)> = Vec::new();
        while let Some((Ordered(m), c)) = rem.pop_last() {
            let qm = div_monomials(&m, lead_m)?;
            let qc = c.mul(&lead_inv);
            for (dm, dc) in &divisor.terms[1..] {
                let key = Ordered(mul_monomials(dm, &qm));
                let delta = dc.mul(&qc).neg();
                match rem.entry(key) {
                    std::collections::btree_map::Entry::Occupied(mut o) => {
                        let v = o.get().add(&delta);
                        if v.is_exact_zero() {
                            o.remove();
                        } else {
                            *o.get_mut() = v;
                        }
                    }
                    std::collections::btree_map::Entry::Vacant(v) => {
                        v.insert(delta);
                    }
                }
            }
            quotient.push((qm, qc));
            if quotient.len() > 1_000_000 || !limits::spend(divisor.terms.len() as u64) {
                return None;
            }
        }
        Some(Poly::from_terms(quotient))
    }

    /// The greatest common divisor of the monomials of `self` and `other` (no coefficient).
    fn monomial_gcd_with(&self, mut g: Monomial) -> Monomial {
        for (m, _) in &self.terms {
            g.retain(|(x, e)| {
                let d = degree_in(m, *x);
                *e = (*e).min(d);
                *e > 0
            });
            if g.is_empty() {
                break;
            }
        }
        g
    }

    /// The rational content (gcd of the coefficients) with the sign of the leading term, so
    /// that `self / content` has integer coefficients with gcd 1 and a positive leading one.
    pub(crate) fn content(&self) -> Number {
        let mut g = Number::ZERO;
        limits::spend(self.terms.len() as u64 * coefficient_weight(self));
        for (_, c) in &self.terms {
            if c.is_float() {
                return Number::ONE;
            }
            g = g.gcd(c);
        }
        if g.is_zero() {
            return Number::ONE;
        }
        match self.terms.first() {
            Some((_, c)) if c.is_negative() => g.neg(),
            _ => g,
        }
    }

    /// `self` divided by its content.
    pub(crate) fn primitive(&self) -> Poly {
        let c = self.content();
        match c.recip() {
            Some(r) if !c.is_one() => self.scale(&r),
            _ => self.clone(),
        }
    }
}

/// The cost of one coefficient product relative to small numbers: the size of a typical big
/// coefficient of `p` (the first, middle and last terms; the middle of a binomial power holds
/// its largest coefficients), in 64-bit words.
fn coefficient_weight(p: &Poly) -> u64 {
    let t = &p.terms;
    if t.is_empty() {
        return 1;
    }
    [0, t.len() / 2, t.len() - 1]
        .iter()
        .map(|&i| t[i].1.size_hint() as u64)
        .max()
        .unwrap_or(1)
}

/// Adds `c m` to a map of terms.
fn accumulate(acc: &mut FxHashMap<Monomial, Number>, m: Monomial, c: Number) {
    match acc.get_mut(&m) {
        Some(v) => *v = v.add(&c),
        None => {
            acc.insert(m, c);
        }
    }
}

/// Applies `sin² = 1 − cos²` and `r^q = b` to one term.
pub(crate) fn rewrite_term(m: Monomial, c: Number) -> Poly {
    if let Some(p) = rewrite_sin_squares(&m, &c) {
        return p;
    }
    let mut plain = Monomial::new();
    let mut factors: Vec<Poly> = Vec::new();
    for &(x, e) in &m {
        match x >> KIND_SHIFT {
            KIND_SIN if e >= 2 => {
                let cos = match atom_info(x).kind {
                    AtomKind::Sin { cos, .. } => cos,
                    _ => unreachable!("an id with the sin bit is a sin atom"),
                };
                // sin^e = sin^(e mod 2) (1 − cos²)^(e div 2)
                if e % 2 == 1 {
                    plain.push((x, 1));
                }
                let one_minus_cos2 = Poly::one().sub(&Poly::atom_pow(cos, 2));
                factors.push(one_minus_cos2.pow(e / 2));
            }
            KIND_ROOT => {
                let (base, q) = match atom_info(x).kind {
                    AtomKind::Root { base, q } => (base, q),
                    _ => unreachable!("an id with the root bit is a root atom"),
                };
                if e % q != 0 {
                    plain.push((x, e % q));
                }
                if e >= q {
                    factors.push(base.pow(e / q));
                }
            }
            _ => plain.push((x, e)),
        }
    }
    let mut p = Poly {
        terms: vec![(plain, c)],
    };
    for f in factors {
        p = p.mul(&f);
    }
    p
}

/// [`rewrite_term`] for a term whose only rewriting is `sin²` or `sin³` factors (the terms of
/// a product of reduced polynomials): each `sin² = 1 − cos²` doubles the list of terms, and
/// the products are distinct monomials, so they are formed directly, without the general
/// product's hashing. `None` for anything else (roots, higher powers).
fn rewrite_sin_squares(m: &Monomial, c: &Number) -> Option<Poly> {
    let mut plain = Monomial::new();
    let mut cosines: SmallVec<[AtomId; 4]> = SmallVec::new();
    for &(x, e) in m {
        match x >> KIND_SHIFT {
            KIND_SIN if e >= 4 => return None,
            KIND_SIN if e >= 2 => {
                let AtomKind::Sin { cos, .. } = atom_info(x).kind else {
                    return None;
                };
                if e == 3 {
                    plain.push((x, 1));
                }
                cosines.push(cos);
            }
            KIND_ROOT => return None,
            _ => plain.push((x, e)),
        }
    }
    let mut terms = vec![(plain, c.clone())];
    for cos in cosines {
        let square: Monomial = smallvec::smallvec![(cos, 2)];
        let mut next = Vec::with_capacity(terms.len() * 2);
        for (mono, coefficient) in terms {
            next.push((mul_monomials(&mono, &square), coefficient.neg()));
            next.push((mono, coefficient));
        }
        terms = next;
    }
    Some(Poly::from_terms(terms))
}

thread_local! {
    /// Work left for the GCD computation under way (in coefficient operations), and how deep
    /// its recursion is. Remainder sequences in many variables can swell without bound; when
    /// the budget is spent the computation returns a trivial common divisor, which is always
    /// correct: the fraction keeps its value and is only less reduced.
    static GCD_WORK: std::cell::Cell<(i64, u32)> = const { std::cell::Cell::new((0, 0)) };
}

/// Coefficient operations one top-level GCD may spend.
const GCD_BUDGET: i64 = 300_000;

fn gcd_budget_spent() -> bool {
    GCD_WORK.with(|w| w.get().0 <= 0)
}

fn spend_gcd_work(ops: usize) {
    limits::spend(ops as u64);
    GCD_WORK.with(|w| {
        let (left, depth) = w.get();
        w.set((left - ops as i64, depth));
    });
}

/// The greatest common divisor of two polynomials (atoms as independent variables), made
/// primitive with a positive leading coefficient. `gcd(0, 0) = 0`.
pub(crate) fn gcd(a: &Poly, b: &Poly) -> Poly {
    GCD_WORK.with(|w| {
        let (left, depth) = w.get();
        w.set((if depth == 0 { GCD_BUDGET } else { left }, depth + 1));
    });
    let g = gcd_inner(a, b);
    GCD_WORK.with(|w| {
        let (left, depth) = w.get();
        w.set((left, depth.saturating_sub(1)));
    });
    g
}

fn gcd_inner(a: &Poly, b: &Poly) -> Poly {
    if a.is_zero() {
        return b.primitive();
    }
    if b.is_zero() {
        return a.primitive();
    }
    if a.as_constant().is_some() || b.as_constant().is_some() {
        return Poly::one();
    }
    if a.terms.iter().chain(&b.terms).any(|(_, c)| c.is_float()) {
        // Floats have no exact gcd; only cancel common monomials.
        let g = b.monomial_gcd_with(a.monomial_gcd_with(a.terms[0].0.clone()));
        return Poly {
            terms: vec![(g, Number::ONE)],
        };
    }
    // Pull out the common monomial factor first: it is cheap and the usual case.
    let start = a.terms[0].0.clone();
    let mono = b.monomial_gcd_with(a.monomial_gcd_with(start));
    let (a, b) = if mono.is_empty() {
        (a.clone(), b.clone())
    } else {
        let m = Poly {
            terms: vec![(mono.clone(), Number::ONE)],
        };
        (
            a.div_exact(&m).unwrap_or_else(|| a.clone()),
            b.div_exact(&m).unwrap_or_else(|| b.clone()),
        )
    };
    let g = gcd_monomial_free(&a, &b, 0);
    let mono_poly = Poly {
        terms: vec![(mono, Number::ONE)],
    };
    g.mul_raw(&mono_poly).primitive()
}

fn gcd_monomial_free(a: &Poly, b: &Poly, depth: usize) -> Poly {
    if a.is_zero() {
        return b.primitive();
    }
    if b.is_zero() {
        return a.primitive();
    }
    if a.as_constant().is_some() || b.as_constant().is_some() || depth > 64 || gcd_budget_spent() {
        return Poly::one();
    }
    if a.terms.len() == 1 || b.terms.len() == 1 {
        // A monomial and a polynomial share only monomial factors, and `gcd` removed the
        // common monomial before calling here.
        return Poly::one();
    }
    // Fast path: one divides the other.
    if a.terms.len() <= b.terms.len() {
        if b.div_exact(a).is_some() {
            return a.primitive();
        }
    } else if a.div_exact(b).is_some() {
        return b.primitive();
    }
    let va = a.atoms();
    let vb = b.atoms();
    // A variable in only one of them: the gcd divides every coefficient in that variable.
    if let Some(&x) = va.iter().find(|x| !vb.contains(x)) {
        let mut g = b.clone();
        for (_, c) in a.coefficients_in(x) {
            g = gcd(&g, &c);
            if g.as_constant().is_some() {
                return Poly::one();
            }
        }
        return g;
    }
    if let Some(&x) = vb.iter().find(|x| !va.contains(x)) {
        let mut g = a.clone();
        for (_, c) in b.coefficients_in(x) {
            g = gcd(&g, &c);
            if g.as_constant().is_some() {
                return Poly::one();
            }
        }
        return g;
    }
    // Main variable: the one of least degree keeps the remainder sequence short.
    let x = *va
        .iter()
        .min_by_key(|x| a.degree(**x).max(b.degree(**x)))
        .expect("non-constant polynomials have atoms");
    let content_a = content_in(a, x, depth);
    let content_b = content_in(b, x, depth);
    let content = gcd(&content_a, &content_b);
    let mut p = a.div_exact(&content_a).unwrap_or_else(|| a.clone());
    let mut q = b.div_exact(&content_b).unwrap_or_else(|| b.clone());
    if p.degree(x) < q.degree(x) {
        std::mem::swap(&mut p, &mut q);
    }
    let mut steps = 0;
    while !q.is_zero() {
        let r = pseudo_remainder(&p, &q, x);
        if r.terms.len() > GCD_MAX_TERMS || gcd_budget_spent() {
            // Remainder sequences can grow explosively in many variables. Returning the
            // contents' gcd is always a correct (if incomplete) common divisor: the fraction
            // stays equal to its value, only less reduced.
            return content;
        }
        p = q;
        q = if r.is_zero() {
            r
        } else {
            primitive_in(&r, x, depth)
        };
        steps += 1;
        if steps > 200 {
            return content;
        }
    }
    let last = if p.degree(x) == 0 {
        Poly::one()
    } else {
        primitive_in(&p, x, depth)
    };
    content.mul_raw(&last).primitive()
}

/// The gcd of the coefficients of `p` in `x`.
fn content_in(p: &Poly, x: AtomId, depth: usize) -> Poly {
    let mut g = Poly::zero();
    for (_, c) in p.coefficients_in(x) {
        g = if g.is_zero() {
            c.primitive()
        } else {
            gcd_monomial_free_full(&g, &c, depth + 1)
        };
        if g.as_constant().is_some() {
            return Poly::one();
        }
    }
    g
}

fn gcd_monomial_free_full(a: &Poly, b: &Poly, _depth: usize) -> Poly {
    gcd(a, b)
}

fn primitive_in(p: &Poly, x: AtomId, depth: usize) -> Poly {
    let c = content_in(p, x, depth);
    p.div_exact(&c).unwrap_or_else(|| p.clone()).primitive()
}

/// The size past which a GCD computation gives up reducing (see `gcd_monomial_free`).
const GCD_MAX_TERMS: usize = 4000;

/// The sparse pseudo-remainder of `a` by `b` in `x`.
fn pseudo_remainder(a: &Poly, b: &Poly, x: AtomId) -> Poly {
    let (db, lb) = b.leading_coefficient_in(x);
    let mut r = a.clone();
    let mut guard = 0;
    loop {
        let (dr, lr) = r.leading_coefficient_in(x);
        if r.is_zero() || dr < db {
            return r;
        }
        r = r.mul_raw(&lb).sub(&b.mul_raw(&lr).shift(x, dr - db));
        let bits: usize = r.terms.iter().map(|(_, c)| c.size_hint()).sum();
        spend_gcd_work(r.terms.len() * (lb.terms.len() + lr.terms.len()) + bits);
        guard += 1;
        if guard > 10_000 || r.terms.len() > GCD_MAX_TERMS || gcd_budget_spent() {
            return r;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn var(name: &str) -> Poly {
        Poly::atom(plain_atom(Expr::symbol(name)))
    }

    #[test]
    fn sin_squares_expand_in_place_as_by_products() {
        // `rewrite_sin_squares` forms the 2^k terms itself; they must be those of the
        // general product `c m (1 − cos²a)(1 − cos²b)…`, cubes and shared cosines included.
        let (sa, ca) = trig_atoms(Expr::symbol("poly_test_a"));
        let (sb, cb) = trig_atoms(Expr::symbol("poly_test_b"));
        let x = plain_atom(Expr::symbol("poly_test_x"));
        let cases: Vec<Monomial> = vec![
            smallvec::smallvec![(sa, 2)],
            smallvec::smallvec![(sa, 3), (x, 2)],
            smallvec::smallvec![(sa, 2), (sb, 2), (ca, 1)],
            smallvec::smallvec![(sa, 3), (sb, 2), (cb, 3), (x, 1)],
        ];
        let one_minus = |cos: AtomId| Poly::one().sub(&Poly::atom_pow(cos, 2));
        for m in cases {
            let mut m = m;
            m.sort_by_key(|&(a, _)| key(a));
            let c = Number::rational(-3, 7).expect("a fraction");
            let fast = rewrite_sin_squares(&m, &c).expect("only sin squares");
            let mut plain = Monomial::new();
            let mut expected_factors = Vec::new();
            for &(a, e) in &m {
                match (a, e) {
                    (a, 2 | 3) if a == sa || a == sb => {
                        if e == 3 {
                            plain.push((a, 1));
                        }
                        expected_factors.push(one_minus(if a == sa { ca } else { cb }));
                    }
                    _ => plain.push((a, e)),
                }
            }
            let mut expected = Poly {
                terms: vec![(plain, c.clone())],
            };
            for f in expected_factors {
                expected = expected.mul_raw(&f);
            }
            assert_eq!(fast, expected, "{m:?}");
        }
    }

    #[test]
    fn sin_squared_is_rewritten() {
        let th = Expr::symbol("poly_test_theta");
        let (s, c) = trig_atoms(th);
        let s = Poly::atom(s);
        let c = Poly::atom(c);
        let one = s.mul(&s).add(&c.mul(&c));
        assert!(one.is_one());
    }

    #[test]
    fn gcd_of_products() {
        let x = var("px");
        let y = var("py");
        let a = x.add(&y).mul(&x.sub(&y)); // x² − y²
        let b = x.add(&y).mul(&x.add(&Poly::one())); // (x + y)(x + 1)
        let g = gcd(&a, &b);
        assert_eq!(g, x.add(&y).primitive());
        let h = gcd(&x.mul(&y), &y.mul(&y));
        assert_eq!(h, y);
    }

    #[test]
    fn exact_division() {
        let x = var("dx");
        let y = var("dy");
        let a = x.add(&y).pow(3);
        assert_eq!(a.div_exact(&x.add(&y)), Some(x.add(&y).pow(2)));
        assert_eq!(a.div_exact(&x.sub(&y)), None);
    }
}
