//! Numbers only: the compiled evaluator [`Tape`], small dense solves ([`solve_in_place`]), the
//! O(n) articulated-body solve of a tree-structured `M q̈ = f` ([`Articulated`]), the
//! integrators ([`integrate()`]), root finding and eigenproblems.
//!
//! This crate knows the symbolic core (`cas`) and nothing of mechanics.
#![warn(missing_docs)]

mod articulated;
pub mod eigen;
pub mod integrate;
mod linalg;
pub mod roots;
mod tape;

pub use articulated::{Articulated, ArticulatedError, ArticulatedNode};
pub use integrate::{
    integrate, integrate_observed, integrate_with_crossings, Crossing, Failure, IntegratorOptions,
    Method, OdeSystem, Outcome, RhsError, Stats, StopReason, DEFAULT_MAX_OUTPUTS,
    DEFAULT_MAX_STEPS, PILOT_STEPS, STEP_COLLAPSE_FRACTION, STIFF_H_LAMBDA, STIFF_PROJECTED_STEPS,
    STIFF_STEPS,
};
pub use linalg::{cholesky_solve_in_place, solve_in_place, LinearError};
pub use tape::{Tape, TapeError};
