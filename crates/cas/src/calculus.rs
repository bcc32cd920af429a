//! Derivatives and series: `∂/∂x`, the total time derivative `d/dt`, and Taylor expansion.
//!
//! Derivatives work on the normal form: the derivative of a polynomial is collected atom by
//! atom (`∂P/∂a · da` for every atom `a` that depends on the variable), and the quotient rule
//! handles the denominator. The result is again in normal form. Coordinates are functions of
//! time: `d/dt q = q̇`, `d/dt q̇ = q̈`, while for partial derivatives `q`, `q̇`, `q̈` are
//! independent variables, as Lagrange's equations treat them.

use std::sync::{Mutex, OnceLock};

use rustc_hash::FxHashMap;
use smallvec::SmallVec;

use crate::expr::{Expr, Func, Node, Symbol, SymbolKind};
use crate::limits;
use crate::normal::{cached_rf, from_rf, Normalizer, Rf};
use crate::number::Number;
use crate::poly::{
    atom_expr, atom_index, atom_info, mul_factor_slices, mul_monomials, needs_rewrite, plain_atom,
    rewrite_term, AtomId, AtomKind, Monomial, Poly, MERGE_BUFFER,
};

/// The variable of a derivative was not a symbol.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("can only differentiate with respect to a symbol")]
pub struct NotASymbol;

#[derive(Clone, Copy)]
enum Wrt {
    Partial(Expr),
    Time,
}

struct Deriver {
    wrt: Wrt,
    normalizer: Normalizer,
    atoms: FxHashMap<AtomId, Rf>,
}

impl Deriver {
    fn new(wrt: Wrt) -> Deriver {
        Deriver {
            wrt,
            normalizer: Normalizer::default(),
            atoms: FxHashMap::default(),
        }
    }

    fn expr(&mut self, e: Expr) -> Rf {
        // Large normal forms keep their working form; borrow it rather than copy it.
        if let Some(r) = cached_rf(e) {
            return self.rf(&r);
        }
        let r = self.normalizer.rf(e);
        self.rf(&r)
    }

    fn rf(&mut self, r: &Rf) -> Rf {
        let dn = self.poly(&r.num);
        if r.den.is_one() {
            return dn;
        }
        let dd = self.poly(&r.den);
        if dn.is_zero() && dd.is_zero() {
            // Free of the variable: no quotient rule (it would square `D` to divide zero).
            return Rf::zero();
        }
        // (N/D)' = (N' D − N D') / D²
        let num = dn
            .mul(&Rf::from_poly(r.den.clone()))
            .sub(&Rf::from_poly(r.num.clone()).mul(&dd));
        num.div(&Rf::from_poly(r.den.mul(&r.den)))
            .unwrap_or_else(Rf::zero)
    }

    fn poly(&mut self, p: &Poly) -> Rf {
        let mut buckets = Buckets::for_poly(p);
        for (m, c) in &p.terms {
            for (i, &(a, _)) in m.iter().enumerate() {
                let part = match buckets.slot(a) {
                    Slot::Constant => continue,
                    Slot::Part(k) => k,
                    Slot::Unknown if self.atom_is_constant(a) => {
                        buckets.set_constant(a);
                        continue;
                    }
                    // `atom_is_constant` has worked out (and kept) the atom's derivative.
                    Slot::Unknown => buckets.open(a, &self.atoms[&a]),
                };
                buckets.push(part, m, i, c);
            }
        }
        buckets.assemble(|a| self.atom(a))
    }

    fn atom_is_constant(&mut self, a: AtomId) -> bool {
        if let Some(r) = self.atoms.get(&a) {
            return r.is_zero();
        }
        self.atom(a).is_zero()
    }

    fn atom(&mut self, a: AtomId) -> Rf {
        if let Some(r) = self.atoms.get(&a) {
            return r.clone();
        }
        let time = matches!(self.wrt, Wrt::Time);
        if time {
            if let Some(r) = remembered_rate(a) {
                self.atoms.insert(a, r.clone());
                return r;
            }
        }
        let r = self.atom_derivative(a);
        if time {
            remember_rate(a, &r);
        }
        self.atoms.insert(a, r.clone());
        r
    }

