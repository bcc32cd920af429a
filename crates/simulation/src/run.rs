//! Preparing and running a simulation: settings from the model's `simulate` statement and the
//! command line, the initial state, and the output rows.

use std::fmt;
use std::ops::ControlFlow;
use std::sync::Arc;

use cas::ParseContext;
use mechanics::kane::{KaneMotion, KaneSystem};
use mechanics::{Equations, System};
use std::cell::RefCell;

use numeric::{
    integrate_observed, Crossing, IntegratorOptions, Method, OdeSystem, Outcome, RhsError,
    TapeError,
};

use crate::compiled::{Compiled, Evaluator};
use crate::forms::{Canonical, SecondOrder};
use crate::kane::{KaneOde, KaneRoute, KaneRows};

/// An integration method, by the name the user gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum MethodName {
    /// `dopri5` (also `rk45`): adaptive Dormand–Prince 5(4) with dense output.
    Dopri5,
    /// `dop853`: adaptive Dormand–Prince 8(5,3) with dense output of order 7; fewer
    /// evaluations than dopri5 at tight tolerances.
    Dop853,
    /// `gauss` (also `symplectic`): Gauss–Legendre order 6 on Hamilton's equations.
    Gauss,
    /// `sdirk` (also `implicit`, `stiff`): L-stable SDIRK of order 2 for stiff systems.
    Sdirk,
}

impl MethodName {
    /// Reads a method name; `None` for a name that is not known.
    #[must_use]
    pub fn parse(name: &str) -> Option<MethodName> {
        match name {
            "dopri5" | "rk45" | "rk" | "explicit" => Some(MethodName::Dopri5),
            "dop853" | "rk853" => Some(MethodName::Dop853),
            "gauss" | "symplectic" | "gauss-legendre" | "variational" => Some(MethodName::Gauss),
            "sdirk" | "implicit" | "stiff" | "bdf" => Some(MethodName::Sdirk),
            _ => None,
        }
    }

    /// The method of a run that names none: [`MethodName::Dop853`] below a relative
    /// tolerance of 1e-6, else [`MethodName::Dopri5`] — whichever takes fewer evaluations
    /// there (docs/simulation.md, "The default method").
    #[must_use]
    pub fn for_tolerance(rtol: f64) -> MethodName {
        if rtol < DOP853_BELOW_RTOL {
            MethodName::Dop853
        } else {
            MethodName::Dopri5
        }
    }
}

/// The relative tolerance below which a run that names no method uses dop853
/// ([`MethodName::for_tolerance`]). Measured on eight models (docs/simulation.md, "The
/// default method"): at rtol 1e-7 and below dop853 takes fewer evaluations than dopri5 on
/// every one (0.95× on the chaotic double pendulum, 0.36–0.72× on the others); at 1e-6 the
/// double pendulum still takes 13 % more with dop853.
const DOP853_BELOW_RTOL: f64 = 1e-6;

impl fmt::Display for MethodName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            MethodName::Dopri5 => "dopri5",
            MethodName::Dop853 => "dop853",
            MethodName::Gauss => "gauss",
            MethodName::Sdirk => "sdirk",
        })
    }
}

/// The resolved settings of one run (the caller merges the user's options with the model's
/// `simulate` statement and the defaults; [`Settings::new`] gives the defaults).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// The method.
    pub method: MethodName,
    /// Start time.
    pub t_start: f64,
    /// End time.
    pub t_end: f64,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// Time between output rows (`None`: every accepted step).
    pub output_step: Option<f64>,
    /// The integration step: fixed for gauss, initial for dopri5 (`None`: chosen).
    pub step: Option<f64>,
    /// The most integration steps; more stops the run (default:
    /// [`numeric::DEFAULT_MAX_STEPS`], 10⁶).
    pub max_steps: u64,
    /// The most output rows (the initial row included); the run stops when one more is
    /// due (default: [`numeric::DEFAULT_MAX_OUTPUTS`], 10⁶).
    pub max_rows: u64,
}

impl Settings {
    /// The integrator's share of the settings.
    fn integrator_options(&self) -> IntegratorOptions {
        IntegratorOptions {
            rtol: self.rtol,
            atol: self.atol,
            step: self.step,
            output_step: self.output_step,
            max_steps: self.max_steps,
            max_outputs: self.max_rows,
        }
    }
}

impl Settings {
    /// From 0 to `t_end`, `rtol` 1e-8, `atol` 1e-10, with the method for that tolerance
    /// ([`MethodName::for_tolerance`]: dop853), a row every accepted step, at most 10⁶ steps
    /// and 10⁶ rows.
    #[must_use]
    pub fn new(t_end: f64) -> Settings {
        Settings {
            method: MethodName::for_tolerance(1e-8),
            t_start: 0.0,
            t_end,
            rtol: 1e-8,
            atol: 1e-10,
            output_step: None,
            step: None,
            max_steps: IntegratorOptions::default().max_steps,
            max_rows: IntegratorOptions::default().max_outputs,
        }
    }

    /// Checks every number: finite, positive where it must be, the span not empty.
    ///
    /// # Errors
    /// [`SimulationError::InvalidSetting`] naming the setting.
    pub fn validate(&self) -> Result<(), SimulationError> {
        check_setting("start time", self.t_start, f64::is_finite, "must be finite")?;
        check_setting("end time", self.t_end, f64::is_finite, "must be finite")?;
        if self.t_end == self.t_start {
            return Err(SimulationError::EmptySpan { t: self.t_start });
        }
        check_setting(
            "rtol",
            self.rtol,
            |x| x > 0.0 && x < 1.0,
            "must be in (0, 1)",
        )?;
        check_setting(
            "atol",
            self.atol,
            |x| x > 0.0 && x.is_finite(),
            "must be positive",
        )?;
        let positive = |x: f64| x > 0.0 && x.is_finite();
        if let Some(s) = self.output_step {
            check_setting("output step", s, positive, "must be positive")?;
        }
        if let Some(s) = self.step {
            check_setting("integration step", s, positive, "must be positive")?;
        }
        if self.max_steps == 0 {
            return Err(SimulationError::InvalidSetting {
                setting: "step limit",
                reason: "0 must be at least 1".to_owned(),
            });
        }
        if self.max_rows == 0 {
            return Err(SimulationError::InvalidSetting {
                setting: "row limit",
                reason: "0 must be at least 1".to_owned(),
            });
        }
        Ok(())
    }

