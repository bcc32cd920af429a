//! Integrators for `y' = F(t, y)`: [`Method::Dopri5`] (adaptive explicit Runge–Kutta 5(4)
//! with a fourth-order dense output; the default), [`Method::Dop853`] (adaptive explicit
//! Runge–Kutta 8(5,3) with a seventh-order dense output: fewer evaluations at tight
//! tolerances), [`Method::Gauss`] (three-stage
//! Gauss–Legendre collocation, order 6, implicit and symplectic, with a fixed step: applied to
//! Hamilton's equations its energy error stays bounded over long runs), and [`Method::Sdirk`]
//! (L-stable implicit SDIRK of order 2, adaptive, for stiff systems).
//!
//! [`integrate`] drives either: it reports the state at the requested output times through an
//! observer, calls [`OdeSystem::project`] after each accepted step (constraint projection),
//! locates the sign changes of the event functions by bisection on the dense output — a
//! stopping event ends the run at the first, a recording event ([`OdeSystem::event_stops`]
//! false) is handed to [`integrate_with_crossings`]'s callback as a [`Crossing`] — and ends
//! with an [`Outcome`]: why it stopped ([`StopReason`], with the time of a
//! failure: a non-finite value, a singular matrix, a step size underflow) and the work done
//! ([`Stats`]). What was observed before a failure stays with the observer. An observer of
//! [`integrate_observed`] may also end the run itself ([`StopReason::Halted`]: a consumer
//! that has had enough, such as an output file at its size limit).

mod dop853;
mod dopri5;
mod explicit;
mod gauss;
pub use gauss::PILOT_STEPS;
mod sdirk;

use std::fmt;
use std::ops::ControlFlow;

use dopri5::{initial_step, Stiffness};

/// What the methods call with each output row: `Break` ends the run there
/// ([`StopReason::Halted`]).
pub(crate) type Observer<'a> = dyn FnMut(f64, &[f64]) -> ControlFlow<()> + 'a;

/// Why the right-hand side could not be evaluated at a state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RhsError {
    /// The mass matrix (or the constrained system's matrix) is singular at this state.
    #[error("the mass matrix is singular (no pivot in column {column})")]
    SingularMatrix {
        /// The column without a pivot.
        column: usize,
    },
    /// A value came out NaN or infinite.
    #[error("a value is not finite (NaN or infinite)")]
    NotFinite,
    /// The projection onto the constraints did not converge.
    #[error("the projection onto the constraints did not converge")]
    ProjectionFailed,
}

/// A first-order system `y' = F(t, y)` with optional constraint projection and events.
pub trait OdeSystem {
    /// The length of `y`.
    fn dimension(&self) -> usize;
    /// Writes `F(t, y)` into `dy`.
    ///
    /// # Errors
    /// When `F` cannot be evaluated at this state.
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError>;
    /// Moves `y` back onto the constraint manifold after an accepted step; returns whether it
    /// changed `y`. The default does nothing.
    ///
    /// # Errors
    /// When the projection fails.
    fn project(&mut self, _t: f64, _y: &mut [f64]) -> Result<bool, RhsError> {
        Ok(false)
    }
    /// How many event functions there are (default: none).
    fn event_count(&self) -> usize {
        0
    }
    /// Writes the event functions' values `g_k(t, y)`; the run stops where one changes sign
    /// (or records the crossing, see [`OdeSystem::event_stops`]).
    fn events(&mut self, _t: f64, _y: &[f64], _g: &mut [f64]) {}
    /// Whether a sign change of event function `index` stops the run (the default) or is
    /// only recorded.
    fn event_stops(&self, _index: usize) -> bool {
        true
    }
}

/// A sign change of a recording event function, located on the dense output.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing<'a> {
    /// Which event function.
    pub index: usize,
    /// When.
    pub t: f64,
    /// Whether it went from negative to positive (else from positive to negative).
    pub rising: bool,
    /// The (interpolated) state at `t`.
    pub y: &'a [f64],
}

