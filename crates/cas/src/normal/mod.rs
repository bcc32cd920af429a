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

mod convert;
mod rf;
mod to_expr;
mod trig;

use std::sync::{Arc, Mutex, OnceLock};

use rustc_hash::FxHashMap;

use crate::expr::{Constant, Expr, Node};
use crate::limits::{self, WorkLimitError};
use crate::poly::plain_atom;

pub(crate) use convert::{eval_float, Normalizer};
pub(crate) use rf::Rf;
pub(crate) use to_expr::{monomial_to_expr, poly_to_expr};

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
    try_to_rf(e).unwrap_or_else(|_| match e.node() {
        // Inside a scope past its limit every conversion stops at once, numbers too; a number
        // is never an atom.
        Node::Number(n) => Rf::constant(n.clone()),
        _ => Rf::atom(plain_atom(e)),
    })
}

/// The normal form of `e` as an [`Rf`], or the work limit it ran into.
pub(crate) fn try_to_rf(e: Expr) -> Result<Rf, WorkLimitError> {
    limits::limited(|| Normalizer::default().rf(e))
}

/// The canonical expression of a normal form, remembered as its own normal form.
pub(crate) fn from_rf(r: &Rf) -> Expr {
    remember(r, || Arc::new(r.clone()))
}

/// [`from_rf`] of a shared working form, which is remembered without a copy.
pub(crate) fn from_shared_rf(r: &Arc<Rf>) -> Expr {
    remember(r, || Arc::clone(r))
}

/// The canonical expression of a normal form, remembered as its own normal form but without
/// its working form (see `NormalForm::to_expr_unremembered`).
pub(crate) fn tree_unremembered(r: &Rf) -> Expr {
    let e = r.to_expr();
    normal_memo()
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .insert(e, e);
    e
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

    /// The denominator of the normal form, and its numerator only when `wanted(denominator)`:
    /// [`Expr::numer_denom`] for a caller that often stops at the denominator (turning a long
    /// numerator back into a tree is most of the cost of `numer_denom`).
    pub(crate) fn denom_then_numer(
        self,
        wanted: impl FnOnce(Expr) -> bool,
    ) -> (Expr, Option<Expr>) {
        let r = to_rf(self);
        let den = from_rf(&Rf::from_poly(r.den));
        let num = wanted(den).then(|| from_rf(&Rf::from_poly(r.num)));
        (den, num)
    }

    /// Whether the expression is the literal `π`.
    pub fn is_pi(self) -> bool {
        matches!(self.node(), Node::Constant(Constant::Pi))
    }
}