    /// Checks, before any step, that a run that nothing stops early stays within the
    /// limits: the rows every output step over the span (the initial one included), and the
    /// steps of gauss's fixed step. A run with stop events may end sooner and is not
    /// checked; it meets the limits as it goes.
    ///
    /// # Errors
    /// [`SimulationError::BeyondLimit`] with the count the settings ask for.
    pub fn check_limits(&self) -> Result<(), SimulationError> {
        let span = (self.t_end - self.t_start).abs();
        if let Some(step) = self.output_step {
            let rows = (span / step).floor() + 1.0;
            if rows > self.max_rows as f64 {
                return Err(self.beyond(Limit::Rows, rows, step));
            }
        }
        if let (MethodName::Gauss, Some(step)) = (self.method, self.step) {
            let steps = (span / step).ceil();
            if steps > self.max_steps as f64 {
                return Err(self.beyond(Limit::Steps, steps, step));
            }
        }
        Ok(())
    }

    fn beyond(&self, limit: Limit, count: f64, step: f64) -> SimulationError {
        SimulationError::BeyondLimit {
            limit,
            count,
            allowed: match limit {
                Limit::Rows => self.max_rows,
                Limit::Steps => self.max_steps,
            },
            t_start: self.t_start,
            t_end: self.t_end,
            step,
        }
    }
}

/// A limit of a run that its settings alone would exceed ([`Settings::check_limits`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// Output rows, one every output step.
    Rows,
    /// Integration steps of a fixed step (gauss).
    Steps,
}

impl fmt::Display for Limit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Limit::Rows => "row",
            Limit::Steps => "step",
        })
    }
}

/// An event that stops a run where its expression crosses zero, by what it means.
#[derive(Debug, Clone, PartialEq)]
pub enum StopEvent {
    /// A condition the user wrote (an expression of `t`, the coordinates `q`, the rates
    /// `q_d` and the parameters), parsed when the run is prepared.
    Condition(String),
    /// A one-sided constraint (a contact pushes, a rope pulls) is lost where its reaction
    /// `value` (≥ 0 while it holds) crosses zero.
    ContactLost {
        /// The reaction's name in the model.
        constraint: String,
        /// The reaction along its one allowed direction, an expression of `t`, `q`, `q̇`.
        value: cas::Expr,
    },
    /// A one-sided constraint is lost where its reaction, evaluated numerically
    /// ([`NumericContacts`]), crosses zero.
    NumericContactLost {
        /// The reaction's name in the model.
        constraint: String,
    },
}

/// One-sided reactions evaluated numerically (issue 17): a run stops where one crosses zero,
/// as at a [`StopEvent::ContactLost`], without its closed form. Not with `gauss` (whose state
/// holds momenta): there the closed form is the route.
#[derive(Debug, Clone)]
pub struct NumericContacts {
    /// The reactions, compiled.
    pub evaluator: Arc<mechanics::ReactionEvaluator>,
    /// The values, in the order the evaluator was compiled with.
    pub values: Vec<f64>,
    /// Each one-sided reaction's name and its column among the evaluator's.
    pub columns: Vec<(String, usize)>,
}

impl PartialEq for NumericContacts {
    /// The same compiled reactions (by identity), values and columns.
    fn eq(&self, other: &NumericContacts) -> bool {
        Arc::ptr_eq(&self.evaluator, &other.evaluator)
            && self.values == other.values
            && self.columns == other.columns
    }
}

/// Everything a run needs besides the equations: values, initial state, events.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Setup {
    /// The numeric value of every parameter and every input held constant.
    pub values: Vec<(String, f64)>,
    /// Inputs given as functions of time: substituted into the equations before compiling.
    pub timed_inputs: Vec<(String, cas::Expr)>,
    /// The initial state: the coordinates, then their rates, in the order of
    /// [`mechanics::Equations::coordinates`].
    pub initial: Vec<f64>,
    /// Events that stop the run, in this order ([`Simulation::stop_event`] reads them back).
    pub stop_events: Vec<StopEvent>,
    /// Record (without stopping) every crossing of zero of these expressions of `t`, `q`,
    /// `q_d` and the parameters: [`Simulation::run_recording`] reports each with its
    /// direction, time and state.
    pub record_when: Vec<String>,
    /// One-sided reactions evaluated numerically that stop the run, after `stop_events`.
    pub numeric_contacts: Option<NumericContacts>,
}

/// A recorded zero crossing of a `record_when` expression.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecordedCrossing<'a> {
    /// Which `record_when` expression (its index in [`Setup::record_when`]).
    pub event: usize,
    /// From negative to positive (else from positive to negative).
    pub rising: bool,
    /// The state there as an output row (see [`Simulation::columns`]).
    pub row: &'a [f64],
}

/// `q̈` by the dense solve (or its error) and by the kinematic tree, where there is one
/// ([`Simulation::rhs_both_routes`]).
pub type RhsRoutes = (Result<Vec<f64>, RhsError>, Option<Vec<f64>>);