/// An integration method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Method {
    /// Dormand–Prince 5(4), adaptive, dense output of order 4 (default).
    Dopri5,
    /// Dormand–Prince 8(5,3) (Hairer's DOP853), adaptive, dense output of order 7 (three
    /// more evaluations in a step that holds an output row or an event): fewer evaluations
    /// than [`Method::Dopri5`] at tight tolerances.
    Dop853,
    /// Gauss–Legendre, 3 stages (order 6), fixed step, symplectic. Without a step given, the
    /// step is chosen by a pilot run over the first [`PILOT_STEPS`] steps against one of half
    /// the step, so that the error extrapolated to the end is within the tolerances; the same
    /// measure is the run's [`Outcome::error_estimate`].
    Gauss,
    /// L-stable SDIRK of order 2, adaptive, Newton with a finite-difference Jacobian: stiff
    /// systems.
    Sdirk,
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Method::Dopri5 => "dopri5",
            Method::Dop853 => "dop853",
            Method::Gauss => "gauss",
            Method::Sdirk => "sdirk",
        })
    }
}

/// Settings of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntegratorOptions {
    /// Relative tolerance (default: 1e-8).
    pub rtol: f64,
    /// Absolute tolerance (default: 1e-10).
    pub atol: f64,
    /// The step: fixed for Gauss–Legendre, initial for adaptive methods (default: chosen from
    /// the tolerances; for Gauss–Legendre by a pilot run, see [`Method::Gauss`]).
    pub step: Option<f64>,
    /// Time between outputs; `None` reports every accepted step (default: `None`).
    pub output_step: Option<f64>,
    /// The most accepted steps before the run stops with [`Failure::TooManySteps`]
    /// (default: [`DEFAULT_MAX_STEPS`]).
    pub max_steps: u64,
    /// The most observer calls (output rows) before the run stops with
    /// [`Failure::TooManyOutputs`] (default: [`DEFAULT_MAX_OUTPUTS`]); the rows up to the
    /// limit are reported.
    pub max_outputs: u64,
}

/// The default step limit: 10⁶ steps, a few seconds of work for the mechanics this crate
/// serves even without optimization — beyond it a run is more likely runaway than wanted.
pub const DEFAULT_MAX_STEPS: u64 = 1_000_000;

/// The default output limit: 10⁶ rows.
pub const DEFAULT_MAX_OUTPUTS: u64 = 1_000_000;

/// An adaptive step below this fraction of the whole time span `|t_end − t₀|` ends the run
/// with [`Failure::StepCollapse`]: at that size the span would take more than 10¹² steps, so
/// the solution is running away (or the problem is stiff), and going on only fills the disk.
pub const STEP_COLLAPSE_FRACTION: f64 = 1e-12;

/// Hairer's stiffness test for Dormand–Prince 5(4): `h·|λ|` estimated from the last two
/// stages above this value (near the boundary of the stability region, about 3.3 on the
/// negative real axis) counts as a step limited by stability rather than accuracy. (DOP853's
/// region reaches further: its threshold is Hairer's 6.1.)
pub const STIFF_H_LAMBDA: f64 = 3.25;

/// This many consecutive accepted steps limited by stability ([`STIFF_H_LAMBDA`]) end an
/// explicit run with [`Failure::Stiff`] — when the rest of the span would take more than
/// [`STIFF_PROJECTED_STEPS`] steps at that size (a mildly stiff run that finishes soon is
/// left to finish).
pub const STIFF_STEPS: u32 = 15;

/// See [`STIFF_STEPS`].
pub const STIFF_PROJECTED_STEPS: f64 = 1e5;

impl Default for IntegratorOptions {
    fn default() -> Self {
        IntegratorOptions {
            rtol: 1e-8,
            atol: 1e-10,
            step: None,
            output_step: None,
            max_steps: DEFAULT_MAX_STEPS,
            max_outputs: DEFAULT_MAX_OUTPUTS,
        }
    }
}

/// Work done during a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps (error too large, or an implicit solve that did not converge).
    pub rejected: u64,
    /// Evaluations of the right-hand side.
    pub evaluations: u64,
}