    fn atom_derivative(&mut self, a: AtomId) -> Rf {
        let info = atom_info(a);
        match info.kind {
            AtomKind::Sin { angle, cos } => Rf::atom(cos).mul(&self.expr(angle)),
            AtomKind::Cos { angle, sin } => Rf::atom(sin).neg().mul(&self.expr(angle)),
            AtomKind::Root { base, q } => {
                // d(b^(1/q)) = (1/q) b^(1/q) b' / b
                let db = self.poly(&base);
                if db.is_zero() {
                    Rf::zero()
                } else {
                    let r = Rf::atom(a)
                        .mul(&db)
                        .scale(&Number::rational(1, q as i64).unwrap_or(Number::ONE));
                    r.div(&Rf::from_poly(base)).unwrap_or_else(Rf::zero)
                }
            }
            AtomKind::Plain => self.plain(info.expr),
        }
    }

    fn plain(&mut self, e: Expr) -> Rf {
        match e.node() {
            Node::Symbol(s) => match self.wrt {
                Wrt::Partial(x) => {
                    if e == x {
                        Rf::one()
                    } else {
                        Rf::zero()
                    }
                }
                Wrt::Time => match s.kind() {
                    SymbolKind::Time => Rf::one(),
                    SymbolKind::TimeFunction { .. } => match s.rate(1) {
                        Some(r) => Rf::atom(plain_atom(Expr::from_symbol(r))),
                        None => Rf::zero(),
                    },
                    _ => Rf::zero(),
                },
            },
            Node::Pow([b, x]) => {
                // d(b^x) = b^x (x' ln b + x b'/b)
                let (b, x) = (*b, *x);
                let db = self.expr(b);
                let dx = self.expr(x);
                if db.is_zero() && dx.is_zero() {
                    return Rf::zero();
                }
                let d = dx.to_expr() * b.ln() + x * db.to_expr() / b;
                self.normalizer.rf(e * d)
            }
            Node::Func(f, args) => self.function(*f, args),
            _ => Rf::zero(),
        }
    }

    fn function(&mut self, f: Func, args: &[Expr]) -> Rf {
        let u = args[0];
        let du = self.expr(u);
        if f != Func::Atan2 && du.is_zero() {
            return Rf::zero();
        }
        let du_e = du.to_expr();
        let one = Expr::one();
        let d = match f {
            Func::Sin => u.cos() * du_e,
            Func::Cos => -(u.sin() * du_e),
            Func::Tan => du_e / u.cos().powi(2),
            Func::Asin => du_e / (one - u.powi(2)).sqrt(),
            Func::Acos => -(du_e / (one - u.powi(2)).sqrt()),
            Func::Atan => du_e / (one + u.powi(2)),
            Func::Atan2 => {
                let (y, x) = (args[0], args[1]);
                let dy = du_e;
                let dx = self.expr(x).to_expr();
                (x * dy - y * dx) / (x.powi(2) + y.powi(2))
            }
            Func::Exp => u.exp() * du_e,
            Func::Ln => du_e / u,
            Func::Abs => u.sign() * du_e,
            // The sign function is piecewise constant; its derivative is zero where defined.
            Func::Sign => Expr::zero(),
        };
        self.normalizer.rf(d)
    }
}

/// The time derivatives of atoms, for every derivation in the process: `d/dt` of an atom is a
/// pure function of it, and a derivation takes the time derivative of many forms over the
/// same atoms (each velocity component, each `∂L/∂q̇_j`), each of which otherwise worked out
/// `d/dt sin θ_k` and the rest again.
fn rate_memo() -> &'static Mutex<FxHashMap<AtomId, Rf>> {
    static MEMO: OnceLock<Mutex<FxHashMap<AtomId, Rf>>> = OnceLock::new();
    MEMO.get_or_init(|| Mutex::new(FxHashMap::default()))
}

fn remembered_rate(a: AtomId) -> Option<Rf> {
    rate_memo()
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .get(&a)
        .cloned()
}

/// Remembers `d/dt a`, unless a work limit was hit while it was worked out (then the result
/// may be a placeholder, which a later call with larger limits must not find).
fn remember_rate(a: AtomId, rate: &Rf) {
    if limits::exceeded() {
        return;
    }
    rate_memo()
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .entry(a)
        .or_insert_with(|| rate.clone());
}

/// The partial derivatives `∂e/∂x` taken so far, for every caller in the process: a
/// derivative is a pure function of `(e, x)`, and the rest equations' users ask for the same
/// ones many times (their Jacobian, which unknowns each equation involves, its blocks, each
/// elimination step of the exact solver, the linearization): spring-chain's exact try took
/// 1.5·10⁹ instructions differentiating its six residuals over and over (issue 20).
fn partial_memo() -> &'static Mutex<FxHashMap<(Expr, Symbol), Expr>> {
    static MEMO: OnceLock<Mutex<FxHashMap<(Expr, Symbol), Expr>>> = OnceLock::new();
    MEMO.get_or_init(|| Mutex::new(FxHashMap::default()))
}

