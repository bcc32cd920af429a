//! Constraint reactions, two independent ways, and whether they agree.
//!
//! **Lagrange I.** The constraint is *released*: the bodies on one side of it get redundant
//! coordinates `u_i` (a displacement along direction `d_i`), the constraint is dropped, and the
//! released system's Lagrange equations read `E_u − Q_u = R·∂r/∂u_i = R·d_i`. Evaluated at
//! `u = u̇ = ü = 0` on the motion of the constrained system (accelerations eliminated with its
//! pure equations of motion, other multipliers from its DAE form), that generalized force is
//! the multiplier, i.e. the reaction. A constraint with no point (a rope written as an
//! equation, a gear) gives the generalized reaction `Q^R_j` on each coordinate instead.
//!
//! **Newton–Euler.** The momentum equation of the released bodies, `Σ m a_G = Σ F + R`, with
//! `a_G` the second time derivative of the centres' positions on the same motion: `R·d_i =
//! (Σ m a_G − Σ m g − Σ F)·d_i + ∂V/∂u_i + ∂D/∂u̇_i` (springs and dampers attached to the
//! released bodies act through the gradient of their potential with respect to the
//! displacement).
//!
//! **Sign convention.** Every reaction is the force that the constraint exerts *on the released
//! bodies*, in inertial components.

mod compare;
mod lagrange_one;
mod motion;
mod newton_euler;
mod numeric;
mod request;
mod result;

use crate::constraint_rank::{constraint_conflict, ConstraintConflict};
use crate::equations::{derive, Equations, MechanicsError};
use crate::system::System;

pub use numeric::{NumericGap, Quantity, ReactionColumn, ReactionEvaluator, ReactionState};
pub use request::{ReactionRequest, Release, ReleaseKind};
pub use result::{Agreement, Method, Reaction};

use lagrange_one::{constraint_reaction, driving_force, release_reaction};
use motion::Motion;

/// What can go wrong computing reactions.
#[derive(Debug, thiserror::Error, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum ReactionError {
    /// The constrained or the released system has no equations of motion.
    #[error("reaction `{reaction}`: {source}")]
    Mechanics {
        /// The reaction.
        reaction: String,
        /// Why.
        source: MechanicsError,
    },
    /// The accelerations (and multipliers) cannot be solved for.
    #[error("the equations of motion cannot be solved for the accelerations")]
    Unsolvable,
    /// The multipliers in closed form would be too large to be of use (the symbolic solve of
    /// `M q̈ + Aᵀλ = f, A q̈ = b` outgrew its budget).
    #[error("the reactions are too large to write in closed form (the symbolic solve for the multipliers went past {budget} terms in an entry)")]
    TooLarge {
        /// The term budget of an entry.
        budget: usize,
    },
    /// Another constraint moves with the released bodies; its multiplier would mix in.
    #[error("reaction `{reaction}`: constraint `{other}` involves the released bodies too; release it as well or ask for a combined reaction")]
    Entangled {
        /// The reaction.
        reaction: String,
        /// The other constraint.
        other: String,
    },
    /// The symbolic work went past a limit of the symbolic core ([`cas::WorkLimits`]).
    #[error("deriving the reactions: {0}")]
    WorkLimit(cas::WorkLimitError),
    /// The reaction cannot be evaluated numerically; its closed form is the route.
    #[error("reaction `{reaction}` cannot be evaluated numerically: {gap}")]
    NotNumeric {
        /// The reaction.
        reaction: String,
        /// Why.
        gap: NumericGap,
    },
    /// A constraint named in a reaction is unknown.
    #[error("no constraint `{0}`")]
    UnknownConstraint(String),
    /// Constraints kept with multipliers depend on one another: their separate reactions are
    /// not determined, or they cannot hold at once.
    #[error(transparent)]
    Conflict(#[from] ConstraintConflict),
}

/// The reactions asked for, on the motion of `system`.
///
/// # Errors
/// The system has no equations of motion, they cannot be solved for the accelerations, a
/// released constraint is entangled with another one, or constraints kept with multipliers
/// are redundant or contradictory ([`ReactionError::Conflict`]).
pub fn reactions(
    system: &System,
    requests: &[ReactionRequest],
) -> Result<Vec<Reaction>, ReactionError> {
    let equations = derive(system).map_err(|source| ReactionError::Mechanics {
        reaction: "(the constrained system)".to_string(),
        source,
    })?;
    reactions_of(system, &equations, requests)
}

/// `f` within the work limits of the symbolic core: past one, the error `f` made of it (a
/// derivation's, which names the part) or [`ReactionError::WorkLimit`].
fn limited<T>(f: impl FnOnce() -> Result<T, ReactionError>) -> Result<T, ReactionError> {
    match cas::run_limited(f) {
        (result, None) => result,
        (
            Err(
                e @ ReactionError::Mechanics {
                    source: MechanicsError::WorkLimit { .. },
                    ..
                },
            ),
            Some(_),
        ) => Err(e),
        (_, Some(error)) => Err(ReactionError::WorkLimit(error)),
    }
}

/// [`reactions`] when the equations of `system` are already derived.
///
/// # Errors
/// As [`reactions`].
pub fn reactions_of(
    system: &System,
    equations: &Equations,
    requests: &[ReactionRequest],
) -> Result<Vec<Reaction>, ReactionError> {
    limited(|| reactions_within(system, equations, requests))
}

fn reactions_within(
    system: &System,
    equations: &Equations,
    requests: &[ReactionRequest],
) -> Result<Vec<Reaction>, ReactionError> {
    if let Some(conflict) = constraint_conflict(system, equations) {
        return Err(conflict.into());
    }
    let motion = Motion::of(equations)?;
    requests
        .iter()
        .map(|request| match request {
            ReactionRequest::Release(release) => release_reaction(system, release, &motion),
            ReactionRequest::Constraint { name, without } => {
                if !system.constraints().iter().any(|c| &c.name == name) {
                    return Err(ReactionError::UnknownConstraint(name.clone()));
                }
                constraint_reaction(name, without, equations, &motion)
            }
            ReactionRequest::Driven {
                name,
                without,
                motion: prescribed,
            } => driving_force(name, without, *prescribed, &motion),
        })
        .collect()
}
