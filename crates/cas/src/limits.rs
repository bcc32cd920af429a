//! Work limits of the symbolic core: how large a polynomial, how high a power and how much
//! work in all one *limited scope* may spend before it stops with a [`WorkLimitError`].
//!
//! Expansion is exponential in the worst case (`sin(a + b + … + w)` with 21 terms is
//! 2²¹ products; `sin(x)^10000` is a polynomial of degree 10 000 with 3 000-digit
//! coefficients). A scope is one conversion to normal form ([`crate::Expr::try_normal`]) or a
//! whole computation run under [`limited`] (a derivation): the conversions inside it share its
//! budget, and once a limit is hit the scope's result is that error, whatever the code inside
//! did with it (an infallible `normal()` inside returns its input, but the scope still fails).
//! After the hit every polynomial operation of the scope returns at once, so the scope unwinds
//! in time proportional to the work already done.
//!
//! The work measure counts monomial operations (a product of an `a`-term and a `b`-term
//! polynomial costs `a b`, weighted by the size of big coefficients), not seconds: a limit is
//! hit at the same point on every machine and under any load. The limits are process-wide
//! ([`set_work_limits`]), or per thread for the scopes started inside [`with_work_limits`];
//! the state of the scope under way is per thread.

use std::cell::Cell;
use std::sync::atomic::{AtomicU32, AtomicU64, AtomicUsize, Ordering};

/// Limits on the work of one limited scope (one conversion to normal form, or a computation
/// run under [`limited`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct WorkLimits {
    /// The most terms one polynomial may have (default: 100 000, about 10 MB).
    pub max_terms: usize,
    /// The highest total degree a power of a polynomial with more than one term may reach
    /// (default: 2 000).
    pub max_degree: u32,
    /// The most work (monomial operations, see the module documentation) one scope may spend
    /// in all (default: 50 000 000, about a second or two of work).
    pub max_work: u64,
}

const DEFAULT: WorkLimits = WorkLimits {
    max_terms: 100_000,
    max_degree: 2_000,
    max_work: 50_000_000,
};

impl Default for WorkLimits {
    fn default() -> WorkLimits {
        DEFAULT
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

    /// These limits with `max_work` set.
    #[must_use]
    pub fn with_max_work(self, max_work: u64) -> WorkLimits {
        WorkLimits { max_work, ..self }
    }

    /// Every limit multiplied by `factor` (at least 1 each; saturating): one knob for "allow
    /// this many times as much".
    #[must_use]
    pub fn scaled(self, factor: f64) -> WorkLimits {
        let scale = |x: f64| (x * factor).clamp(1.0, u64::MAX as f64);
        WorkLimits {
            max_terms: scale(self.max_terms as f64) as usize,
            max_degree: scale(f64::from(self.max_degree)).min(f64::from(u32::MAX)) as u32,
            max_work: scale(self.max_work as f64) as u64,
        }
    }
}

/// A limited scope stopped at a work limit.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum WorkLimitError {
    /// A polynomial would have had more terms than [`WorkLimits::max_terms`].
    #[error(
        "the expanded form grows past {limit} terms (the work limit `max_terms`; raise the \
         work limits to go on)"
    )]
    Terms {
        /// The limit that was hit.
        limit: usize,
    },
    /// A power would have had a higher degree than [`WorkLimits::max_degree`].
    #[error(
        "a power of degree {degree} exceeds the work limit of degree {limit} (`max_degree`; \
         raise the work limits to go on)"
    )]
    Degree {
        /// The degree the power would have had.
        degree: u64,
        /// The limit that was hit.
        limit: u32,
    },
    /// The scope spent more work than [`WorkLimits::max_work`].
    #[error(
        "the symbolic work exceeds its limit of {limit} operations (`max_work`; raise the \
         work limits to go on)"
    )]
    Work {
        /// The limit that was hit.
        limit: u64,
    },
}

static MAX_TERMS: AtomicUsize = AtomicUsize::new(DEFAULT.max_terms);
static MAX_DEGREE: AtomicU32 = AtomicU32::new(DEFAULT.max_degree);
static MAX_WORK: AtomicU64 = AtomicU64::new(DEFAULT.max_work);

/// Sets the process-wide work limits for every later scope, in every thread (a thread inside
/// [`with_work_limits`] keeps its own).
pub fn set_work_limits(limits: WorkLimits) {
    MAX_TERMS.store(limits.max_terms, Ordering::Relaxed);
    MAX_DEGREE.store(limits.max_degree, Ordering::Relaxed);
    MAX_WORK.store(limits.max_work, Ordering::Relaxed);
}

/// The work limits in force on this thread.
pub fn work_limits() -> WorkLimits {
    STATE
        .with(|s| s.chosen.get())
        .unwrap_or_else(|| WorkLimits {
            max_terms: MAX_TERMS.load(Ordering::Relaxed),
            max_degree: MAX_DEGREE.load(Ordering::Relaxed),
            max_work: MAX_WORK.load(Ordering::Relaxed),
        })
}

