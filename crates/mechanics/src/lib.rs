//! Mechanics over `cas` expressions: the checked input [`System`], and Lagrange's equations of
//! the second kind [`derive()`] → [`Equations`].
//!
//! | symbol | meaning | shape |
//! |---|---|---|
//! | `q` | independent generalized coordinates | n |
//! | `K`, `V`, `L = K − V` | kinetic energy, potential energy, Lagrangian (`U = −V`) | scalar |
//! | `Q` | generalized forces by virtual work, damping `−∂D/∂q̇` included | n |
//! | `M(q,t) q̈ = f(q,q̇,t)` | the equations of motion | n×n, n |
//! | `A q̈ = b` | constraints kept with multipliers: `M q̈ + Aᵀλ = f` | m×n, m |
//!
//! ```
//! use cas::Expr;
//! use mechanics::{derive, Load, Particle, System};
//! // A simple pendulum: x = l sin θ, y = −l cos θ, gravity −g ŷ.
//! let th = Expr::coordinate("theta");
//! let (m, l, g) = (Expr::symbol("m"), Expr::symbol("l"), Expr::symbol("g"));
//! let mut system = System::new();
//! system.add_coordinate("theta");
//! system.add_particle(Particle {
//!     name: "P".into(),
//!     mass: m,
//!     position: [l * th.sin(), -(l * th.cos()), Expr::zero()],
//! });
//! system.add_load(Load::Gravity([Expr::zero(), -g, Expr::zero()]));
//! let eq = derive(&system).unwrap();
//! assert!(eq.mass_matrix()[0][0].equals(m * l.powi(2)));
//! assert!(eq.forcing()[0].equals(-(m * g * l * th.sin())));
//! ```
#![warn(missing_docs)]

pub mod canonical;
mod compiled_eval;
mod configuration;
mod constraint_rank;
mod equations;
pub mod equilibria;
pub mod kane;
mod kkt;
pub mod linearize;
mod parameter_signs;
mod polynomial_rest;
mod reactions;
pub mod stability_condition;
mod system;
mod tree;
mod unilateral;

pub use configuration::{configuration, keep_distinct_configurations};
pub use constraint_rank::{constraint_conflict, ConstraintConflict};
pub use equations::{
    angular_velocity, derive, derive_without_first_integrals, Elimination, Equations,
    FirstIntegral, MechanicsError, Part,
};
pub use kkt::{null_space, KeptRest};
pub use parameter_signs::Inequality;
pub use polynomial_rest::RestPolynomial;
pub use reactions::{
    reactions, reactions_of, Agreement, Method, NumericGap, Quantity, Reaction, ReactionColumn,
    ReactionError, ReactionEvaluator, ReactionRequest, ReactionState, Release, ReleaseKind,
};
pub use system::{
    rotation_about, Constraint, ConstraintForm, Load, Particle, RigidBody, Rotation, System, Vector,
};
pub use tree::{KinematicTree, TreeNode};
pub use unilateral::{along_motion, scan as scan_unilateral, Unilateral};
