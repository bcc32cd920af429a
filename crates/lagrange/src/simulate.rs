//! Simulations of an [`Analysis`]: the settings resolved against the model's `simulate`
//! statement, the one-sided contacts as stop events, runs with their rows kept or streamed,
//! how each run ended (typed), its summary, and sweeps over values on all cores — one
//! derivation for all of them.

use std::ops::ControlFlow;

use numeric::{Failure, Outcome, Stats, StopReason};
use rayon::prelude::*;
use serde_json::{json, Value};
use simulation::{Limit, MethodName, Settings, Setup, Simulation, SimulationError, StopEvent};

use crate::assign::{AssignmentError, Range};
use crate::{Analysis, Error, ReactionProbe};

/// What the user asks of a run; `None` takes the model's `simulate` statement, then the
/// default (dopri5, rtol 1e-8, atol 1e-10, from 0, a row every step).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SimulationOptions {
    /// The method (default: the model's, else chosen by the relative tolerance,
    /// [`MethodName::for_tolerance`]).
    pub method: Option<MethodName>,
    /// Start time.
    pub t_start: Option<f64>,
    /// End time (required here or in the model).
    pub t_end: Option<f64>,
    /// Relative tolerance.
    pub rtol: Option<f64>,
    /// Absolute tolerance.
    pub atol: Option<f64>,
    /// Time between output rows.
    pub output_step: Option<f64>,
    /// The integration step: fixed for gauss, initial for dopri5.
    pub step: Option<f64>,
    /// Stop where this expression of `t`, `q`, `q_d` and the parameters crosses zero.
    pub stop_when: Option<String>,
    /// Record every zero crossing of these expressions without stopping.
    pub record_when: Vec<String>,
    /// Run on where a one-sided constraint would be lost (the equations then describe a
    /// motion that cannot happen).
    pub through_contact_loss: bool,
    /// The most integration steps (default: [`Settings::new`]'s 10⁶).
    pub max_steps: Option<u64>,
    /// The most output rows (default: [`Settings::new`]'s 10⁶). A run that nothing can
    /// stop early and whose output step asks for more is refused before it starts.
    pub max_rows: Option<u64>,
}

/// The default limit of the CSV a run writes ([`run_to_csv`]): 256 MiB.
pub const DEFAULT_MAX_BYTES: u64 = 256 << 20;

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Ending {
    /// It reached the end time.
    Finished,
    /// The stop condition crossed zero.
    Condition {
        /// The condition as written.
        text: String,
    },
    /// A one-sided constraint is lost: its reaction changes sign.
    ContactLost {
        /// The reaction's name.
        constraint: String,
    },
    /// The integration failed; the rows before are valid.
    Failed(Failure),
    /// The output reached its size limit ([`run_to_csv`]); the rows written are valid.
    OutputLimit {
        /// The limit, in bytes.
        bytes: u64,
    },
    /// The caller's row callback ended the run ([`Simulation::run_until`]).
    Halted,
}

/// What a caller can change so that a run goes further ([`Ending::remedy`]); a front end
/// names its own option for each.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Remedy {
    /// The problem is stiff: an implicit method (`sdirk`).
    ImplicitMethod,
    /// An implicit method if the problem is stiff, else a smaller step.
    ImplicitMethodOrSmallerStep,
    /// A larger step limit ([`SimulationOptions::max_steps`]).
    MoreSteps,
    /// A larger row limit ([`SimulationOptions::max_rows`]), or fewer rows (a longer output step).
    MoreRows,
    /// A larger byte limit on the output, or fewer rows.
    MoreBytes,
    /// Go on past the loss of a one-sided contact
    /// ([`SimulationOptions::through_contact_loss`]).
    ThroughContactLoss,
}

