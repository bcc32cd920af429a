//! Work limits of the symbolic core: how large a polynomial, and how high a power, one
//! conversion to normal form may build before it stops with a [`WorkLimitError`].
//!
//! Expansion is exponential in the worst case (`sin(a + b + … + w)` with 21 terms is
//! 2²¹ products; `sin(x)^100000` is a polynomial of degree 100 000 with 30 000-digit
//! coefficients). The limits are process-wide ([`set_work_limits`]); the state of the
//! conversion under way is per thread. Inside a conversion, a step past a limit records the
//! error and every later polynomial operation returns at once, so the conversion unwinds in
//! time proportional to the work already done.

use std::cell::Cell;
use std::sync::atomic::{AtomicU32, AtomicUsize, Ordering};

/// Limits on the work of one conversion to normal form ([`crate::Expr::try_normal`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct WorkLimits {
    /// The most terms one polynomial may have (default: 500 000, about 50 MB).
    pub max_terms: usize,
    /// The highest total degree a power of a polynomial with more than one term may reach
    /// (default: 10 000).
    pub max_degree: u32,
}

impl Default for WorkLimits {
    fn default() -> WorkLimits {
        WorkLimits {
            max_terms: 500_000,
            max_degree: 10_000,
        }
    }
}

impl WorkLimits {
    /// These limits with `max_terms` set.
    #[must_use]
    pub fn with_max_terms(self, max_terms: usize) -> WorkLimits {
        WorkLimits { max_terms, ..self }
    }

    /// These limits with `max_degree` set.
    #[must_use]
    pub fn with_max_degree(self, max_degree: u32) -> WorkLimits {
        WorkLimits { max_degree, ..self }
    }
}

/// A conversion to normal form stopped at a work limit.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum WorkLimitError {
    /// A polynomial would have had more terms than [`WorkLimits::max_terms`].
    #[error(
        "the expanded form grows past {limit} terms (the work limit `max_terms`; raise it with \
         `cas::set_work_limits` to go on)"
    )]
    Terms {
        /// The limit that was hit.
        limit: usize,
    },
    /// A power would have had a higher degree than [`WorkLimits::max_degree`].
    #[error(
        "a power of degree {degree} exceeds the work limit of degree {limit} (`max_degree`; \
         raise it with `cas::set_work_limits` to go on)"
    )]
    Degree {
        /// The degree the power would have had.
        degree: u64,
        /// The limit that was hit.
        limit: u32,
    },
}

static MAX_TERMS: AtomicUsize = AtomicUsize::new(500_000);
static MAX_DEGREE: AtomicU32 = AtomicU32::new(10_000);

/// Sets the work limits for every later conversion, in every thread.
pub fn set_work_limits(limits: WorkLimits) {
    MAX_TERMS.store(limits.max_terms, Ordering::Relaxed);
    MAX_DEGREE.store(limits.max_degree, Ordering::Relaxed);
}

/// The work limits in force.
pub fn work_limits() -> WorkLimits {
    WorkLimits {
        max_terms: MAX_TERMS.load(Ordering::Relaxed),
        max_degree: MAX_DEGREE.load(Ordering::Relaxed),
    }
}

thread_local! {
    /// How deep this thread is in guarded conversions, and the limit hit in the outermost one.
    static STATE: Cell<(u32, Option<WorkLimitError>)> = const { Cell::new((0, None)) };
}

/// Runs `f` as a guarded conversion: the first limit hit inside it (or inside a conversion it
/// contains) is its error.
pub(crate) fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, WorkLimitError> {
    STATE.with(|s| {
        let (depth, err) = s.take();
        s.set((depth + 1, err));
    });
    let value = f();
    let err = STATE.with(|s| {
        let (depth, err) = s.take();
        let depth = depth.saturating_sub(1);
        // The outermost conversion clears the error; inner ones leave it for it to see.
        s.set((depth, if depth == 0 { None } else { err.clone() }));
        err
    });
    match err {
        Some(e) => Err(e),
        None => Ok(value),
    }
}

/// Whether the conversion under way has hit a limit (its results are then discarded).
pub(crate) fn exceeded() -> bool {
    STATE.with(|s| {
        let state = s.take();
        let hit = state.0 > 0 && state.1.is_some();
        s.set(state);
        hit
    })
}

fn trip(e: WorkLimitError) {
    STATE.with(|s| {
        let (depth, err) = s.take();
        let err = if depth > 0 { err.or(Some(e)) } else { err };
        s.set((depth, err));
    });
}

/// Checks a polynomial size against [`WorkLimits::max_terms`]; `false` (and the limit
/// recorded) when it is past the limit inside a guarded conversion.
pub(crate) fn terms_ok(terms: usize) -> bool {
    let limit = MAX_TERMS.load(Ordering::Relaxed);
    if terms <= limit || !in_conversion() {
        return true;
    }
    trip(WorkLimitError::Terms { limit });
    false
}

/// Checks the degree of a power against [`WorkLimits::max_degree`], like [`terms_ok`].
pub(crate) fn degree_ok(degree: u64) -> bool {
    let limit = MAX_DEGREE.load(Ordering::Relaxed);
    if degree <= u64::from(limit) || !in_conversion() {
        return true;
    }
    trip(WorkLimitError::Degree { degree, limit });
    false
}

fn in_conversion() -> bool {
    STATE.with(|s| {
        let state = s.take();
        let depth = state.0;
        s.set(state);
        depth > 0
    })
}
