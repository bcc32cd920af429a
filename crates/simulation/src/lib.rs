//! Simulation of a lagrange model: the equations of motion derived by `mechanics` are
//! compiled once into register tapes ([`numeric::Tape`]) and integrated by `numeric`'s methods.
//!
//! * [`Simulation::prepare`]: model (with `--set` overrides already applied) → compiled
//!   equations, initial state, settings. Everything that can be wrong with the input is found
//!   here, before any step.
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
mod run;

pub use run::{MethodName, RecordedCrossing, Simulation, SimulationError, SimulationOptions};