impl Ending {
    /// Reads an outcome of `simulation`.
    #[must_use]
    pub fn of(simulation: &Simulation, outcome: &Outcome) -> Ending {
        match outcome.stop {
            StopReason::Event { index, .. } => match simulation.stop_event(index) {
                Some(
                    StopEvent::ContactLost { constraint, .. }
                    | StopEvent::NumericContactLost { constraint },
                ) => Ending::ContactLost {
                    constraint: constraint.clone(),
                },
                Some(StopEvent::Condition(text)) => Ending::Condition { text: text.clone() },
                None => Ending::Condition {
                    text: String::new(),
                },
            },
            StopReason::Failed(failure) => Ending::Failed(failure),
            StopReason::Halted { .. } => Ending::Halted,
            _ => Ending::Finished,
        }
    }

    /// Whether the run stopped short of what was asked (a failure, a limit): the CLI's
    /// exit 3. A stop condition or a lost contact is what was asked.
    #[must_use]
    pub fn stopped_short(&self) -> bool {
        matches!(
            self,
            Ending::Failed(_) | Ending::OutputLimit { .. } | Ending::Halted
        )
    }

    /// What happened, as a sentence for people (`None` when the run finished); `t` is where
    /// it ended.
    #[must_use]
    pub fn sentence(&self, t: f64) -> Option<String> {
        match self {
            Ending::Finished => None,
            Ending::Condition { text } => Some(format!("stopped at t = {t}: the stop condition `{text}` crossed zero")),
            Ending::ContactLost { constraint } => Some(format!(
                "stopped at t = {t}: the one-sided constraint `{constraint}` is lost there (its reaction changes sign)"
            )),
            Ending::Failed(failure) => Some(format!("the simulation stopped {failure}")),
            Ending::OutputLimit { bytes } => Some(format!(
                "the simulation stopped at t = {t}: the output reached its limit of {bytes} bytes; raise it, or write fewer rows (a row every output step)"
            )),
            Ending::Halted => Some(format!("the run was ended at t = {t} by its caller")),
        }
    }

    /// What would let a run that a limit or the method stopped go further, if anything would.
    #[must_use]
    pub fn remedy(&self) -> Option<Remedy> {
        Some(match self {
            Ending::Failed(Failure::Stiff { .. }) => Remedy::ImplicitMethod,
            Ending::Failed(Failure::NotConverged { .. }) => Remedy::ImplicitMethodOrSmallerStep,
            Ending::Failed(Failure::TooManySteps { .. }) => Remedy::MoreSteps,
            Ending::Failed(Failure::TooManyOutputs { .. }) => Remedy::MoreRows,
            Ending::OutputLimit { .. } => Remedy::MoreBytes,
            Ending::ContactLost { .. } => Remedy::ThroughContactLoss,
            _ => return None,
        })
    }

    /// A short word for tables: `finished`, `event`, `contact lost: NAME`, `failed …`.
    #[must_use]
    pub fn word(&self) -> String {
        match self {
            Ending::Finished => "finished".into(),
            Ending::Condition { .. } => "event".into(),
            Ending::ContactLost { constraint } => format!("contact lost: {constraint}"),
            Ending::Failed(failure) => format!("failed {failure}"),
            Ending::OutputLimit { bytes } => format!("failed: output limit of {bytes} bytes"),
            Ending::Halted => "halted".into(),
        }
    }

