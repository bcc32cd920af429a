//! Simulation of a lagrange model: the equations of motion derived by `mechanics` are
//! compiled once into register tapes ([`numeric::Tape`]) and integrated by `numeric`'s methods.
//!
//! * [`Simulation::prepare`]: a [`mechanics::System`] and its derived
//!   [`mechanics::Equations`], with values, initial state and events ([`Setup`]) and resolved
//!   [`Settings`] → compiled equations. Nothing is derived here, so one derivation serves many
//!   runs (sweeps); everything that can be wrong with the input is found here, before any
//!   step. The model language is not known here: the `lagrange` crate reads a model's
//!   settings and values and hands them over.
//! * [`Simulation::run`]: integrates and hands each output row
//!   `[t, q…, q̇…, energy error, constraint drift]` ([`Simulation::columns`]) to a callback,
//!   then returns the [`numeric::Outcome`] (finished, event, or a failure with its time).
//!
//! | symbol | meaning | shape |
//! |---|---|---|
//! | `M(q,t) q̈ = f(q,q̇,t) − Aᵀλ` | equations of motion | n×n, n |
//! | `A q̈ = b` | constraints kept with multipliers (acceleration level) | m×n, m |
//! | `Φ(q,t) = 0`, `c(q,q̇,t) = 0` | the same constraints at position and velocity level | m |
//! | `p = ∂L/∂q̇ = M q̇ + p₀`, `ṗ = ∂L/∂q + Q` | Hamilton's form, for the symplectic method | n |
#![warn(missing_docs)]

mod compiled;
mod forms;
mod kane;
mod run;

pub use run::{
    Drift, InitialCorrection, Limit, MethodName, NumericContacts, RecordedCrossing, RhsRoutes,
    Settings, Setup, Simulation, SimulationError, StopEvent,
};