/// What stops a simulation before it starts.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimulationError {
    /// A setting is not a finite number, or out of range.
    #[error("invalid setting `{setting}`: {reason}")]
    InvalidSetting {
        /// The setting.
        setting: &'static str,
        /// Why.
        reason: String,
    },
    /// The end time equals the start time.
    #[error("the run would start and end at t = {}: the time span is empty; give an end time other than the start time", number_text(*t))]
    EmptySpan {
        /// The start (and end) time.
        t: f64,
    },
    /// The settings alone ask for more rows (or fixed steps) than the limit allows, and no
    /// stop event could end the run sooner.
    #[error("from t = {} to {} every {} makes {} {limit}s, more than the {limit} limit of {allowed}; shorten the span, lengthen the step, or raise the limit", number_text(*t_start), number_text(*t_end), number_text(*step), count_text(*count))]
    BeyondLimit {
        /// Which limit.
        limit: Limit,
        /// The rows or steps the settings ask for.
        count: f64,
        /// The limit.
        allowed: u64,
        /// Start time.
        t_start: f64,
        /// End time.
        t_end: f64,
        /// The output step (rows) or the fixed step (steps).
        step: f64,
    },
    /// An expression needs a value that was not given.
    #[error("{0}; give it a value")]
    MissingValue(TapeError),
    /// The equations handed over still hold an acceleration (or a higher derivative) of a
    /// coordinate: the derivation did not solve for it. Not the user's mistake: a bug.
    #[error("the equations of motion still hold `{name}`, a derivative of a coordinate that the derivation should have solved for; this is a bug of lagrange, please report it")]
    UnsolvedDerivative {
        /// The symbol (`y_dd`).
        name: String,
    },
    /// The initial state does not have two numbers (position, rate) per coordinate.
    #[error("the initial state has {given} numbers; {needed} are needed (the coordinates, then their rates)")]
    InitialState {
        /// How many were given.
        given: usize,
        /// How many are needed.
        needed: usize,
    },
    /// A stop condition does not parse, or names something unknown.
    #[error("stop condition `{text}`: {reason}")]
    StopCondition {
        /// The condition as written.
        text: String,
        /// What is wrong, with the column.
        reason: String,
    },
    /// An expression to record does not parse, or names something unknown.
    #[error("expression to record `{text}`: {reason}")]
    RecordCondition {
        /// The expression as written.
        text: String,
        /// What is wrong, with the column.
        reason: String,
    },
    /// The symplectic method needs an unconstrained system.
    #[error("gauss integrates Hamilton's equations and does not handle constraints kept with multipliers ({constraints}); use dopri5")]
    GaussWithConstraints {
        /// The constraints.
        constraints: String,
    },
    /// The initial state could not be made consistent, or the equations fail there.
    #[error("at the initial state: {0}")]
    Initial(RhsError),
    /// Kane's route could not be set up: the speeds, the initial configuration on the
    /// holonomic constraints or the initial rates ([`Simulation::prepare_kane`]).
    #[error("on Kane's route: {0}")]
    Kane(mechanics::kane::KaneError),
    /// Reactions by multipliers were asked of a run on Kane's route, whose reduced equations
    /// eliminate the constraints instead of keeping multipliers.
    #[error("the run is on Kane's route, whose reduced equations have no multipliers")]
    NoMultipliers,
    /// A run on Kane's route was asked for something it does not do (an input given as a
    /// function of time, the symplectic method).
    #[error("Kane's route does not take {0}")]
    KaneUnsupported(&'static str),
}

/// A symbol the compiled equations lack: a coordinate's second or higher derivative is the
/// derivation's failure, anything else a value the user did not give.
fn missing_value(error: TapeError, coordinates: &[String]) -> SimulationError {
    let TapeError::UnboundSymbol { name } = &error else {
        return SimulationError::MissingValue(error);
    };
    let derivative = coordinates.iter().any(|q| {
        name.strip_prefix(q.as_str())
            .and_then(|rest| rest.strip_prefix('_'))
            .is_some_and(|ds| ds.len() >= 2 && ds.chars().all(|c| c == 'd'))
    });
    if derivative {
        SimulationError::UnsolvedDerivative { name: name.clone() }
    } else {
        SimulationError::MissingValue(error)
    }
}

/// A time or step as a person reads it: in powers of ten when very large or small (`{}`
/// would write all 309 digits of 1e308).
fn number_text(x: f64) -> String {
    if x != 0.0 && (x.abs() >= 1e15 || x.abs() < 1e-4) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// A count of rows or steps as a person reads it: whole below 10¹⁵, else in powers of ten.
fn count_text(count: f64) -> String {
    if count < 1e15 {
        format!("{count:.0}")
    } else if count.is_finite() {
        format!("{count:.1e}")
    } else {
        "more than 10³⁰⁸".to_owned()
    }
}

/// The largest constraint residuals over the rows of a run (written rows and recorded
/// crossings), at position level (`|Φ_i(q,t)|` of the holonomic constraints kept with
/// multipliers) and at velocity level (`|c_i(q,q̇,t)|` of every kept constraint). NaN when the
/// constraint rows could not be matched to their constraints (the drift is unknown).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Drift {
    /// The largest `|Φ_i|` (0 when no kept constraint is holonomic).
    pub position: f64,
    /// The largest `|c_i|`.
    pub velocity: f64,
}

impl Drift {
    /// Takes in one state's residuals; NaN (unknown) stays NaN, which `max` would drop.
    pub(crate) fn note(&mut self, position: f64, velocity: f64) {
        let keep = |largest: f64, x: f64| {
            if largest.is_nan() || x.is_nan() {
                f64::NAN
            } else {
                largest.max(x)
            }
        };
        self.position = keep(self.position, position);
        self.velocity = keep(self.velocity, velocity);
    }
}

/// How the initial state was moved onto the constraints kept with multipliers.
#[derive(Debug, Clone, PartialEq)]
pub struct InitialCorrection {
    /// The state as given: coordinates, then rates.
    pub given: Vec<f64>,
    /// The state on the constraints, from which the run starts.
    pub corrected: Vec<f64>,
}