    /// As JSON: `kind` is `finished`, `event` (with `event`), `contact_lost` (with
    /// `constraint`), `failed` (with `reason`, `failure` and `numbers`; the output limit is
    /// the failure `too_many_bytes`) or `halted`; `t` is where it ended.
    #[must_use]
    pub fn to_json(&self, t: f64) -> Value {
        match self {
            Ending::Finished => json!({ "kind": "finished", "t": t }),
            Ending::Condition { text } => json!({ "kind": "event", "t": t, "event": text }),
            Ending::ContactLost { constraint } => {
                json!({ "kind": "contact_lost", "t": t, "constraint": constraint })
            }
            Ending::Failed(failure) => {
                // The failure reads "at t = …: why"; the time is a field of its own.
                let text = failure.to_string();
                let reason = text.split_once(": ").map_or(text.as_str(), |(_, r)| r);
                let numbers: serde_json::Map<String, Value> = failure
                    .numbers()
                    .into_iter()
                    .map(|(name, value)| (name.to_owned(), json!(value)))
                    .collect();
                json!({ "kind": "failed", "t": failure_time(failure).unwrap_or(t), "reason": reason,
                        "failure": failure.kind(), "numbers": numbers })
            }
            Ending::OutputLimit { bytes } => json!({
                "kind": "failed", "t": t, "reason": format!("the output reached its limit of {bytes} bytes"),
                "failure": "too_many_bytes", "numbers": { "bytes": bytes }
            }),
            Ending::Halted => json!({ "kind": "halted", "t": t }),
        }
    }
}

/// When a failure happened.
#[must_use]
pub fn failure_time(failure: &Failure) -> Option<f64> {
    Some(failure.time())
}

/// A recorded zero crossing.
#[derive(Debug, Clone, PartialEq)]
pub struct Crossing {
    /// Which expression (index into [`SimulationOptions::record_when`]).
    pub event: usize,
    /// From negative to positive.
    pub rising: bool,
    /// `t`, the coordinates and their rates there.
    pub state: Vec<f64>,
}

/// A finished run with every row kept.
#[derive(Debug, Clone)]
pub struct Run {
    /// The column names: `t`, the coordinates, their rates `q_d`, `energy_error`,
    /// `constraint_drift`.
    pub columns: Vec<String>,
    /// The rows.
    pub rows: Vec<Vec<f64>>,
    /// The recorded crossings.
    pub crossings: Vec<Crossing>,
    /// How it ended.
    pub ending: Ending,
    /// The time reached.
    pub t: f64,
    /// Steps, rejected steps, evaluations.
    pub stats: Stats,
    /// The method that ran.
    pub method: MethodName,
    /// The time span asked for.
    pub span: (f64, f64),
}

/// What a run produced, counted as its rows and crossings arrive (for a summary).
#[derive(Debug, Clone, Default)]
pub struct Tally {
    /// Rows seen.
    pub rows: u64,
    /// The largest constraint drift of any row (NaN once one was unknown).
    pub max_drift: f64,
    /// The last row.
    pub last: Vec<f64>,
    /// The recorded crossings.
    pub crossings: Vec<Crossing>,
}

impl Tally {
    /// Counts an output row.
    pub fn row(&mut self, row: &[f64]) {
        self.rows += 1;
        // NaN (drift unknown) stays NaN: `max` would drop it.
        let drift = row.last().copied().unwrap_or(f64::NAN);
        self.max_drift = if drift.is_nan() || self.max_drift.is_nan() {
            f64::NAN
        } else {
            self.max_drift.max(drift)
        };
        self.last.clear();
        self.last.extend_from_slice(row);
    }

    /// Keeps a recorded crossing (its `t`, coordinates and rates).
    pub fn crossing(&mut self, crossing: &simulation::RecordedCrossing<'_>) {
        let n = crossing.row.len().saturating_sub(3) / 2;
        self.crossings.push(Crossing {
            event: crossing.event,
            rising: crossing.rising,
            state: crossing.row[..=2 * n].to_vec(),
        });
    }

    /// The last row's relative energy error.
    #[must_use]
    pub fn energy_error(&self) -> f64 {
        self.last.iter().rev().nth(1).copied().unwrap_or(f64::NAN)
    }