fn remembered_partial(e: Expr, var: Symbol) -> Option<Expr> {
    partial_memo()
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .get(&(e, var))
        .copied()
}

/// Remembers `∂e/∂var`, unless a work limit was hit while it was worked out (as
/// [`remember_rate`]).
fn remember_partial(e: Expr, var: Symbol, derivative: Expr) {
    if limits::exceeded() {
        return;
    }
    partial_memo()
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .entry((e, var))
        .or_insert(derivative);
}

/// The monomial `m` with its `i`-th factor `a^e` lowered to `a^(e−1)`, and `e·c`: the
/// term's partial derivative with respect to the atom `a`, before `da`.
fn lowered(m: &Monomial, i: usize, e: u32, c: &Number) -> (Monomial, Number) {
    let mut reduced = m.clone();
    if e == 1 {
        reduced.remove(i);
    } else {
        reduced[i].1 = e - 1;
    }
    (reduced, c.mul(&Number::int(i64::from(e))))
}

/// `m` with its `i`-th factor lowered by one, times `md`: [`lowered`] and [`mul_monomials`] in
/// one pass on the stack (this product is formed for every factor of every term of a
/// derivative), without the intermediate monomial.
fn lowered_product(m: &Monomial, i: usize, md: &Monomial) -> Monomial {
    if m.len() + md.len() > MERGE_BUFFER {
        return mul_monomials(&lowered(m, i, m[i].1, &Number::ONE).0, md);
    }
    let mut reduced = [(0, 0); MERGE_BUFFER];
    let mut k = 0;
    for (j, &(x, e)) in m.iter().enumerate() {
        let e = if j == i { e - 1 } else { e };
        if e > 0 {
            reduced[k] = (x, e);
            k += 1;
        }
    }
    mul_factor_slices(&reduced[..k], md)
}

/// The terms of `∂P/∂a · da` for each atom `a` of a polynomial `P`, in the order the atoms are
/// first met. When `da` is one term (`d sin θ = cos θ θ̇`, `d θ̇ = θ̈`, `∂θ/∂θ = 1`: nearly
/// always) each term's product is formed as the term is read; otherwise the terms of `∂P/∂a`
/// wait for a full product in [`Buckets::assemble`].
///
/// Each atom's part is found through a table indexed by atom index over the range of the
/// polynomial's atoms: a derivative visits every factor of every term, and looking the atom
/// up in hash maps (whether it is constant, its derivative, its part) was a third of it.
#[derive(Default)]
struct Buckets {
    /// The atoms' parts, in the order the atoms are first met.
    parts: Vec<Bucket>,
    /// The smallest atom index of the polynomial: `slots` is indexed from it.
    low: u32,
    /// Each atom's part, [`CONSTANT`] or [`UNKNOWN`].
    slots: Vec<u32>,
    /// Products a rewriting rule applies to (`sin θ · d cos θ = −sin² θ θ̇`).
    rewrites: Vec<(Monomial, Number)>,
}

/// The terms of `∂P/∂a · da` for one atom `a`.
struct Bucket {
    atom: AtomId,
    /// `da` when it is one term: the bucket's terms are multiplied by it already.
    single: Option<(Monomial, Number)>,
    terms: Vec<(Monomial, Number)>,
}

/// A slot of an atom not met yet.
const UNKNOWN: u32 = u32::MAX;
/// A slot of an atom whose derivative is zero.
const CONSTANT: u32 = u32::MAX - 1;

/// What [`Buckets`] knows of an atom.
enum Slot {
    Unknown,
    Constant,
    Part(usize),
}

impl Buckets {
    /// Empty parts for the atoms of `p`.
    fn for_poly(p: &Poly) -> Buckets {
        Buckets::for_range(atom_range(p))
    }

    /// Empty parts for atoms whose indices are in `low..=high`.
    fn for_range((low, high): (u32, u32)) -> Buckets {
        let slots = if low <= high {
            vec![UNKNOWN; (high - low + 1) as usize]
        } else {
            Vec::new()
        };
        Buckets {
            low,
            slots,
            ..Buckets::default()
        }
    }