/// Why a run failed.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Failure {
    /// The right-hand side failed.
    #[error("at t = {t}: {error}")]
    Rhs {
        /// When.
        t: f64,
        /// What.
        error: RhsError,
    },
    /// The step size fell below what the time's precision resolves.
    #[error("at t = {t}: the step size underflowed (h = {h:e}); the solution may blow up or the problem be stiff")]
    StepUnderflow {
        /// When.
        t: f64,
        /// The step size.
        h: f64,
    },
    /// An implicit stage solve did not converge at the fixed step (or, for gauss's chosen
    /// step, only at a step so small that the span would take more than
    /// [`STIFF_PROJECTED_STEPS`] steps).
    #[error("at t = {t}: the implicit stage equations did not converge with h = {h:.3e}: gauss solves them by fixed-point iteration, which needs a step below the fastest time scale of the system; if the problem is stiff use the implicit method sdirk, else a smaller step")]
    NotConverged {
        /// When.
        t: f64,
        /// The step size.
        h: f64,
    },
    /// The step limit was reached.
    #[error("at t = {t} after {steps} steps: the step limit was reached; raise it if the run needs more steps")]
    TooManySteps {
        /// When.
        t: f64,
        /// The limit.
        steps: u64,
    },
    /// The output limit was reached: the next row (at `t`) would be one more than `rows`.
    #[error("at t = {t}: the row limit of {rows} output rows was reached; raise it, or write fewer rows (a row every output step)")]
    TooManyOutputs {
        /// When the next row was due.
        t: f64,
        /// The limit (rows written).
        rows: u64,
    },
    /// The adaptive step fell below [`STEP_COLLAPSE_FRACTION`] of the time span (or the
    /// first step the dynamics ask for is already below it: the span is far too long for
    /// them).
    #[error("at t = {t}: the step size fell to h = {h:.3e}, {fraction:.1e} of the time span {span:?}, which would take more than 10¹² such steps: the end time is too far for the motion's time scale, the solution runs away (values too large?) or the problem is stiff")]
    StepCollapse {
        /// When.
        t: f64,
        /// The step size.
        h: f64,
        /// The whole time span `|t_end − t₀|`.
        span: f64,
        /// `h / span`.
        fraction: f64,
    },
    /// The explicit method's step was limited by stability, not accuracy, for
    /// [`STIFF_STEPS`] consecutive steps (Hairer's test: `h·|λ| > `[`STIFF_H_LAMBDA`] for
    /// dopri5, `> 6.1` for dop853), and
    /// the rest of the span would take more than [`STIFF_PROJECTED_STEPS`] such steps.
    #[error("at t = {t}: the problem is stiff (h·|λ| ≈ {h_lambda:.2} at h = {h:e} for {steps} steps in a row; the rest of the span would take {remaining:.2e} steps); use the implicit method sdirk")]
    Stiff {
        /// When.
        t: f64,
        /// The step size.
        h: f64,
        /// The last estimate of `h·|λ|`.
        h_lambda: f64,
        /// Consecutive stability-limited steps.
        steps: u32,
        /// The steps the rest of the span would take at `h`.
        remaining: f64,
    },
}

impl Failure {
    /// When it happened.
    #[must_use]
    pub fn time(&self) -> f64 {
        match *self {
            Failure::Rhs { t, .. }
            | Failure::StepUnderflow { t, .. }
            | Failure::NotConverged { t, .. }
            | Failure::TooManySteps { t, .. }
            | Failure::TooManyOutputs { t, .. }
            | Failure::StepCollapse { t, .. }
            | Failure::Stiff { t, .. } => t,
        }
    }

    /// A short name for machine-readable output: `rhs`, `step_underflow`, `not_converged`,
    /// `too_many_steps`, `too_many_outputs`, `step_collapse`, `stiff`.
    #[must_use]
    pub fn kind(&self) -> &'static str {
        match self {
            Failure::Rhs { .. } => "rhs",
            Failure::StepUnderflow { .. } => "step_underflow",
            Failure::NotConverged { .. } => "not_converged",
            Failure::TooManySteps { .. } => "too_many_steps",
            Failure::TooManyOutputs { .. } => "too_many_outputs",
            Failure::StepCollapse { .. } => "step_collapse",
            Failure::Stiff { .. } => "stiff",
        }
    }

    /// The numbers that decided it, by name (the time is [`Failure::time`]).
    #[must_use]
    pub fn numbers(&self) -> Vec<(&'static str, f64)> {
        match *self {
            Failure::Rhs { .. } => Vec::new(),
            Failure::StepUnderflow { h, .. } | Failure::NotConverged { h, .. } => vec![("h", h)],
            Failure::TooManySteps { steps, .. } => vec![("steps", steps as f64)],
            Failure::TooManyOutputs { rows, .. } => vec![("rows", rows as f64)],
            Failure::StepCollapse {
                h, span, fraction, ..
            } => vec![("h", h), ("span", span), ("fraction", fraction)],
            Failure::Stiff {
                h, h_lambda, steps, ..
            } => vec![
                ("h", h),
                ("h_lambda", h_lambda),
                ("steps", f64::from(steps)),
            ],
        }
    }
}