    /// The summary of the run that produced these (docs/json.md, "simulate --summary"),
    /// which ended as `ending` ([`Streamed::summary_json`] passes its own).
    #[must_use]
    pub fn summary(
        &self,
        model: &str,
        simulation: &Simulation,
        outcome: &Outcome,
        ending: &Ending,
        wall_time: f64,
    ) -> Value {
        let integrator = simulation.integrator_options();
        let columns = simulation.columns();
        let n = (columns.len() - 3) / 2;
        let (t_start, t_end) = simulation.span();
        let events: Vec<Value> = self
            .crossings
            .iter()
            .map(|c| {
                let state: serde_json::Map<String, Value> = columns[1..=2 * n]
                    .iter()
                    .zip(&c.state[1..])
                    .map(|(name, value)| (name.clone(), json!(value)))
                    .collect();
                json!({
                    "event": simulation.recorded().get(c.event),
                    "direction": direction(c.rising),
                    "t": c.state[0],
                    "state": state,
                })
            })
            .collect();
        json!({
            "schema": report::SCHEMA,
            "model": model,
            "method": simulation.method().to_string(),
            "rtol": integrator.rtol,
            "atol": integrator.atol,
            "step": integrator.step,
            "output_step": integrator.output_step,
            "t_start": t_start,
            "t_end": t_end,
            "t_reached": outcome.t,
            "outcome": ending.to_json(outcome.t),
            "steps": outcome.stats.steps,
            "rejected_steps": outcome.stats.rejected,
            "rhs_evaluations": outcome.stats.evaluations,
            "error_estimate": outcome.error_estimate,
            "wall_time_s": wall_time,
            "rows": self.rows,
            "final_energy_error": self.energy_error(),
            "max_constraint_drift": self.max_drift,
            "max_position_drift": simulation.drift().map(|d| d.position),
            "max_velocity_drift": simulation.drift().map(|d| d.velocity),
            "events": events,
        })
    }
}

/// `rising` or `falling`.
#[must_use]
pub fn direction(rising: bool) -> &'static str {
    if rising {
        "rising"
    } else {
        "falling"
    }
}

impl Analysis {
    /// The settings of a run: `options`, else the model's `simulate` statement, else the
    /// defaults.
    ///
    /// # Errors
    /// [`Error::NoEndTime`], [`Error::UnknownMethod`], or an invalid setting.
    pub fn settings(&self, options: &SimulationOptions) -> Result<Settings, Error> {
        let statement = self.source().and_then(|s| s.model.simulation());
        let model = self.source().map(|s| &s.model);
        let from_model = |pick: fn(&model::Simulation) -> Option<&model::Expr>| {
            let e = pick(statement?)?;
            model?.evaluate_constant(e)
        };
        let method = match options.method {
            Some(m) => Some(m),
            None => match statement.and_then(|s| s.method.as_ref()) {
                Some(name) => Some(MethodName::parse(&name.name).ok_or_else(|| {
                    self.in_statement(
                        Error::UnknownMethod {
                            name: name.name.clone(),
                        },
                        name.span,
                    )
                })?),
                None => None,
            },
        };
        let t_end = options
            .t_end
            .or_else(|| from_model(|s| s.to.as_ref()))
            .ok_or(Error::NoEndTime)?;
        let mut settings = Settings::new(t_end);
        settings.t_start = options
            .t_start
            .or_else(|| from_model(|s| s.from.as_ref()))
            .unwrap_or(0.0);
        settings.rtol = options
            .rtol
            .or_else(|| from_model(|s| s.rtol.as_ref()))
            .unwrap_or(settings.rtol);
        settings.atol = options
            .atol
            .or_else(|| from_model(|s| s.atol.as_ref()))
            .unwrap_or(settings.atol);
        // Without a method named, the tolerance decides (dop853 for tight ones).
        settings.method = method.unwrap_or_else(|| MethodName::for_tolerance(settings.rtol));
        settings.output_step = options
            .output_step
            .or_else(|| from_model(|s| s.step.as_ref()));
        settings.step = options.step;
        settings.max_steps = options.max_steps.unwrap_or(settings.max_steps);
        settings.max_rows = options.max_rows.unwrap_or(settings.max_rows);
        settings
            .validate()
            .map_err(|e| self.locate_setting(e, options))?;
        Ok(settings)
    }