impl InitialCorrection {
    /// The values that moved, `name = given → corrected`, by the run's column names
    /// ([`Simulation::columns`]).
    #[must_use]
    pub fn describe(&self, columns: &[String]) -> String {
        columns
            .iter()
            .skip(1)
            .zip(self.given.iter().zip(&self.corrected))
            .filter(|(_, (a, b))| a != b)
            .map(|(name, (a, b))| format!("{name} = {a} → {b:.6}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// A prepared simulation: compiled equations, initial state, settings.
#[derive(Debug, Clone)]
pub struct Simulation {
    route: Route,
    coordinates: Vec<String>,
    method: MethodName,
    t_start: f64,
    t_end: f64,
    options: IntegratorOptions,
    initial: Vec<f64>,
    correction: Option<InitialCorrection>,
    initial_energy: f64,
    stop_events: Vec<StopEvent>,
    record_when: Vec<String>,
    drift: Drift,
}

/// How the right-hand side is evaluated.
#[derive(Debug, Clone)]
enum Route {
    /// The derived equations `M q̈ = f − Aᵀλ`, compiled.
    Lagrange(Box<Compiled>),
    /// Kane's reduced equations, evaluated numerically ([`Simulation::prepare_kane`]).
    Kane(Box<KaneRoute>),
}

/// Initial states that differ by less than this (relative to their size) are the same.
const MOVED: f64 = 1e-9;

impl Simulation {
    /// Compiles `equations` with the values of `setup` and sets up a run of `settings`.
    /// Nothing is derived here: the caller derives once and may prepare many runs.
    ///
    /// # Errors
    /// A [`SimulationError`] saying what is missing or wrong.
    pub fn prepare(
        system: &System,
        equations: &Equations,
        settings: &Settings,
        setup: Setup,
    ) -> Result<Simulation, SimulationError> {
        settings.validate()?;
        if setup.stop_events.is_empty() && setup.numeric_contacts.is_none() {
            settings.check_limits()?;
        }
        let coordinates = equations.coordinates().to_vec();
        let n = coordinates.len();
        if setup.initial.len() != 2 * n {
            return Err(SimulationError::InitialState {
                given: setup.initial.len(),
                needed: 2 * n,
            });
        }
        if settings.method == MethodName::Gauss && !equations.constraint_names().is_empty() {
            return Err(SimulationError::GaussWithConstraints {
                constraints: equations.constraint_names().join(", "),
            });
        }
        let (events, stopping_events) = compile_events(&coordinates, &setup)?;
        let mut compiled = Compiled::new(
            system,
            equations,
            &setup.values,
            &setup.timed_inputs,
            &events,
            stopping_events,
            settings.method == MethodName::Gauss,
        )
        .map_err(|e| missing_value(e, &coordinates))?;
        // The momenta of `gauss` give no accelerations to evaluate the reactions with.
        let mut stop_events = setup.stop_events;
        if settings.method != MethodName::Gauss {
            if let Some(contacts) = setup.numeric_contacts {
                stop_events.extend(contacts.columns.iter().map(|(name, _)| {
                    StopEvent::NumericContactLost {
                        constraint: name.clone(),
                    }
                }));
                compiled.contacts = Some(contacts);
            }
        }

        let t_start = settings.t_start;
        let (initial, correction) = start_on_constraints(&mut compiled, t_start, setup.initial)?;
        compiled.set_state(&initial[..n], &initial[n..], t_start);
        let (initial_energy, _) = compiled.energy_and_drift();

        Ok(Simulation {
            route: Route::Lagrange(Box::new(compiled)),
            coordinates,
            method: settings.method,
            t_start,
            t_end: settings.t_end,
            options: settings.integrator_options(),
            initial,
            correction,
            initial_energy,
            stop_events,
            record_when: setup.record_when,
            drift: Drift::default(),
        })
    }

    /// Sets up a run on Kane's route: the reduced equations `M_r u̇ = f_r` of `system`
    /// evaluated numerically at each state ([`mechanics::kane::KaneMotion`]), for systems
    /// whose equations with multipliers are too large to derive. `setup.initial` holds the
    /// coordinates, then the rates; `given[j]` says whether rate `j` was given: the speeds
    /// give those exactly and the others as the constraints fix them (as small as they
    /// allow where they leave them free). The holonomically fixed coordinates are moved onto
    /// their constraints by Newton's method. One-sided contacts are not watched here.
    ///
    /// # Errors
    /// As [`Simulation::prepare`]; [`SimulationError::Kane`] when no speed is free, the
    /// holonomic constraints have no solution near the initial configuration or the given
    /// rates break the constraints; [`SimulationError::KaneUnsupported`] for `gauss` or an
    /// input given as a function of time.
    pub fn prepare_kane(
        system: &System,
        settings: &Settings,
        setup: Setup,
        given: &[bool],
    ) -> Result<Simulation, SimulationError> {
        settings.validate()?;
        if setup.stop_events.is_empty() {
            settings.check_limits()?;
        }
        let coordinates = system.coordinates().to_vec();
        let n = coordinates.len();
        if setup.initial.len() != 2 * n || given.len() != n {
            return Err(SimulationError::InitialState {
                given: setup.initial.len(),
                needed: 2 * n,
            });
        }
        if settings.method == MethodName::Gauss {
            return Err(SimulationError::KaneUnsupported(
                "the symplectic method gauss (use dop853 or dopri5)",
            ));
        }
        if !setup.timed_inputs.is_empty() {
            return Err(SimulationError::KaneUnsupported(
                "inputs given as functions of time",
            ));
        }
        let t_start = settings.t_start;
        let route = kane_route(system, &coordinates, &setup, given, t_start)?;
        let mut initial = route.start_full.clone();
        // The rates not given are not the user's: they are reported as found, not as moved.
        let mut asked = setup.initial.clone();
        for (j, g) in given.iter().enumerate() {
            if !g {
                asked[n + j] = initial[n + j];
            }
        }
        let moved = asked
            .iter()
            .zip(&initial)
            .any(|(a, b)| (a - b).abs() > MOVED * (1.0 + a.abs()));
        let correction = moved.then(|| InitialCorrection {
            given: asked,
            corrected: initial.clone(),
        });
        let initial_energy = route.energy(t_start, &initial);
        initial.truncate(2 * n);
        Ok(Simulation {
            route: Route::Kane(Box::new(route)),
            coordinates,
            method: settings.method,
            t_start,
            t_end: settings.t_end,
            options: settings.integrator_options(),
            initial,
            correction,
            initial_energy,
            stop_events: setup.stop_events,
            record_when: setup.record_when,
            drift: Drift::default(),
        })
    }

    /// Whether the run goes by Kane's reduced equations ([`Simulation::prepare_kane`]).
    #[must_use]
    pub fn by_kane(&self) -> bool {
        matches!(self.route, Route::Kane(_))
    }

    /// The stop event of an [`numeric::StopReason::Event`]'s index.
    #[must_use]
    pub fn stop_event(&self, index: usize) -> Option<&StopEvent> {
        // The tape's stopping events, its recorded ones, then the numeric contacts.
        let (stopping, tape) = match &self.route {
            Route::Lagrange(c) => (c.stopping_events, c.tape_event_count()),
            Route::Kane(k) => (k.stopping_events, k.event_outputs),
        };
        match index {
            i if i < stopping => self.stop_events.get(i),
            i if i >= tape => self.stop_events.get(stopping + (i - tape)),
            _ => None,
        }
    }

    /// The expressions recorded without stopping, as given.
    #[must_use]
    pub fn recorded(&self) -> &[String] {
        &self.record_when
    }

    /// How the initial state was moved onto the constraints, when it was not on them.
    #[must_use]
    pub fn initial_correction(&self) -> Option<&InitialCorrection> {
        self.correction.as_ref()
    }

    /// The names of the output columns: `t`, the coordinates, their rates `q_d`,
    /// `energy_error`, `constraint_drift`.
    #[must_use]
    pub fn columns(&self) -> Vec<String> {
        let mut columns = vec!["t".to_owned()];
        columns.extend(self.coordinates.iter().cloned());
        columns.extend(self.coordinates.iter().map(|q| format!("{q}_d")));
        columns.push("energy_error".to_owned());
        columns.push("constraint_drift".to_owned());
        columns
    }

    /// The largest constraint residuals over the rows of the last run (zeros before a run);
    /// `None` without constraints kept with multipliers.
    #[must_use]
    pub fn drift(&self) -> Option<Drift> {
        match &self.route {
            Route::Lagrange(c) => (c.m > 0).then_some(self.drift),
            Route::Kane(_) => Some(self.drift),
        }
    }

    /// The multipliers `λ` of `M q̈ + Aᵀλ = f`, `A q̈ = b` at time `t` and state `(q, q̇)`,
    /// one per constraint row (in the order of [`mechanics::Equations::constraint_names`]),
    /// solved numerically on the compiled equations: the reactions of the constraints kept
    /// with multipliers are `Q^R = −Aᵀλ`. Rows that depend on others there get 0.
    ///
    /// # Errors
    /// A state of the wrong length, or the KKT matrix singular there.
    pub fn multipliers_at(&mut self, t: f64, state: &[f64]) -> Result<Vec<f64>, SimulationError> {
        let n = self.coordinates.len();
        if state.len() != 2 * n {
            return Err(SimulationError::InitialState {
                given: state.len(),
                needed: 2 * n,
            });
        }
        let Route::Lagrange(compiled) = &mut self.route else {
            return Err(SimulationError::NoMultipliers);
        };
        if compiled.m == 0 {
            return Ok(Vec::new());
        }
        SecondOrder::new(compiled)
            .multipliers(t, state)
            .map_err(SimulationError::Initial)
    }

    /// The method that will run.
    #[must_use]
    pub fn method(&self) -> MethodName {
        self.method
    }

    /// The time span `(start, end)`.
    #[must_use]
    pub fn span(&self) -> (f64, f64) {
        (self.t_start, self.t_end)
    }

    /// The initial state `(q, q̇)` (projected onto the constraints when there are any).
    #[must_use]
    pub fn initial_state(&self) -> &[f64] {
        &self.initial
    }

    /// The energy at the start (the conserved `h` when there is one, else `K + V`).
    #[must_use]
    pub fn initial_energy(&self) -> f64 {
        self.initial_energy
    }

    /// How many tape instructions one right-hand side evaluation runs (the tree's tape where
    /// the right-hand side goes by the tree, see [`Simulation::rhs_by_tree`]).
    #[must_use]
    pub fn rhs_instructions(&self) -> usize {
        match &self.route {
            Route::Lagrange(c) => match &c.tree {
                Some(tree) if tree.preferred => tree.evaluator.instruction_count(),
                _ => c.dynamics.as_ref().map_or(0, Evaluator::instruction_count),
            },
            Route::Kane(k) => k.motion.system().size(),
        }
    }

    /// Whether `q̈` is evaluated in O(n) on the model's kinematic tree
    /// ([`mechanics::KinematicTree`], [`numeric::Articulated`]) rather than by the dense
    /// solve of `M q̈ = f`: a model without constraints whose tree is cheaper and agrees with
    /// the dense solve at sample states.
    #[must_use]
    pub fn rhs_by_tree(&self) -> bool {
        match &self.route {
            Route::Lagrange(c) => c.tree.as_ref().is_some_and(|t| t.preferred),
            Route::Kane(_) => false,
        }
    }

    /// Switches the right-hand side to the tree (`true`) or to the dense solve (`false`), for
    /// benchmarks that compare the routes in one process; returns whether it now goes by the
    /// tree (never where the model has none).
    pub fn set_rhs_by_tree(&mut self, by_tree: bool) -> bool {
        if let Route::Lagrange(c) = &mut self.route {
            // The dense route needs its tape, which the tree's route did not compile; where it
            // cannot be compiled the tree stays.
            let tree_stays = !by_tree && c.dense_tape().is_err();
            if let (false, Some(tree)) = (tree_stays, c.tree.as_mut()) {
                tree.preferred = by_tree;
            }
        }
        self.rhs_by_tree()
    }

    /// `q̈` at `(t, (q, q̇))` by the dense solve (or its error: a singular mass matrix) and,
    /// where the model has a kinematic tree that agrees with the dense solve (whether or not
    /// the right-hand side goes by it), by the tree (`None` otherwise, or where its
    /// elimination fails at the state): the two routes side by side, for tests and
    /// benchmarks. `None` when `state` does not hold two numbers per coordinate, or when the
    /// dense tape (compiled here if the tree's route did without it) cannot be compiled.
    pub fn rhs_both_routes(&mut self, t: f64, state: &[f64]) -> Option<RhsRoutes> {
        let Route::Lagrange(compiled) = &mut self.route else {
            return None;
        };
        if state.len() != 2 * compiled.n || compiled.dense_tape().is_err() {
            return None;
        }
        let mut system = SecondOrder::new(compiled);
        Some(system.both_routes(t, state))
    }

    /// Hands `body` the right-hand side `(t, (q, q̇)) → (q̇, q̈)` as the integrator sees it
    /// (buffers allocated once, outside `body`), for benchmarks and checks.
    pub fn with_rhs<R>(&mut self, body: impl FnOnce(&mut dyn OdeSystem) -> R) -> R {
        match &mut self.route {
            Route::Lagrange(compiled) => body(&mut SecondOrder::new(compiled)),
            Route::Kane(route) => body(&mut KaneOde { route }),
        }
    }

    /// The integrator's settings: tolerances, step, output step.
    #[must_use]
    pub fn integrator_options(&self) -> IntegratorOptions {
        self.options
    }

    /// Runs the simulation, handing each output row (see [`Simulation::columns`]) to
    /// `on_row`. With constraints, each written state is projected onto them (positions, then
    /// velocities), as the integrator's step ends are. The energy error is `(E − E₀)/|E₀|`, or
    /// `E − E₀` when `|E₀| < 1e-12`.
    pub fn run(&mut self, on_row: &mut dyn FnMut(&[f64])) -> Outcome {
        self.run_recording(on_row, &mut |_| {})
    }

    /// [`Simulation::run`], also handing every zero crossing of a `record_when` expression
    /// to `on_crossing`, in time order, with the state there as a row like the output rows.
    pub fn run_recording(
        &mut self,
        on_row: &mut dyn FnMut(&[f64]),
        on_crossing: &mut dyn FnMut(RecordedCrossing<'_>),
    ) -> Outcome {
        self.run_until(
            &mut |row| {
                on_row(row);
                ControlFlow::Continue(())
            },
            on_crossing,
        )
    }

    /// [`Simulation::run_recording`] with a row callback that may end the run: after a row
    /// for which it returns `Break`, the run stops there ([`numeric::StopReason::Halted`]).
    pub fn run_until(
        &mut self,
        on_row: &mut dyn FnMut(&[f64]) -> ControlFlow<()>,
        on_crossing: &mut dyn FnMut(RecordedCrossing<'_>),
    ) -> Outcome {
        let n = self.coordinates.len();
        let method = self.method;
        let (t0, t1, options) = (self.t_start, self.t_end, self.options);
        let compiled = match &mut self.route {
            Route::Lagrange(compiled) => compiled,
            Route::Kane(route) => {
                let (outcome, drift) = run_kane(
                    route,
                    (method, t0, t1, &options),
                    self.initial_energy,
                    on_row,
                    on_crossing,
                );
                self.drift = drift;
                return outcome;
            }
        };
        let stopping = compiled.stopping_events;
        // Rows and crossings are both written by the row maker; the integrator calls one
        // callback at a time, so they share it through a RefCell.
        let rows = RefCell::new(RowMaker::new(compiled, self.initial_energy));
        let outcome = match method {
            MethodName::Dopri5 | MethodName::Dop853 | MethodName::Sdirk => {
                let mut system = SecondOrder::new(compiled);
                integrate_observed(
                    &mut system,
                    match method {
                        MethodName::Sdirk => Method::Sdirk,
                        MethodName::Dop853 => Method::Dop853,
                        _ => Method::Dopri5,
                    },
                    t0,
                    &self.initial,
                    t1,
                    &options,
                    &mut |t, y| on_row(rows.borrow_mut().row(t, &y[..n], &y[n..])),
                    &mut |c: Crossing<'_>| {
                        let mut maker = rows.borrow_mut();
                        on_crossing(RecordedCrossing {
                            event: c.index.saturating_sub(stopping),
                            rising: c.rising,
                            row: maker.row(c.t, &c.y[..n], &c.y[n..]),
                        });
                    },
                )
            }
            MethodName::Gauss => {
                // p = M q̇ + p₀ at the start.
                let mut converter = (**compiled).clone();
                let mut y0 = self.initial.clone();
                {
                    let c = &mut converter;
                    c.set_state(&self.initial[..n], &vec![0.0; n], t0);
                    let inputs = c.inputs.clone();
                    if let Some((mass_momentum, _)) = c.canonical.as_mut() {
                        let out = mass_momentum.eval(&inputs);
                        for i in 0..n {
                            y0[n + i] = out[n * n + i]
                                + (0..n)
                                    .map(|k| out[i * n + k] * self.initial[n + k])
                                    .sum::<f64>();
                        }
                    }
                }
                let rates = RefCell::new(Canonical::new(&mut converter));
                let velocity = |t: f64, y: &[f64]| {
                    rates
                        .borrow_mut()
                        .velocity(t, y)
                        .unwrap_or_else(|_| vec![f64::NAN; n])
                };
                let mut system = Canonical::new(compiled);
                integrate_observed(
                    &mut system,
                    Method::Gauss,
                    t0,
                    &y0,
                    t1,
                    &options,
                    &mut |t, y| {
                        let qd = velocity(t, y);
                        on_row(rows.borrow_mut().row(t, &y[..n], &qd))
                    },
                    &mut |c: Crossing<'_>| {
                        let qd = velocity(c.t, c.y);
                        let mut maker = rows.borrow_mut();
                        on_crossing(RecordedCrossing {
                            event: c.index.saturating_sub(stopping),
                            rising: c.rising,
                            row: maker.row(c.t, &c.y[..n], &qd),
                        });
                    },
                )
            }
        };
        self.drift = rows.into_inner().drift;
        outcome
    }
}

/// Kane's route compiled for `setup`, its initial state found and the equations evaluated
/// there once (so that a state where they cannot be solved fails before the run).
fn kane_route(
    system: &System,
    coordinates: &[String],
    setup: &Setup,
    given: &[bool],
    t_start: f64,
) -> Result<KaneRoute, SimulationError> {
    let n = coordinates.len();
    let names: Vec<String> = setup.values.iter().map(|(name, _)| name.clone()).collect();
    let values: Vec<f64> = setup.values.iter().map(|(_, v)| *v).collect();
    let kane = KaneSystem::new(system, &names).map_err(SimulationError::Kane)?;
    let motion = KaneMotion::new(kane, values, &setup.initial[..n], t_start)
        .map_err(SimulationError::Kane)?;
    let rates: Vec<Option<f64>> = given
        .iter()
        .zip(&setup.initial[n..])
        .map(|(g, v)| g.then_some(*v))
        .collect();
    let start = motion
        .initial_state(&rates, t_start)
        .map_err(SimulationError::Kane)?;
    let (events, stopping_events) = compile_events(coordinates, setup)?;
    let mut route = KaneRoute::new(motion, coordinates, &setup.values, &events, stopping_events)
        .map_err(|e| missing_value(e, coordinates))?;
    let mut probe = vec![0.0; start.len()];
    KaneOde { route: &mut route }
        .rhs(t_start, &start, &mut probe)
        .map_err(SimulationError::Initial)?;
    route.start_full = route
        .full(t_start, &start)
        .map_err(SimulationError::Initial)?;
    route.start = start;
    Ok(route)
}

/// Integrates on Kane's route from its start, handing out rows and crossings as
/// [`Simulation::run_until`] does; returns the outcome and the constraints' drift. The route
/// itself is left as prepared (Newton's starts move on a copy).
fn run_kane(
    prepared: &KaneRoute,
    (method, t0, t1, options): (MethodName, f64, f64, &IntegratorOptions),
    energy0: f64,
    on_row: &mut dyn FnMut(&[f64]) -> ControlFlow<()>,
    on_crossing: &mut dyn FnMut(RecordedCrossing<'_>),
) -> (Outcome, Drift) {
    let mut route = prepared.clone();
    let stopping = route.stopping_events;
    let rows = RefCell::new(KaneRows::new(prepared, energy0));
    let start = route.start.clone();
    let method = match method {
        MethodName::Sdirk => Method::Sdirk,
        MethodName::Dopri5 => Method::Dopri5,
        _ => Method::Dop853,
    };
    let outcome = integrate_observed(
        &mut KaneOde { route: &mut route },
        method,
        t0,
        &start,
        t1,
        options,
        &mut |t, y| on_row(rows.borrow_mut().row(t, y)),
        &mut |c: Crossing<'_>| {
            let mut maker = rows.borrow_mut();
            on_crossing(RecordedCrossing {
                event: c.index.saturating_sub(stopping),
                rising: c.rising,
                row: maker.row(c.t, c.y),
            });
        },
    );
    (outcome, rows.into_inner().drift)
}

/// Makes output rows `[t, q…, q̇…, energy error, constraint drift]` from states, with its own
/// copy of the compiled equations (energy, drift, projection) apart from the integrated one.
struct RowMaker {
    monitor: Compiled,
    drift: Drift,
    energy0: f64,
    scale: f64,
    projected: Vec<f64>,
    saved: Vec<f64>,
    row: Vec<f64>,
}

impl RowMaker {
    fn new(compiled: &Compiled, energy0: f64) -> RowMaker {
        let n = compiled.n;
        RowMaker {
            monitor: compiled.clone(),
            drift: Drift::default(),
            energy0,
            scale: if energy0.abs() < 1e-12 {
                1.0
            } else {
                energy0.abs()
            },
            projected: vec![0.0; 2 * n],
            saved: vec![0.0; 2 * n],
            row: vec![0.0; 2 * n + 3],
        }
    }

    fn row(&mut self, t: f64, q: &[f64], qd: &[f64]) -> &[f64] {
        let n = self.monitor.n;
        // Outputs between steps come from the dense output, which leaves the constraint
        // manifold by about the local error; the written state is projected back like the
        // step ends (when that fails, the state is written as it is and its drift shows).
        let (q, qd) = if self.monitor.m > 0 {
            self.projected[..n].copy_from_slice(q);
            self.projected[n..].copy_from_slice(qd);
            self.saved.copy_from_slice(&self.projected);
            if SecondOrder::new(&mut self.monitor)
                .project(t, &mut self.projected)
                .is_err()
            {
                self.projected.copy_from_slice(&self.saved);
            }
            (&self.projected[..n], &self.projected[n..])
        } else {
            (q, qd)
        };
        self.monitor.set_state(q, qd, t);
        let (energy, position, velocity) = self.monitor.energy_and_drifts();
        let drift = position.max(velocity);
        self.drift.note(position, velocity);
        self.row[0] = t;
        self.row[1..=n].copy_from_slice(q);
        self.row[n + 1..=2 * n].copy_from_slice(qd);
        self.row[2 * n + 1] = (energy - self.energy0) / self.scale;
        self.row[2 * n + 2] = drift;
        &self.row
    }
}

/// The stop events (the conditions read, the contacts' reactions as they are), then the
/// recorded expressions, as expressions of `t`, the coordinates, their rates and the
/// parameters; also how many of them stop the run.
fn compile_events(
    coordinates: &[String],
    setup: &Setup,
) -> Result<(Vec<cas::Expr>, usize), SimulationError> {
    let known = EventNames::new(coordinates, &setup.values);
    let mut events = Vec::new();
    for event in &setup.stop_events {
        events.push(match event {
            StopEvent::Condition(text) => {
                known
                    .parse(text)
                    .map_err(|reason| SimulationError::StopCondition {
                        text: text.clone(),
                        reason,
                    })?
            }
            StopEvent::ContactLost { value, .. } => *value,
            // Numeric contacts come through `Setup::numeric_contacts`; one given here has no
            // expression and never fires (a constant keeps the events' indices in order).
            StopEvent::NumericContactLost { .. } => cas::Expr::one(),
        });
    }
    let stopping_events = events.len();
    for text in &setup.record_when {
        events.push(
            known
                .parse(text)
                .map_err(|reason| SimulationError::RecordCondition {
                    text: text.clone(),
                    reason,
                })?,
        );
    }
    Ok((events, stopping_events))
}

/// The initial state moved onto the constraint manifold (positions, then velocities), with
/// the correction when it moved; the equations are evaluated there once, so that a state
/// where they cannot be solved fails before the run.
fn start_on_constraints(
    compiled: &mut Compiled,
    t_start: f64,
    given: Vec<f64>,
) -> Result<(Vec<f64>, Option<InitialCorrection>), SimulationError> {
    let mut initial = given.clone();
    SecondOrder::new(compiled)
        .project(t_start, &mut initial)
        .map_err(SimulationError::Initial)?;
    let moved = given
        .iter()
        .zip(&initial)
        .any(|(a, b)| (a - b).abs() > MOVED * (1.0 + a.abs()));
    let correction = moved.then(|| InitialCorrection {
        given,
        corrected: initial.clone(),
    });
    let mut probe = vec![0.0; initial.len()];
    SecondOrder::new(compiled)
        .rhs(t_start, &initial, &mut probe)
        .map_err(SimulationError::Initial)?;
    Ok((initial, correction))
}

fn check_setting(
    setting: &'static str,
    value: f64,
    valid: impl Fn(f64) -> bool,
    reason: &str,
) -> Result<(), SimulationError> {
    if valid(value) {
        Ok(())
    } else {
        Err(SimulationError::InvalidSetting {
            setting,
            reason: format!("{value} {reason}"),
        })
    }
}

/// What an event expression (`--stop-when`, `--record-when`) may name: `t`, the coordinates,
/// their rates and the parameters and inputs that have values.
struct EventNames {
    context: ParseContext,
    allowed: std::collections::HashSet<cas::Symbol>,
    listing: String,
}

impl EventNames {
    fn new(coordinates: &[String], parameters: &[(String, f64)]) -> EventNames {
        let context = coordinates
            .iter()
            .fold(ParseContext::new(), |c, q| c.with_coordinate(q));
        let mut names = vec!["t".to_owned()];
        names.extend(coordinates.iter().cloned());
        names.extend(coordinates.iter().map(|q| format!("{q}_d")));
        names.extend(parameters.iter().map(|(name, _)| name.clone()));
        let allowed = std::iter::once(cas::Expr::time())
            .chain(coordinates.iter().map(|q| cas::Expr::coordinate(q)))
            .chain(coordinates.iter().map(|q| cas::Expr::rate(q, 1)))
            .chain(parameters.iter().map(|(name, _)| cas::Expr::symbol(name)))
            .filter_map(cas::Expr::as_symbol)
            .collect();
        EventNames {
            context,
            allowed,
            listing: names.join(", "),
        }
    }

    /// Parses `text`; an error names what is wrong and the column where it is.
    fn parse(&self, text: &str) -> Result<cas::Expr, String> {
        let expr = cas::parse(text, &self.context).map_err(|e| e.to_string())?;
        let mut stack = vec![expr];
        while let Some(e) = stack.pop() {
            if let cas::Node::Symbol(symbol) = e.node() {
                if !self.allowed.contains(symbol) {
                    let mut name = symbol.name().to_owned();
                    if symbol.order() > 0 {
                        name.push('_');
                        name.extend(std::iter::repeat_n('d', usize::from(symbol.order())));
                    }
                    let at = column_of(text, &name)
                        .map_or_else(String::new, |c| format!(" at column {c}"));
                    return Err(format!(
                        "unknown name `{name}`{at}; the expression may use {}",
                        self.listing
                    ));
                }
            }
            stack.extend_from_slice(e.children());
        }
        Ok(expr)
    }
}

/// The 1-based column (in characters) where `name` first occurs in `text` as a whole word.
fn column_of(text: &str, name: &str) -> Option<usize> {
    let is_word = |c: char| c.is_alphanumeric() || c == '_';
    let mut from = 0;
    while let Some(found) = text[from..].find(name) {
        let start = from + found;
        let end = start + name.len();
        let before = text[..start].chars().next_back().is_some_and(is_word);
        let after = text[end..].chars().next().is_some_and(is_word);
        if !before && !after {
            return Some(text[..start].chars().count() + 1);
        }
        from = end;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unbound(name: &str) -> TapeError {
        TapeError::UnboundSymbol { name: name.into() }
    }

    #[test]
    fn a_coordinates_acceleration_left_in_the_equations_is_a_bug_not_a_missing_value() {
        let coordinates = ["x".to_owned(), "y".to_owned()];
        for name in ["y_dd", "x_ddd"] {
            assert_eq!(
                missing_value(unbound(name), &coordinates),
                SimulationError::UnsolvedDerivative { name: name.into() }
            );
        }
        // A parameter, a name that only starts like a coordinate, or a first rate (a state
        // variable: never missing, but not an acceleration either) is a missing value.
        for name in ["k", "yy_dd", "y_dx", "y_d"] {
            assert_eq!(
                missing_value(unbound(name), &coordinates),
                SimulationError::MissingValue(unbound(name))
            );
        }
    }
}
