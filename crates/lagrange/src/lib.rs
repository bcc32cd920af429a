//! lagrange: analytical mechanics from a model file, model text or a system built in code —
//! the equations of motion (Lagrange II), first integrals, constraint reactions (Lagrange I
//! and Newton–Euler), equilibria with their stability, linearized dynamics, simulations,
//! sweeps and the step-by-step solution. This crate is the one entry point: the command
//! line and the Python package are glue over it.
//!
//! An [`Analysis`] holds one system; each result is computed once, when first asked for,
//! and kept. A pendulum built in code, derived, its equilibria found and linearized, and
//! simulated:
//!
//! ```
//! use lagrange::cas::Expr;
//! use lagrange::mechanics::{Load, Particle, System};
//! use lagrange::{Analysis, SimulationOptions};
//!
//! // A simple pendulum: x = l sin θ, y = −l cos θ, gravity −g ŷ.
//! let theta = Expr::coordinate("theta");
//! let (m, l, g) = (Expr::symbol("m"), Expr::symbol("l"), Expr::symbol("g"));
//! let mut system = System::new();
//! system.add_coordinate("theta");
//! system.add_parameter("m", Some(Expr::from(1)));
//! system.add_parameter("l", Some(Expr::from(2)));
//! system.add_parameter("g", Some(Expr::float(9.81)));
//! system.add_particle(Particle {
//!     name: "P".into(),
//!     mass: m,
//!     position: [l * theta.sin(), -(l * theta.cos()), Expr::zero()],
//! });
//! system.add_load(Load::Gravity([Expr::zero(), -g, Expr::zero()]));
//!
//! let mut pendulum = Analysis::from_system(system);
//! let equations = pendulum.equations()?;
//! assert!(equations.mass_matrix()[0][0].equals(m * l.powi(2)));
//!
//! // Two equilibria: hanging (stable, ω = √(g/l)) and upright (unstable).
//! let equilibria = pendulum.equilibria()?;
//! assert_eq!(equilibria.set.equilibria.len(), 2);
//! let frequencies: Vec<f64> = equilibria
//!     .linearized
//!     .iter()
//!     .filter_map(|l| l.as_ref().ok()?.frequencies().first().copied().flatten())
//!     .collect();
//! assert_eq!(frequencies.len(), 1);
//! assert!((frequencies[0] - (9.81f64 / 2.0).sqrt()).abs() < 1e-9);
//!
//! // Released from 0.1 rad: after one small-oscillation period it is back near 0.1.
//! pendulum.set_value("theta", 0.1)?;
//! let period = 2.0 * std::f64::consts::PI / frequencies[0];
//! let options = SimulationOptions { t_end: Some(period), ..SimulationOptions::default() };
//! let run = pendulum.simulate(&options)?;
//! let last = run.rows.last().expect("rows");
//! assert!((last[1] - 0.1).abs() < 1e-3);
//! assert_eq!(pendulum.derivations(), 1); // derived once for all of the above
//! # Ok::<(), lagrange::Error>(())
//! ```
//!
//! From a model file instead: [`Analysis::from_file`] (or [`Analysis::from_text`]); values
//! are set with [`Analysis::set`] from `NAME=VALUE` text ([`parse_assignment`]) or
//! [`Analysis::set_value`]. Errors carry their [`ErrorKind`]: the user's mistake, degenerate
//! mechanics, or an inconsistency of lagrange's own.
#![warn(missing_docs)]

mod analysis;
pub mod assign;
mod chart;
mod chart_modes;
pub mod csv;
mod equilibria;
mod equilibria_conditions;
mod error;
pub mod expression;
mod figure;
mod floquet;
mod formats;
mod kane_eom;
mod kane_motion;
mod kane_solution;
mod modes;
mod output;
mod plot_extras;
mod projection;
mod question;
mod reaction_values;
mod reactions;
mod runs;
mod simulate;
mod solve;
mod steady;
mod steady_condition;
pub mod steady_print;
mod working;
mod written;

pub use analysis::{Analysis, Source};
pub use assign::{parse_assignment, parse_range, Assignment, AssignmentError, Range};
pub use chart::{AtPole, PoleSpin, PoleStability};
pub use chart_modes::ChartModes;
pub use equilibria::{Deviations, Equilibria, EquilibriumSweep, Search, SweepStep, DEFAULT_RANGE};
pub use equilibria_conditions::Conditions as StabilityConditions;
pub use error::{Error, ErrorKind, ModelErrors, OneRunOnly};
pub use floquet::{Floquet, FloquetChart, FloquetError, FloquetOptions};
pub use formats::{
    json_text, kane_written, Dialect, Linearized, ReportFormat, ResultFormat, Written,
};
pub use kane_eom::{kane_json, kane_text, KaneEom, Method};
pub use output::{FileFormat, Output, SolutionOutput};
pub use projection::ProjectedReaction;
pub use question::{Answer, EquilibriumQuestion, Misuse, QuestionError, QuestionPart};
pub use reaction_values::{
    AtEquilibria, ReactionProbe, ReactionRoute, ReactionValues, CLOSED_FORM_KKT, CLOSED_FORM_WORK,
};
pub use reactions::{NumericMultipliers, Reactions};
pub use runs::{correction_warning, duration, SweepRequest, SweepTable};
pub use simulate::{
    direction, failure_time, grid, plan, run_kept, run_sampled, run_to_csv,
    run_to_csv_with_reactions, samples, Crossing, Ending, Remedy, Run, SimulationOptions, Streamed,
    SweepRun, Tally, DEFAULT_MAX_BYTES,
};
pub use solve::{Figures, Solution, PNG_SCALE};
pub use steady::{CanonicalForm, ChangeKind, StabilityChange, SteadySweep};
pub use steady_condition::{
    condition_json as steady_condition_json, condition_lines as steady_condition_lines,
};
pub use written::{check_output, create, write_file, PreparedRun, RunFiles, WrittenRun};

pub use cas;
pub use draw;
pub use mechanics;
pub use model;
pub use numeric;
pub use report;
pub use simulation;
pub use simulation::MethodName;