    /// A bad setting that came from the model's `simulate` statement, with its line and
    /// column; one the caller gave stays as it is. A setting that is wrong with another
    /// (an end time equal to the start, a span too long for its output step) points at the
    /// first of them that the statement gave.
    pub(crate) fn locate_setting(
        &self,
        error: SimulationError,
        options: &SimulationOptions,
    ) -> Error {
        type Pick = fn(&model::Simulation) -> Option<&model::Expr>;
        let from: (bool, Pick) = (options.t_start.is_some(), |s| s.from.as_ref());
        let to: (bool, Pick) = (options.t_end.is_some(), |s| s.to.as_ref());
        let step: (bool, Pick) = (options.output_step.is_some(), |s| s.step.as_ref());
        let parts: Vec<(bool, Pick)> = match &error {
            SimulationError::InvalidSetting { setting, .. } => match *setting {
                "start time" => vec![from],
                "end time" => vec![to],
                "rtol" => vec![(options.rtol.is_some(), |s| s.rtol.as_ref())],
                "atol" => vec![(options.atol.is_some(), |s| s.atol.as_ref())],
                "output step" => vec![step],
                _ => Vec::new(),
            },
            SimulationError::EmptySpan { .. } => vec![to, from],
            // The span's length and the output step decide: a start from the statement with
            // both of those from the caller is not the model's mistake.
            SimulationError::BeyondLimit {
                limit: Limit::Rows, ..
            } => vec![step, to],
            SimulationError::BeyondLimit {
                limit: Limit::Steps,
                ..
            } => vec![to],
            _ => Vec::new(),
        };
        let span = parts
            .into_iter()
            .filter(|(given, _)| !given)
            .find_map(|(_, pick)| statement_part(self, pick));
        match span {
            Some(span) => self.in_statement(error.into(), span),
            None => error.into(),
        }
    }

    /// `error`, located at `span` of the model's `simulate` statement.
    fn in_statement(&self, error: Error, span: model::Span) -> Error {
        let Some(source) = self.source() else {
            return error;
        };
        let at = model::line_col(&source.text, span.start);
        Error::Located {
            message: format!("in the `simulate` statement: {error}"),
            line: at.line,
            column: at.column,
            kind: crate::ErrorKind::Input,
        }
    }

    /// A prepared run: the equations (derived once) compiled with the current values, the
    /// initial state, the stop events (the condition asked for, then the one-sided contacts
    /// unless `through_contact_loss`).
    ///
    /// # Errors
    /// As [`Analysis::settings`] and [`Analysis::equations`], or a [`Error::Simulation`].
    pub fn simulation(&self, options: &SimulationOptions) -> Result<Simulation, Error> {
        self.simulation_by(self.simulation_method(), options)
    }

    /// A prepared run of the equations `method` names: Lagrange's (as
    /// [`Analysis::simulation`] prepares for most models) or Kane's reduced equations
    /// ([`Analysis::kane_simulation`]); the two routes give the same columns.
    ///
    /// # Errors
    /// As [`Analysis::simulation`] or [`Analysis::kane_simulation`].
    pub fn simulation_by(
        &self,
        method: crate::Method,
        options: &SimulationOptions,
    ) -> Result<Simulation, Error> {
        if method == crate::Method::Kane {
            return self.kane_simulation(options);
        }
        let settings = self.settings(options)?;
        let equations = self.equations()?;
        let mut stop_events: Vec<StopEvent> = options
            .stop_when
            .iter()
            .map(|text| StopEvent::Condition(text.clone()))
            .collect();
        let mut numeric_contacts = None;
        if !options.through_contact_loss {
            // Numerically where the reactions are evaluated so (not with `gauss`, whose
            // state holds momenta), else their closed forms.
            numeric_contacts = self.numeric_contacts(settings.method)?;
            if numeric_contacts.is_none() {
                stop_events.extend(self.one_sided_contacts()?.iter().map(|(name, value)| {
                    StopEvent::ContactLost {
                        constraint: name.clone(),
                        value: *value,
                    }
                }));
            }
        }
        let setup = Setup {
            values: self.values()?,
            timed_inputs: self.timed_inputs().to_vec(),
            initial: self.initial_state()?,
            stop_events,
            record_when: options.record_when.clone(),
            numeric_contacts,
        };
        Simulation::prepare(self.system(), equations, &settings, setup)
            .map_err(|e| self.locate_setting(e, options))
    }