/// Why a run stopped.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum StopReason {
    /// It reached the end time.
    Finished,
    /// Event function `index` changed sign at `t`.
    Event {
        /// Which event function.
        index: usize,
        /// When.
        t: f64,
    },
    /// It failed; everything observed before is valid.
    Failed(Failure),
    /// The observer ended the run after its row at `t` ([`integrate_observed`]).
    Halted {
        /// The time of the last row observed.
        t: f64,
    },
}

/// The result of [`integrate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    /// Why it stopped.
    pub stop: StopReason,
    /// The time reached.
    pub t: f64,
    /// Work done.
    pub stats: Stats,
    /// An estimate of the largest error of a state component at the end, where the method
    /// makes one (gauss: from its pilot runs, see [`Method::Gauss`]); `None` for the adaptive
    /// methods, whose tolerances bound the local error of each step only.
    pub error_estimate: Option<f64>,
}

/// Integrates `system` from `(t0, y0)` to `t_end` (which may be below `t0`), calling
/// `observer(t, y)` at `t0`, at each output time (every `output_step`, or each accepted step)
/// and at the final time.
pub fn integrate(
    system: &mut dyn OdeSystem,
    method: Method,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    options: &IntegratorOptions,
    observer: &mut dyn FnMut(f64, &[f64]),
) -> Outcome {
    integrate_with_crossings(
        system,
        method,
        t0,
        y0,
        t_end,
        options,
        observer,
        &mut |_| {},
    )
}

/// [`integrate`], handing every sign change of a recording event function (in time order,
/// none after the stop of a stopping event) to `on_crossing`.
#[allow(clippy::too_many_arguments)]
pub fn integrate_with_crossings(
    system: &mut dyn OdeSystem,
    method: Method,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    options: &IntegratorOptions,
    observer: &mut dyn FnMut(f64, &[f64]),
    on_crossing: &mut dyn FnMut(Crossing<'_>),
) -> Outcome {
    integrate_observed(
        system,
        method,
        t0,
        y0,
        t_end,
        options,
        &mut |t, y| {
            observer(t, y);
            ControlFlow::Continue(())
        },
        on_crossing,
    )
}

/// [`integrate_with_crossings`] with an observer that may end the run: after a row for
/// which it returns `Break`, the run stops with [`StopReason::Halted`] at that row's time.
#[allow(clippy::too_many_arguments)]
pub fn integrate_observed(
    system: &mut dyn OdeSystem,
    method: Method,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    options: &IntegratorOptions,
    observer: &mut dyn FnMut(f64, &[f64]) -> ControlFlow<()>,
    on_crossing: &mut dyn FnMut(Crossing<'_>),
) -> Outcome {
    let mut driver = Driver::new(system, t0, y0, t_end, options, on_crossing);
    if driver.options.max_outputs == 0 {
        return Outcome {
            stop: StopReason::Failed(Failure::TooManyOutputs { t: t0, rows: 0 }),
            t: t0,
            stats: driver.stats,
            error_estimate: None,
        };
    }
    driver.outputs = 1;
    let stop = if observer(t0, y0).is_break() {
        StopReason::Halted { t: t0 }
    } else {
        match method {
            Method::Dopri5 => dopri5::run(&mut driver, observer),
            Method::Dop853 => dop853::run(&mut driver, observer),
            Method::Gauss => gauss::run(&mut driver, observer),
            Method::Sdirk => sdirk::run(&mut driver, observer),
        }
    };
    Outcome {
        stop,
        t: driver.t,
        stats: driver.stats,
        error_estimate: driver.error_estimate,
    }
}

/// State shared by the methods: time, state, outputs, events, counters.
pub(crate) struct Driver<'s> {
    pub(crate) system: &'s mut dyn OdeSystem,
    pub(crate) t: f64,
    pub(crate) y: Vec<f64>,
    pub(crate) t_end: f64,
    pub(crate) direction: f64,
    pub(crate) options: IntegratorOptions,
    pub(crate) stats: Stats,
    /// See [`Outcome::error_estimate`].
    pub(crate) error_estimate: Option<f64>,
    next_output: Option<f64>,
    output_index: u64,
    /// Observer calls so far (bounded by `max_outputs`).
    outputs: u64,
    t0: f64,
    events_before: Vec<f64>,
    events_after: Vec<f64>,
    events_probe: Vec<f64>,
    /// Crossings of recording events found in the current step: (index, t, rising).
    recorded: Vec<(usize, f64, bool)>,
    on_crossing: &'s mut dyn FnMut(Crossing<'_>),
    scratch: Vec<f64>,
}

