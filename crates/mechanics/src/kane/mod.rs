//! Kane's method over the expression graph: generalized speeds, nonholonomic constraints
//! eliminated through dependent speeds, the reduced equations `M_r u̇ = f_r`, and their
//! linearization about a steady motion.
//!
//! Nothing here builds the normal form of an equation. The [`System`](crate::System)'s expressions (positions,
//! rotation matrices, constraints) are hash-consed graphs; they become one flat [`Program`]
//! (each shared sub-expression one slot), evaluated with dual numbers for exact derivatives:
//! velocities and accelerations as Taylor coefficients in time, partial velocities as
//! directional derivatives, and the linearization as one more derivative. The reduced
//! equations are thus a procedure, exact to rounding at any state, whose cost grows with the
//! size of the geometry's graph rather than with the expanded equations (docs/mechanics.md,
//! "Kane's method").
//!
//! | symbol | meaning | shape |
//! |---|---|---|
//! | `q`, `q̇` | coordinates and their rates | n |
//! | `A q̇ + b = 0` | velocity constraints (holonomic ones differentiated), independent rows | m×n |
//! | `u` | independent speeds: the rates not fixed by the constraints | p = n − m |
//! | `q̇ = T u + s` | the rates from the speeds | n×p |
//! | `M_r u̇ = f_r` | Kane's equations `Tᵀ(F + F*) = 0` | p×p, p |

mod agree;
mod dynamics;
mod forces;
mod linear;
mod motion;
mod program;
mod rank;
mod scalar;
mod split;
mod steady;
mod steady_condition;
mod steady_rates;
mod symbolic;
mod verdict;

pub use agree::Agreement;
pub use dynamics::{KaneSystem, Reduced, SpeedSplit};
pub use motion::KaneMotion;
pub use program::{Program, Variables};
pub use rank::constraint_rank;
pub use scalar::{Dual, Scalar};
pub use steady::{SteadyLinearization, SteadyMotion};
pub use steady_condition::{exact_value, fresh_lambda, ExactSteadyMotion};
pub use symbolic::{KaneEquations, Sym, MAX_NODES, MAX_PROGRAM};
pub use verdict::{SteadySpectrum, SteadyVerdict};

use thiserror::Error;

/// What can go wrong in Kane's method.
#[derive(Clone, Debug, Error, PartialEq)]
#[non_exhaustive]
pub enum KaneError {
    /// A symbol in the system that is neither a coordinate, its rate, time nor a named value.
    #[error("`{0}` has no value: give every parameter and input a value")]
    UnknownSymbol(String),
    /// An acceleration inside a model expression.
    #[error("the acceleration of `{0}` appears in an expression; Kane's method takes forces of positions and rates only")]
    Acceleration(String),
    /// A function with the wrong number of arguments.
    #[error("`{0}` has the wrong number of arguments")]
    Arity(&'static str),
    /// A function the numeric evaluation does not know.
    #[error("the function `{0}` cannot be evaluated")]
    UnknownFunction(&'static str),
    /// The constraints leave no coordinate free, or a matrix to solve is singular.
    #[error("{0} is singular at this state")]
    Singular(&'static str),
    /// A holonomic constraint that cannot be satisfied near the given configuration.
    #[error(
        "the holonomic constraints have no solution near the given configuration (residual {0:e})"
    )]
    NoConfiguration(f64),
    /// The given motion is not steady.
    #[error("the motion is not steady: the speeds change at the rate {0:e}")]
    NotSteady(f64),
    /// The steady rates are not fixed by the rates given and the constraints.
    #[error("the rates of the steady motion are not fixed: give the rate of one of {0}")]
    RatesNotFixed(String),
    /// The rates given contradict the constraints.
    #[error("the rates given break the constraints (residual {0:e})")]
    RatesBreakConstraints(f64),
    /// A coordinate that moves in a steady motion changes the equations.
    #[error("`{0}` changes at a steady motion, but the equations depend on it: a steady motion keeps such coordinates constant")]
    MovingShape(String),
    /// A parameter value missing.
    #[error("{0}")]
    Value(String),
    /// The symbolic form is over a size limit (the Whipple bicycle's).
    #[error(
        "{what} has {size} operations, over the limit of {limit} for printing it symbolically"
    )]
    TooLarge {
        /// What is too large.
        what: &'static str,
        /// Its size.
        size: usize,
        /// The limit.
        limit: usize,
    },
    /// The normal form of the symbolic equations passed the work limits.
    #[error("the normal form of Kane's equations: {0}")]
    WorkLimit(cas::WorkLimitError),
}

impl KaneError {
    /// Whether the mistake is in the input (a value, the steady motion asked for) rather than
    /// in the mechanics.
    #[must_use]
    pub fn is_input(&self) -> bool {
        matches!(
            self,
            KaneError::UnknownSymbol(_)
                | KaneError::RatesNotFixed(_)
                | KaneError::RatesBreakConstraints(_)
                | KaneError::MovingShape(_)
                | KaneError::Value(_)
        )
    }
}