    /// Runs a simulation and keeps every row.
    ///
    /// # Errors
    /// As [`Analysis::simulation`]. A run that fails part-way is not an error: its
    /// [`Run::ending`] says so and the rows before are kept.
    pub fn simulate(&self, options: &SimulationOptions) -> Result<Run, Error> {
        let mut simulation = self.simulation(options)?;
        Ok(run_kept(&mut simulation))
    }

    /// Many runs, the values of `names` set to each row of `values` in turn, on all cores;
    /// the equations are derived once for all of them. `on_done` is called after each run
    /// (for a progress bar).
    ///
    /// # Errors
    /// As [`Analysis::simulation`] for the first run (a name or setting that is wrong for
    /// every run); later runs carry their own errors.
    pub fn sweep(
        &self,
        options: &SimulationOptions,
        names: &[String],
        values: &[Vec<f64>],
        on_done: &(dyn Fn() + Sync),
    ) -> Result<Vec<Result<SweepRun, Error>>, Error> {
        // Derived (and the contacts found) once, before the runs share the analysis; Kane's
        // route derives nothing symbolic.
        let method = self.simulation_method();
        if method == crate::Method::Lagrange {
            self.equations()?;
            if !options.through_contact_loss {
                self.one_sided_contacts()?;
            }
        }
        let one = |row: &Vec<f64>| -> Result<SweepRun, Error> {
            let mut analysis = self.clone();
            for (name, value) in names.iter().zip(row) {
                analysis.set_value(name, *value)?;
            }
            let mut simulation = analysis.simulation_by(method, options)?;
            let mut last = Vec::new();
            let outcome = simulation.run(&mut |r| {
                last.clear();
                last.extend_from_slice(r);
            });
            Ok(SweepRun {
                last,
                steps: outcome.stats.steps,
                ending: Ending::of(&simulation, &outcome),
            })
        };
        if let Some(first) = values.first() {
            one(first)?;
        }
        Ok(values
            .par_iter()
            .map(|row| {
                let result = one(row);
                on_done();
                result
            })
            .collect())
    }
}

/// Where in the model text a part of its `simulate` statement is.
fn statement_part(
    analysis: &Analysis,
    pick: fn(&model::Simulation) -> Option<&model::Expr>,
) -> Option<model::Span> {
    let statement = analysis.source()?.model.simulation()?;
    pick(statement).map(|e| e.span)
}

/// One run of a sweep: its last row and how it ended.
#[derive(Debug, Clone)]
pub struct SweepRun {
    /// The last output row.
    pub last: Vec<f64>,
    /// Accepted steps.
    pub steps: u64,
    /// How it ended.
    pub ending: Ending,
}

/// A run written as it goes: its outcome, tally, the rows kept (when asked) and wall time.
#[derive(Debug, Clone)]
pub struct Streamed {
    /// How the integration ended, with its work.
    pub outcome: Outcome,
    /// How the run ended (the output limit included, which the outcome only knows as a
    /// halt).
    pub ending: Ending,
    /// Rows, drift, crossings.
    pub tally: Tally,
    /// Every row, when asked to keep them (for a plot).
    pub kept: Vec<Vec<f64>>,
    /// Bytes written, the header included.
    pub bytes: u64,
    /// Wall time of the run, in seconds.
    pub wall_time: f64,
}