impl<'s> Driver<'s> {
    fn new(
        system: &'s mut dyn OdeSystem,
        t0: f64,
        y0: &[f64],
        t_end: f64,
        options: &IntegratorOptions,
        on_crossing: &'s mut dyn FnMut(Crossing<'_>),
    ) -> Self {
        let direction = if t_end >= t0 { 1.0 } else { -1.0 };
        let events = system.event_count();
        let mut events_before = vec![0.0; events];
        if events > 0 {
            system.events(t0, y0, &mut events_before);
        }
        let output_step = options
            .output_step
            .filter(|s| s.is_finite() && *s > 0.0)
            .map(f64::abs);
        Driver {
            system,
            t: t0,
            y: y0.to_vec(),
            t_end,
            direction,
            options: *options,
            stats: Stats::default(),
            error_estimate: None,
            next_output: output_step.map(|s| t0 + direction * s),
            output_index: 1,
            outputs: 0,
            t0,
            events_before,
            events_after: vec![0.0; events],
            events_probe: vec![0.0; events],
            recorded: Vec::new(),
            on_crossing,
            scratch: vec![0.0; y0.len()],
        }
    }

    pub(crate) fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Failure> {
        self.stats.evaluations += 1;
        self.system
            .rhs(t, y, dy)
            .map_err(|error| Failure::Rhs { t, error })?;
        if dy.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(Failure::Rhs {
                t,
                error: RhsError::NotFinite,
            })
        }
    }

    /// After a step from `self.t` to `t1` with the new state `y1` and an interpolant over the
    /// step: reports outputs, checks events, and advances. Returns `Some` when the run stops.
    pub(crate) fn accept(
        &mut self,
        t1: f64,
        y1: &[f64],
        interpolate: &dyn Fn(f64, &mut [f64]),
        observer: &mut Observer<'_>,
    ) -> Option<StopReason> {
        self.stats.steps += 1;
        let stop_event = self.events_in_step(t1, y1, interpolate);
        self.report_crossings(stop_event, interpolate);
        if let Some(stop) = self.outputs_in_step(t1, y1, stop_event, interpolate, observer) {
            return Some(stop);
        }
        self.advance(t1, y1, stop_event, interpolate, observer)
    }

    /// Every sign change of an event function in the step to `t1`, located by bisection on
    /// the interpolant: the recording ones go to `self.recorded`; the first stopping one is
    /// returned (its index and time).
    fn events_in_step(
        &mut self,
        t1: f64,
        y1: &[f64],
        interpolate: &dyn Fn(f64, &mut [f64]),
    ) -> Option<(usize, f64)> {
        let mut stop_event: Option<(usize, f64)> = None;
        self.recorded.clear();
        if self.events_before.is_empty() {
            return None;
        }
        self.system.events(t1, y1, &mut self.events_after);
        for k in 0..self.events_before.len() {
            let (g0, g1) = (self.events_before[k], self.events_after[k]);
            if g0 != 0.0 && (g0 * g1 < 0.0 || g1 == 0.0) {
                let t = self.locate(k, g0, t1, interpolate);
                if self.system.event_stops(k) {
                    let earlier = stop_event.is_none_or(|(_, s)| (t - s) * self.direction < 0.0);
                    if earlier {
                        stop_event = Some((k, t));
                    }
                } else {
                    self.recorded.push((k, t, g0 < 0.0));
                }
            }
        }
        std::mem::swap(&mut self.events_before, &mut self.events_after);
        stop_event
    }

    /// Hands the recorded crossings of the step to the callback in time order, none after
    /// the stop.
    fn report_crossings(
        &mut self,
        stop_event: Option<(usize, f64)>,
        interpolate: &dyn Fn(f64, &mut [f64]),
    ) {
        if self.recorded.is_empty() {
            return;
        }
        let direction = self.direction;
        self.recorded
            .sort_by(|a, b| (a.1 * direction).total_cmp(&(b.1 * direction)));
        for &(index, t, rising) in &self.recorded {
            // A crossing at the stop itself is kept; one past it did not happen.
            if stop_event.is_some_and(|(_, s)| (t - s) * direction > 0.0) {
                break;
            }
            interpolate(t, &mut self.scratch);
            (self.on_crossing)(Crossing {
                index,
                t,
                rising,
                y: &self.scratch,
            });
        }
    }

    /// The output rows due inside the step (up to the stop event, before the end time):
    /// every output step on the interpolant, or the step's end.
    fn outputs_in_step(
        &mut self,
        t1: f64,
        y1: &[f64],
        stop_event: Option<(usize, f64)>,
        interpolate: &dyn Fn(f64, &mut [f64]),
        observer: &mut Observer<'_>,
    ) -> Option<StopReason> {
        let horizon = stop_event.map_or(t1, |(_, t)| t);
        match self.options.output_step {
            Some(step) if step.is_finite() && step > 0.0 => {
                while let Some(to) = self.next_output {
                    let inside = (to - horizon) * self.direction <= 0.0
                        && (to - self.t_end) * self.direction < 0.0;
                    if !inside {
                        break;
                    }
                    if let Some(stop) = self.no_room(to) {
                        return Some(stop);
                    }
                    interpolate(to, &mut self.scratch);
                    let flow = observer(to, &self.scratch);
                    self.outputs += 1;
                    self.output_index += 1;
                    self.next_output =
                        Some(self.t0 + self.direction * step * self.output_index as f64);
                    if flow.is_break() {
                        self.t = to;
                        self.y.copy_from_slice(&self.scratch);
                        return Some(StopReason::Halted { t: to });
                    }
                }
            }
            _ => {
                if stop_event.is_none() && t1 != self.t_end {
                    if let Some(stop) = self.no_room(t1) {
                        return Some(stop);
                    }
                    let flow = observer(t1, y1);
                    self.outputs += 1;
                    if flow.is_break() {
                        self.t = t1;
                        self.y.copy_from_slice(y1);
                        return Some(StopReason::Halted { t: t1 });
                    }
                }
            }
        }
        None
    }

    /// Whether [`Driver::accept`] of a step to `(t1, y1)` will call its interpolant: an
    /// output row due inside the step, or an event function that changes sign in it. A
    /// method whose dense output costs evaluations (DOP853) builds it only then.
    pub(crate) fn interpolation_needed(&mut self, t1: f64, y1: &[f64]) -> bool {
        let row_due = match (self.options.output_step, self.next_output) {
            (Some(step), Some(to)) if step.is_finite() && step > 0.0 => {
                (to - t1) * self.direction <= 0.0 && (to - self.t_end) * self.direction < 0.0
            }
            _ => false,
        };
        if row_due || self.events_before.is_empty() {
            return row_due;
        }
        self.system.events(t1, y1, &mut self.events_probe);
        self.events_before
            .iter()
            .zip(&self.events_probe)
            .any(|(&g0, &g1)| g0 != 0.0 && (g0 * g1 < 0.0 || g1 == 0.0))
    }

    /// Moves to the step's end (or to the stop event, with its row), with the final row at
    /// the end time; the step limit.
    fn advance(
        &mut self,
        t1: f64,
        y1: &[f64],
        stop_event: Option<(usize, f64)>,
        interpolate: &dyn Fn(f64, &mut [f64]),
        observer: &mut Observer<'_>,
    ) -> Option<StopReason> {
        if let Some((index, t)) = stop_event {
            if let Some(stop) = self.no_room(t) {
                return Some(stop);
            }
            interpolate(t, &mut self.scratch);
            // The event's row is its last: a halt there changes nothing.
            let _ = observer(t, &self.scratch);
            self.outputs += 1;
            self.t = t;
            self.y.copy_from_slice(&self.scratch);
            return Some(StopReason::Event { index, t });
        }
        if t1 == self.t_end {
            if let Some(stop) = self.no_room(t1) {
                return Some(stop);
            }
        }
        self.t = t1;
        self.y.copy_from_slice(y1);
        if t1 == self.t_end {
            // The last row: the run is finished whatever the observer says.
            let _ = observer(t1, y1);
            self.outputs += 1;
            return Some(StopReason::Finished);
        }
        if self.stats.steps >= self.options.max_steps {
            return Some(StopReason::Failed(Failure::TooManySteps {
                t: t1,
                steps: self.options.max_steps,
            }));
        }
        None
    }

    /// The stop when the output limit is reached and a row is due at `t`.
    fn no_room(&self, t: f64) -> Option<StopReason> {
        (self.outputs >= self.options.max_outputs).then_some(StopReason::Failed(
            Failure::TooManyOutputs {
                t,
                rows: self.options.max_outputs,
            },
        ))
    }

    /// The smallest adaptive step allowed at time `t`, and whether a step below it is a
    /// collapse relative to the span (else an underflow of `t`'s precision).
    pub(crate) fn step_floor(&self, t: f64) -> (f64, bool) {
        let underflow = 16.0 * f64::EPSILON * t.abs().max(1e-300);
        let collapse = STEP_COLLAPSE_FRACTION * (self.t_end - self.t0).abs();
        if collapse > underflow {
            (collapse, true)
        } else {
            (underflow, false)
        }
    }

    /// The failure of a step `h` below the floor at `t` ([`Driver::step_floor`]).
    pub(crate) fn too_small(&self, t: f64, h: f64) -> Option<Failure> {
        let (floor, collapse) = self.step_floor(t);
        if h >= floor {
            None
        } else if collapse {
            let span = (self.t_end - self.t0).abs();
            Some(Failure::StepCollapse {
                t,
                h,
                span,
                fraction: h / span,
            })
        } else {
            Some(Failure::StepUnderflow { t, h })
        }
    }

    /// Where event `k`, `g0` at the step's start and of the other sign (or zero) at `t1`,
    /// crosses zero: bisection on the interpolant down to adjacent floating-point times.
    fn locate(&mut self, k: usize, g0: f64, t1: f64, interpolate: &dyn Fn(f64, &mut [f64])) -> f64 {
        let (mut a, mut b) = (self.t, t1);
        let mut ga = g0;
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if m == a || m == b {
                break;
            }
            interpolate(m, &mut self.scratch);
            self.system.events(m, &self.scratch, &mut self.events_probe);
            if ga * self.events_probe[k] <= 0.0 {
                b = m;
            } else {
                a = m;
                ga = self.events_probe[k];
            }
        }
        b
    }

    /// Projects the current state after a step; returns whether it changed.
    pub(crate) fn project(&mut self) -> Result<bool, Failure> {
        let t = self.t;
        self.system
            .project(t, &mut self.y)
            .map_err(|error| Failure::Rhs { t, error })
    }

    /// The weighted RMS norm of an error estimate.
    pub(crate) fn error_norm(&self, y0: &[f64], y1: &[f64], error: &[f64]) -> f64 {
        let (rtol, atol) = (self.options.rtol, self.options.atol);
        let n = y0.len().max(1) as f64;
        let sum: f64 = y0
            .iter()
            .zip(y1)
            .zip(error)
            .map(|((a, b), e)| {
                let scale = atol + rtol * a.abs().max(b.abs());
                (e / scale).powi(2)
            })
            .sum();
        (sum / n).sqrt()
    }
}

/// One end of a step for [`hermite`]: time, state, derivative.
pub(crate) type StepEnd<'a> = (f64, &'a [f64], &'a [f64]);

/// Cubic Hermite interpolation between two step ends.
pub(crate) fn hermite(start: StepEnd<'_>, end: StepEnd<'_>, t: f64, out: &mut [f64]) {
    let ((t0, y0, f0), (t1, y1, f1)) = (start, end);
    let h = t1 - t0;
    let s = if h == 0.0 { 1.0 } else { (t - t0) / h };
    let h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s);
    let h10 = s * (1.0 - s) * (1.0 - s);
    let h01 = s * s * (3.0 - 2.0 * s);
    let h11 = s * s * (s - 1.0);
    for (i, value) in out.iter_mut().enumerate() {
        *value = h00 * y0[i] + h10 * h * f0[i] + h01 * y1[i] + h11 * h * f1[i];
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod tests_dop853;