    /// What is known of the atom `a` of the polynomial.
    fn slot(&self, a: AtomId) -> Slot {
        match self.slots[(atom_index(a) - self.low) as usize] {
            UNKNOWN => Slot::Unknown,
            CONSTANT => Slot::Constant,
            k => Slot::Part(k as usize),
        }
    }

    fn set_constant(&mut self, a: AtomId) {
        self.slots[(atom_index(a) - self.low) as usize] = CONSTANT;
    }

    /// Opens the part of the atom `a`, whose derivative is `da`, and returns its number.
    fn open(&mut self, a: AtomId, da: &Rf) -> usize {
        let k = self.parts.len();
        self.slots[(atom_index(a) - self.low) as usize] = k as u32;
        self.parts.push(Bucket {
            atom: a,
            single: one_term(da).map(|(m, c)| (m.clone(), c.clone())),
            terms: Vec::new(),
        });
        k
    }

    /// Adds the derivative of the term `c m` with respect to its `i`-th factor, the atom of
    /// part `k`.
    fn push(&mut self, k: usize, m: &Monomial, i: usize, c: &Number) {
        let bucket = &mut self.parts[k];
        let Some((md, cd)) = &bucket.single else {
            bucket.terms.push(lowered(m, i, m[i].1, c));
            return;
        };
        let product = lowered_product(m, i, md);
        let coefficient = c.mul(&Number::int(i64::from(m[i].1))).mul(cd);
        if product.iter().any(|&(x, k)| needs_rewrite(x, k)) {
            self.rewrites.push((product, coefficient));
        } else {
            bucket.terms.push((product, coefficient));
        }
    }

    /// `Σ_a ∂P/∂a · da`: polynomial parts are gathered and sort-merged once (adding them one
    /// by one would copy the growing sum for every atom); fractions are added after.
    fn assemble(self, mut derivative: impl FnMut(AtomId) -> Rf) -> Rf {
        // Most atoms' derivatives are one term (`d sin θ = cos θ θ̇`), so the parts' sizes
        // are about the result's: reserved once rather than grown by copying.
        let size: usize = self.parts.iter().map(|b| b.terms.len()).sum();
        let mut terms = Vec::with_capacity(size + self.rewrites.len());
        let mut fractions = Rf::zero();
        for bucket in self.parts {
            // Removing one factor `a` from distinct monomials leaves distinct monomials, so the
            // bucket is a valid polynomial, and multiplying by one monomial keeps it one; each
            // bucket is a sorted run, which the final merge sorts with the others.
            let (a, part) = (bucket.atom, bucket.terms);
            if bucket.single.is_some() {
                if !limits::spend(part.len() as u64) {
                    return Rf::zero();
                }
                terms.extend(part);
                continue;
            }
            let partial = Poly { terms: part };
            let da = derivative(a);
            if da.den.is_one() {
                terms.extend(partial.mul(&da.num).terms);
            } else {
                fractions = fractions.add(&Rf::from_poly(Poly::from_terms(partial.terms)).mul(&da));
            }
        }
        for (m, c) in self.rewrites {
            terms.extend(rewrite_term(m, c).terms);
        }
        Rf::from_poly(Poly::from_terms(terms)).add(&fractions)
    }
}

/// The smallest and the largest atom index of `p` (`(u32::MAX, 0)` when it has no atom).
fn atom_range(p: &Poly) -> (u32, u32) {
    let (mut low, mut high) = (u32::MAX, 0);
    for (m, _) in &p.terms {
        for &(a, _) in m {
            low = low.min(atom_index(a));
            high = high.max(atom_index(a));
        }
    }
    (low, high)
}

/// The one term `c m` of a polynomial `da`, if that is what it is.
fn one_term(da: &Rf) -> Option<(&Monomial, &Number)> {
    match da.num.terms.as_slice() {
        [(m, c)] if da.den.is_one() => Some((m, c)),
        _ => None,
    }
}