/// Runs a prepared simulation and writes its rows to `out` as CSV (header first) as they
/// come, keeping them too when `keep`; `on_time` hears the time of each row (a progress bar).
/// The CSV stays within `max_bytes` ([`DEFAULT_MAX_BYTES`]): the run stops after the last
/// row that leaves room for one as long as the longest so far ([`Ending::OutputLimit`]).
///
/// # Errors
/// The first write error, after the run.
pub fn run_to_csv(
    simulation: &mut Simulation,
    out: &mut dyn std::io::Write,
    keep: bool,
    max_bytes: u64,
    on_time: &mut dyn FnMut(f64),
) -> std::io::Result<Streamed> {
    run_to_csv_with_reactions(simulation, None, out, keep, max_bytes, on_time)
}

/// [`run_to_csv`], each row followed by the reactions of `reactions` at its state (columns
/// named by [`ReactionProbe::columns`], evaluated numerically; the rows kept carry them too).
///
/// # Errors
/// As [`run_to_csv`].
pub fn run_to_csv_with_reactions(
    simulation: &mut Simulation,
    reactions: Option<&ReactionProbe>,
    out: &mut dyn std::io::Write,
    keep: bool,
    max_bytes: u64,
    on_time: &mut dyn FnMut(f64),
) -> std::io::Result<Streamed> {
    let mut columns = simulation.columns();
    if let Some(probe) = reactions {
        columns.extend(probe.columns());
    }
    // The reactions are evaluated on a copy: the run holds the simulation.
    let mut probing = reactions.map(|probe| (probe, simulation.clone()));
    let n = (simulation.columns().len() - 3) / 2;
    let mut extended = Vec::new();
    let header = format!("{}\n", columns.join(","));
    out.write_all(header.as_bytes())?;
    let mut write_error = None;
    let mut kept = Vec::new();
    let mut tally = Tally::default();
    let mut recorded = Tally::default();
    let mut bytes = header.len() as u64;
    let mut longest = 0;
    let mut full = false;
    let started = std::time::Instant::now();
    let outcome = simulation.run_until(
        &mut |row| {
            let full_row = match &mut probing {
                Some((probe, copy)) => {
                    extended.clear();
                    extended.extend_from_slice(row);
                    extended.extend(probe.at(copy, row[0], &row[1..=2 * n]));
                    &extended[..]
                }
                None => row,
            };
            let line = crate::csv::row(full_row);
            if write_error.is_none() {
                write_error = out.write_all(line.as_bytes()).err();
            }
            bytes += line.len() as u64;
            longest = longest.max(line.len() as u64);
            if keep {
                kept.push(full_row.to_vec());
            }
            tally.row(row);
            on_time(row[0]);
            full = bytes + longest > max_bytes;
            if full {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        },
        &mut |c| recorded.crossing(&c),
    );
    let wall_time = started.elapsed().as_secs_f64();
    if let Some(error) = write_error {
        return Err(error);
    }
    out.flush()?;
    tally.crossings = recorded.crossings;
    let ending = match outcome.stop {
        StopReason::Halted { .. } if full => Ending::OutputLimit { bytes: max_bytes },
        _ => Ending::of(simulation, &outcome),
    };
    Ok(Streamed {
        outcome,
        ending,
        tally,
        kept,
        bytes,
        wall_time,
    })
}

/// Runs a prepared simulation and keeps every row and crossing.
pub fn run_kept(simulation: &mut Simulation) -> Run {
    run_sampled(simulation, usize::MAX)
}

/// Runs a prepared simulation and keeps at most about `most` rows, evenly spread over the
/// run, and the last one: when the rows kept reach `2·most`, every other one is dropped and
/// from then on only every other row is kept (then every fourth, …). Memory stays bounded
/// whatever the run's length; a plot of the rows kept looks like one of all of them as long
/// as `most` is well above the plot's width.
pub fn run_sampled(simulation: &mut Simulation, most: usize) -> Run {
    let columns = simulation.columns();
    let n = (columns.len() - 3) / 2;
    let mut rows = Sampled::new(most);
    let mut crossings = Vec::new();
    let outcome = simulation.run_recording(&mut |row| rows.push(row), &mut |c| {
        crossings.push(Crossing {
            event: c.event,
            rising: c.rising,
            state: c.row[..=2 * n].to_vec(),
        });
    });
    let rows = rows.finish();
    Run {
        columns,
        rows,
        crossings,
        ending: Ending::of(simulation, &outcome),
        t: outcome.t,
        stats: outcome.stats,
        method: simulation.method(),
        span: simulation.span(),
    }
}

/// Rows thinned as they come (see [`run_sampled`]).
struct Sampled {
    most: usize,
    rows: Vec<Vec<f64>>,
    /// Every `stride`-th row is kept.
    stride: u64,
    seen: u64,
    /// The latest row, and whether it is among `rows`.
    last: Vec<f64>,
    last_kept: bool,
}

impl Sampled {
    fn new(most: usize) -> Sampled {
        Sampled {
            most: most.max(1),
            rows: Vec::new(),
            stride: 1,
            seen: 0,
            last: Vec::new(),
            last_kept: true,
        }
    }

    fn push(&mut self, row: &[f64]) {
        self.last_kept = self.seen % self.stride == 0;
        if self.last_kept {
            self.rows.push(row.to_vec());
            if self.rows.len() >= self.most.saturating_mul(2) {
                // Rows i·stride are kept; the even i are the multiples of the new stride.
                let mut i = 0;
                self.rows.retain(|_| {
                    i += 1;
                    i % 2 == 1
                });
                self.stride *= 2;
                self.last_kept = false;
            }
        }
        self.seen += 1;
        self.last.clear();
        self.last.extend_from_slice(row);
    }

    /// The rows kept, the last one of the run included.
    fn finish(mut self) -> Vec<Vec<f64>> {
        if !self.last_kept {
            self.rows.push(self.last);
        }
        self.rows
    }
}

/// The values of a sweep: a grid of `steps + 1` values over one range.
#[must_use]
pub fn grid(range: &Range, steps: usize) -> Vec<Vec<f64>> {
    let steps = steps.max(1);
    (0..=steps)
        .map(|k| vec![range.low + (range.high - range.low) * k as f64 / steps as f64])
        .collect()
}

/// The values of a Monte-Carlo sweep: `count` draws, each value uniform in its range; the
/// same seed gives the same draws everywhere.
///
/// # Errors
/// [`AssignmentError::Form`] for zero samples.
pub fn samples(ranges: &[Range], count: usize, seed: u64) -> Result<Vec<Vec<f64>>, Error> {
    if count == 0 {
        return Err(AssignmentError::Form {
            text: "0".into(),
            form: "a number of samples of at least 1",
        }
        .into());
    }
    let mut state = seed.max(1);
    Ok((0..count)
        .map(|_| {
            ranges
                .iter()
                .map(|r| r.low + (r.high - r.low) * uniform(&mut state))
                .collect()
        })
        .collect())
}

/// The values of a sweep over `ranges`: `samples` Monte-Carlo draws, or else a grid of
/// `steps + 1` values over one range.
///
/// # Errors
/// [`Error::NotAvailable`] for several ranges without samples, or zero samples.
pub fn plan(
    ranges: &[Range],
    samples: Option<usize>,
    steps: usize,
    seed: u64,
) -> Result<Vec<Vec<f64>>, Error> {
    match (samples, ranges) {
        (Some(count), _) => self::samples(ranges, count, seed),
        (None, [range]) => Ok(grid(range, steps)),
        (None, _) => Err(Error::NotAvailable(
            "several ranges need Monte-Carlo samples; a grid sweeps one name".into(),
        )),
    }
}

/// A small deterministic generator (xorshift64*).
fn uniform(state: &mut u64) -> f64 {
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    let x = state.wrapping_mul(0x2545_f491_4f6c_dd1d);
    (x >> 11) as f64 / (1u64 << 53) as f64
}