/// Runs `f` with `limits` in force for the scopes it starts on this thread (a scope already
/// under way keeps the limits it started with).
pub fn with_work_limits<T>(limits: WorkLimits, f: impl FnOnce() -> T) -> T {
    let before = STATE.with(|s| s.chosen.replace(Some(limits)));
    let value = f();
    STATE.with(|s| s.chosen.set(before));
    value
}

/// The per-thread state of the scope under way.
struct State {
    /// How deep this thread is in limited scopes (0: none; nothing is limited).
    depth: Cell<u32>,
    /// The first limit hit in the outermost scope.
    error: Cell<Option<WorkLimitError>>,
    /// Whether `error` is set (read on every polynomial operation).
    tripped: Cell<bool>,
    /// Work spent by the outermost scope.
    work: Cell<u64>,
    /// The limits of the outermost scope, fixed when it starts.
    limits: Cell<WorkLimits>,
    /// Limits chosen by [`with_work_limits`].
    chosen: Cell<Option<WorkLimits>>,
}

thread_local! {
    static STATE: State = const {
        State {
            depth: Cell::new(0),
            error: Cell::new(None),
            tripped: Cell::new(false),
            work: Cell::new(0),
            limits: Cell::new(DEFAULT),
            chosen: Cell::new(None),
        }
    };
}

/// Runs `f` as a limited scope: the first work limit hit inside it (in any conversion it
/// contains, even one whose caller ignored the error) is its error. A scope inside another
/// joins it: they share the budget and the error.
///
/// # Errors
/// The [`WorkLimitError`] of the first limit hit; `f`'s value is then discarded (what was
/// computed after the hit is not meaningful).
pub fn limited<T>(f: impl FnOnce() -> T) -> Result<T, WorkLimitError> {
    match run_limited(f) {
        (value, None) => Ok(value),
        (_, Some(e)) => Err(e),
    }
}

/// [`limited`], keeping `f`'s value beside the limit hit: for a caller that prefers an error
/// `f` made itself from the limit (one that says which part of its work hit it).
pub fn run_limited<T>(f: impl FnOnce() -> T) -> (T, Option<WorkLimitError>) {
    let outermost = STATE.with(|s| {
        let depth = s.depth.get();
        if depth == 0 {
            s.limits.set(work_limits());
            s.work.set(0);
            s.error.set(None);
            s.tripped.set(false);
        }
        s.depth.set(depth + 1);
        depth == 0
    });
    let value = f();
    let err = STATE.with(|s| {
        s.depth.set(s.depth.get().saturating_sub(1));
        if outermost {
            s.tripped.set(false);
            s.error.take()
        } else {
            let e = s.error.take();
            s.error.set(e.clone());
            e
        }
    });
    (value, err)
}

/// The limit hit so far by the scope under way, if any (`None` outside a scope).
pub fn limit_hit() -> Option<WorkLimitError> {
    STATE.with(|s| {
        if s.tripped.get() {
            let e = s.error.take();
            s.error.set(e.clone());
            e
        } else {
            None
        }
    })
}

/// Whether the scope under way has hit a limit (its results are then discarded).
pub(crate) fn exceeded() -> bool {
    STATE.with(|s| s.tripped.get())
}

fn trip(s: &State, e: WorkLimitError) {
    if !s.tripped.get() {
        s.error.set(Some(e));
        s.tripped.set(true);
    }
}

/// Checks a polynomial size against [`WorkLimits::max_terms`]; `false` (and the limit
/// recorded) when it is past the limit inside a scope.
pub(crate) fn terms_ok(terms: usize) -> bool {
    STATE.with(|s| {
        let limit = s.limits.get().max_terms;
        if terms <= limit || s.depth.get() == 0 {
            return true;
        }
        trip(s, WorkLimitError::Terms { limit });
        false
    })
}

/// Checks the degree of a power against [`WorkLimits::max_degree`], like [`terms_ok`].
pub(crate) fn degree_ok(degree: u64) -> bool {
    STATE.with(|s| {
        let limit = s.limits.get().max_degree;
        if degree <= u64::from(limit) || s.depth.get() == 0 {
            return true;
        }
        trip(s, WorkLimitError::Degree { degree, limit });
        false
    })
}

/// Spends `units` of work in the scope under way; `false` (and the limit recorded) once the
/// scope is past [`WorkLimits::max_work`]. Outside a scope nothing is counted.
pub(crate) fn spend(units: u64) -> bool {
    STATE.with(|s| {
        if s.depth.get() == 0 {
            return true;
        }
        let work = s.work.get().saturating_add(units);
        s.work.set(work);
        let limit = s.limits.get().max_work;
        if work <= limit {
            return !s.tripped.get();
        }
        trip(s, WorkLimitError::Work { limit });
        false
    })
}