/// `∂r/∂v` for every `v` of `vars`, equal to [`partial_derivative_rf`] for each. A polynomial
/// is read once for all the variables (each term is handed to the variables its atoms depend
/// on), not once per variable: the gradient of a Lagrangian with T terms in n coordinates
/// costs O(T) instead of O(n T).
pub(crate) fn gradient_rf(r: &Rf, vars: &[Symbol]) -> Vec<Rf> {
    if !r.den.is_one() {
        return vars.iter().map(|&v| partial_derivative_rf(r, v)).collect();
    }
    let mut derivers: Vec<Deriver> = vars
        .iter()
        .map(|&v| Deriver::new(Wrt::Partial(Expr::from_symbol(v))))
        .collect();
    // Which variables each atom depends on (with the atom's part for each), decided once per
    // atom.
    let mut depends: FxHashMap<AtomId, Vec<(usize, usize)>> = FxHashMap::default();
    let range = atom_range(&r.num);
    let mut buckets: Vec<Buckets> = vars.iter().map(|_| Buckets::for_range(range)).collect();
    for (m, c) in &r.num.terms {
        for (i, &(a, _)) in m.iter().enumerate() {
            let on = depends.entry(a).or_insert_with(|| {
                // Only a variable the atom mentions can have a non-zero derivative; asking
                // every variable's deriver about every atom made the gradient of an n-link
                // Lagrangian compute O(n²) atom derivatives, nearly all of them zero.
                let mentioned = symbols_in(atom_expr(a));
                let varying = |(k, d): (usize, &mut Deriver)| {
                    (mentioned.contains(&vars[k]) && !d.atom_is_constant(a)).then_some(k)
                };
                let on: Vec<usize> = derivers
                    .iter_mut()
                    .enumerate()
                    .filter_map(varying)
                    .collect();
                // `on` holds the variables whose derivers worked out `a`'s derivative.
                on.into_iter()
                    .map(|k| (k, buckets[k].open(a, &derivers[k].atoms[&a])))
                    .collect()
            });
            for &(k, part) in on.iter() {
                buckets[k].push(part, m, i, c);
            }
        }
    }
    let derivers = derivers.iter_mut();
    let assemble = |(b, d): (Buckets, &mut Deriver)| b.assemble(|a| d.atom(a));
    buckets.into_iter().zip(derivers).map(assemble).collect()
}

/// The symbols that occur in `e` (each once).
fn symbols_in(e: Expr) -> SmallVec<[Symbol; 4]> {
    let mut found: SmallVec<[Symbol; 4]> = SmallVec::new();
    let mut stack: SmallVec<[Expr; 8]> = SmallVec::new();
    stack.push(e);
    while let Some(x) = stack.pop() {
        match x.as_symbol() {
            Some(s) if !found.contains(&s) => found.push(s),
            Some(_) => {}
            None => stack.extend_from_slice(x.children()),
        }
    }
    found
}

/// Whether the symbol `s` occurs in `e` (each shared node visited once).
fn mentions(e: Expr, s: Symbol) -> bool {
    let mut seen: rustc_hash::FxHashSet<Expr> = rustc_hash::FxHashSet::default();
    let mut stack: SmallVec<[Expr; 16]> = SmallVec::new();
    stack.push(e);
    while let Some(x) = stack.pop() {
        if let Some(found) = x.as_symbol() {
            if found == s {
                return true;
            }
        } else if seen.insert(x) {
            stack.extend_from_slice(x.children());
        }
    }
    false
}

/// `∂r/∂var` of a working form.
pub(crate) fn partial_derivative_rf(r: &Rf, var: Symbol) -> Rf {
    Deriver::new(Wrt::Partial(Expr::from_symbol(var))).rf(r)
}

/// `d/dt r` of a working form.
pub(crate) fn time_derivative_rf(r: &Rf) -> Rf {
    Deriver::new(Wrt::Time).rf(r)
}

impl Expr {
    /// The partial derivative `∂self/∂var`, in normal form. Coordinates and their rates are
    /// independent variables here (`∂q̇/∂q = 0`).
    ///
    /// Each derivative is worked out once per process and remembered.
    pub fn diff(self, var: Symbol) -> Expr {
        if let Some(d) = remembered_partial(self, var) {
            return d;
        }
        if !mentions(self, var) {
            // Exactly what the derivation below gives, without walking every atom's
            // derivative: the rest equations' users ask about every unknown in every equation.
            return Expr::zero();
        }
        let mut d = Deriver::new(Wrt::Partial(Expr::from_symbol(var)));
        let r = d.expr(self);
        let derivative = from_rf(&r);
        remember_partial(self, var, derivative);
        derivative
    }

    /// The partial derivative with respect to an expression that must be a symbol.
    pub fn try_diff(self, var: Expr) -> Result<Expr, NotASymbol> {
        match var.as_symbol() {
            Some(s) => Ok(self.diff(s)),
            None => Err(NotASymbol),
        }
    }

    /// The total time derivative `d/dt`, in normal form: `t` has rate 1, a function of time
    /// `q` has rate `q̇` (and `q̇` has `q̈`), other symbols are constant.
    pub fn dt(self) -> Expr {
        let mut d = Deriver::new(Wrt::Time);
        let r = d.expr(self);
        from_rf(&r)
    }

    /// The Taylor polynomial of total degree `order` about `point` (pairs of a variable and
    /// its value there), in normal form. `order = 1` is the linearization.
    ///
    /// With `h = x − x₀`, this is `Σ_{k ≤ order} (1/k!) dᵏ/dεᵏ f(x₀ + ε h) |_{ε=0}`.
    pub fn taylor(self, point: &[(Symbol, Expr)], order: u32) -> Expr {
        let eps = Expr::symbol("\u{1}taylor_epsilon");
        let eps_sym = eps.as_symbol().expect("a symbol expression holds a symbol");
        let shifted: Vec<(Expr, Expr)> = point
            .iter()
            .map(|(x, x0)| {
                let xe = Expr::from_symbol(*x);
                (xe, *x0 + eps * (xe - *x0))
            })
            .collect();
        let mut g = self.subs(&shifted).normal();
        let mut total = Expr::zero();
        let mut factorial = Number::ONE;
        for k in 0..=order {
            if k > 0 {
                g = g.diff(eps_sym);
                factorial = factorial.mul(&Number::int(k as i64));
            }
            let at_zero = g.subs(&[(eps, Expr::zero())]);
            let inv = factorial.recip().unwrap_or(Number::ONE);
            total += Expr::number(inv) * at_zero;
        }
        total.normal()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_derivative_follows_the_chain_rule() {
        let th = Expr::coordinate("theta");
        let thd = Expr::rate("theta", 1);
        let thdd = Expr::rate("theta", 2);
        let l = Expr::symbol("l");
        assert!((l * th.cos()).dt().equals(-(l * thd * th.sin())));
        assert!((thd * th.cos())
            .dt()
            .equals(thdd * th.cos() - thd.powi(2) * th.sin()));
        assert_eq!(Expr::time().powi(2).dt(), (2 * Expr::time()).normal());
    }

    #[test]
    fn partial_derivatives_treat_rates_as_independent() {
        let x = Expr::coordinate("x");
        let xd = Expr::rate("x", 1);
        let k = x.powi(2) * xd;
        assert!(k.diff(x.as_symbol().unwrap()).equals(2 * x * xd));
        assert!(k.diff(xd.as_symbol().unwrap()).equals(x.powi(2)));
    }

    #[test]
    fn quotient_and_functions() {
        let x = Expr::symbol("x");
        let s = x.as_symbol().unwrap();
        assert!((Expr::one() / x).diff(s).equals(-(x.powi(-2))));
        assert!(x.ln().diff(s).equals(Expr::one() / x));
        assert!(x.sqrt().diff(s).equals(Expr::one() / (2 * x.sqrt())));
        assert!(x.atan().diff(s).equals(Expr::one() / (1 + x.powi(2))));
    }

    #[test]
    fn remembered_and_unmentioned_derivatives_are_the_derivation_s() {
        let (x, y) = (Expr::symbol("x"), Expr::symbol("y"));
        let (sx, sy) = (x.as_symbol().unwrap(), y.as_symbol().unwrap());
        let e = ((x.powi(2) + 1).sqrt() * y.sin() / (x + y)).normal();
        let first = e.diff(sx);
        // The second call is answered from the memo: the same expression, still the derivative.
        assert_eq!(e.diff(sx), first);
        let expected = (x / (x.powi(2) + 1).sqrt() * y.sin() / (x + y)
            - (x.powi(2) + 1).sqrt() * y.sin() / (x + y).powi(2))
        .normal();
        assert!(first.equals(expected), "{first}");
        // A symbol the expression does not mention: zero without a derivation.
        let z = Expr::symbol("z").as_symbol().unwrap();
        assert!(e.diff(z).is_zero());
        assert!(!e.diff(sy).is_zero());
        // An angle that is a quotient free of the variable has derivative zero (both parts'
        // derivatives are, so the quotient rule is skipped).
        let angle = y / (y + 1);
        assert!((x * angle.sin()).diff(sx).equals(angle.sin()));
    }

    #[test]
    fn taylor_of_cosine() {
        let x = Expr::symbol("x");
        let s = x.as_symbol().unwrap();
        let t = x.cos().taylor(&[(s, Expr::zero())], 2);
        assert!(t.equals(Expr::one() - x.powi(2) / 2));
        let lin = x.sin().taylor(&[(s, Expr::pi())], 1);
        assert!(lin.equals(Expr::pi() - x));
    }
}
