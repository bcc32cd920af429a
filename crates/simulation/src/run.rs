//! Preparing and running a simulation: settings from the model's `simulate` statement and the
//! command line, the initial state, and the output rows.

use std::fmt;

use cas::ParseContext;
use model::Model;
use numeric::{integrate, IntegratorOptions, Method, OdeSystem, Outcome, RhsError, TapeError};

use crate::compiled::Compiled;
use crate::forms::{Canonical, SecondOrder};

/// An integration method, by the name the user gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum MethodName {
    /// `dopri5` (also `rk45`): adaptive Dormand–Prince 5(4) with dense output.
    Dopri5,
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
            "gauss" | "symplectic" | "gauss-legendre" | "variational" => Some(MethodName::Gauss),
            "sdirk" | "implicit" | "stiff" | "bdf" => Some(MethodName::Sdirk),
            _ => None,
        }
    }
}

impl fmt::Display for MethodName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            MethodName::Dopri5 => "dopri5",
            MethodName::Gauss => "gauss",
            MethodName::Sdirk => "sdirk",
        })
    }
}

/// Settings of one run; `None` takes the model's `simulate` statement, then the default.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SimulationOptions {
    /// The method (default: the model's, else dopri5).
    pub method: Option<MethodName>,
    /// Start time (default: the model's `from`, else 0).
    pub t_start: Option<f64>,
    /// End time (default: the model's `to`; required).
    pub t_end: Option<f64>,
    /// Relative tolerance (default: the model's, else 1e-8).
    pub rtol: Option<f64>,
    /// Absolute tolerance (default: the model's, else 1e-10).
    pub atol: Option<f64>,
    /// Output step (default: the model's `step`, else every accepted step).
    pub output_step: Option<f64>,
    /// The integration step: fixed for gauss, initial for dopri5 (default: chosen).
    pub step: Option<f64>,
    /// Stop where this expression of `t`, the coordinates (`q`) and rates (`q_d`) crosses zero.
    pub stop_when: Option<String>,
    /// Further stop events, after `stop_when`'s: expressions of `t`, `q`, `q̇` that stop the run
    /// where they cross zero (a one-sided reaction — a contact's normal force, a rope's
    /// tension — whose sign change means the constraint is lost).
    pub stop_events: Vec<cas::Expr>,
}

/// What stops a simulation before it starts.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimulationError {
    /// The equations could not be derived.
    #[error(transparent)]
    Mechanics(#[from] mechanics::MechanicsError),
    /// The model could not be lowered.
    #[error(transparent)]
    Lower(#[from] model::LowerError),
    /// No end time.
    #[error("no end time: give --t-end, or write `simulate to T` in the model")]
    NoEndTime,
    /// A setting is not a finite number, or out of range.
    #[error("invalid setting `{setting}`: {reason}")]
    InvalidSetting {
        /// The setting.
        setting: &'static str,
        /// Why.
        reason: String,
    },
    /// An unknown method name in the model's `simulate` statement.
    #[error("unknown method `{name}` (available: dopri5, gauss, sdirk)")]
    UnknownMethod {
        /// The name.
        name: String,
    },
    /// An expression needs a value that the model does not give.
    #[error("{0}; give it a value in the model or with --set NAME=VALUE")]
    MissingValue(TapeError),
    /// An initial value is not a number.
    #[error("the initial value of `{coordinate}` is not a number")]
    InitialValue {
        /// The coordinate (with `'` for its rate).
        coordinate: String,
    },
    /// The `--stop-when` expression does not parse.
    #[error("--stop-when: {0}")]
    StopWhen(String),
    /// The symplectic method needs an unconstrained system.
    #[error("gauss integrates Hamilton's equations and does not handle constraints kept with multipliers ({constraints}); use dopri5")]
    GaussWithConstraints {
        /// The constraints.
        constraints: String,
    },
    /// The initial state could not be made consistent, or the equations fail there.
    #[error("at the initial state: {0}")]
    Initial(RhsError),
}

/// A prepared simulation: compiled equations, initial state, settings.
#[derive(Debug, Clone)]
pub struct Simulation {
    compiled: Compiled,
    coordinates: Vec<String>,
    method: MethodName,
    t_start: f64,
    t_end: f64,
    options: IntegratorOptions,
    initial: Vec<f64>,
    initial_energy: f64,
}

impl Simulation {
    /// Derives, compiles and sets up a run of `model` (overrides already applied).
    ///
    /// # Errors
    /// A [`SimulationError`] saying what is missing or wrong.
    pub fn prepare(
        model: &Model,
        options: &SimulationOptions,
    ) -> Result<Simulation, SimulationError> {
        let settings = model.simulation();
        let from_model = |e: Option<&model::Expr>| e.and_then(|e| model.evaluate_constant(e));
        let method = match options.method {
            Some(m) => m,
            None => match settings.and_then(|s| s.method.as_ref()) {
                Some(name) => {
                    MethodName::parse(&name.name).ok_or_else(|| SimulationError::UnknownMethod {
                        name: name.name.clone(),
                    })?
                }
                None => MethodName::Dopri5,
            },
        };
        let t_start = options
            .t_start
            .or_else(|| from_model(settings.and_then(|s| s.from.as_ref())))
            .unwrap_or(0.0);
        let t_end = options
            .t_end
            .or_else(|| from_model(settings.and_then(|s| s.to.as_ref())))
            .ok_or(SimulationError::NoEndTime)?;
        let rtol = options
            .rtol
            .or_else(|| from_model(settings.and_then(|s| s.rtol.as_ref())))
            .unwrap_or(1e-8);
        let atol = options
            .atol
            .or_else(|| from_model(settings.and_then(|s| s.atol.as_ref())))
            .unwrap_or(1e-10);
        let output_step = options
            .output_step
            .or_else(|| from_model(settings.and_then(|s| s.step.as_ref())));
        check_setting(
            "t-end",
            t_end,
            |x| x.is_finite() && x != t_start,
            "must differ from the start time",
        )?;
        check_setting("t-start", t_start, f64::is_finite, "must be finite")?;
        check_setting("rtol", rtol, |x| x > 0.0 && x < 1.0, "must be in (0, 1)")?;
        check_setting(
            "atol",
            atol,
            |x| x > 0.0 && x.is_finite(),
            "must be positive",
        )?;
        if let Some(s) = output_step {
            check_setting("step", s, |x| x > 0.0 && x.is_finite(), "must be positive")?;
        }
        if let Some(s) = options.step {
            check_setting(
                "integration step",
                s,
                |x| x > 0.0 && x.is_finite(),
                "must be positive",
            )?;
        }

        let system = model::lower(model)?;
        let equations = mechanics::derive(&system)?;
        let coordinates = equations.coordinates().to_vec();
        if method == MethodName::Gauss && !equations.constraint_names().is_empty() {
            return Err(SimulationError::GaussWithConstraints {
                constraints: equations.constraint_names().join(", "),
            });
        }
        let events = match &options.stop_when {
            Some(text) => {
                let context = coordinates
                    .iter()
                    .fold(ParseContext::new(), |c, q| c.with_coordinate(q));
                vec![cas::parse(text, &context)
                    .map_err(|e| SimulationError::StopWhen(e.to_string()))?]
            }
            None => Vec::new(),
        };
        let events: Vec<cas::Expr> = events
            .into_iter()
            .chain(options.stop_events.iter().copied())
            .collect();
        let parameters = model.numeric_values();
        let mut compiled = Compiled::new(
            &system,
            &equations,
            &parameters,
            &events,
            method == MethodName::Gauss,
        )
        .map_err(SimulationError::MissingValue)?;

        let n = coordinates.len();
        let mut initial = vec![0.0; 2 * n];
        for (k, q) in coordinates.iter().enumerate() {
            initial[k] =
                model
                    .initial_value(q, false)
                    .ok_or_else(|| SimulationError::InitialValue {
                        coordinate: q.clone(),
                    })?;
            initial[n + k] =
                model
                    .initial_value(q, true)
                    .ok_or_else(|| SimulationError::InitialValue {
                        coordinate: format!("{q}'"),
                    })?;
        }
        // Constrained: start on the constraint manifold (positions, then velocities).
        SecondOrder::new(&mut compiled)
            .project(t_start, &mut initial)
            .map_err(SimulationError::Initial)?;
        let mut probe = vec![0.0; 2 * n];
        SecondOrder::new(&mut compiled)
            .rhs(t_start, &initial, &mut probe)
            .map_err(SimulationError::Initial)?;
        compiled.set_state(&initial[..n], &initial[n..], t_start);
        let (initial_energy, _) = compiled.energy_and_drift();

        Ok(Simulation {
            compiled,
            coordinates,
            method,
            t_start,
            t_end,
            options: IntegratorOptions {
                rtol,
                atol,
                step: options.step,
                output_step,
                ..IntegratorOptions::default()
            },
            initial,
            initial_energy,
        })
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

    /// How many tape instructions one right-hand side evaluation runs.
    #[must_use]
    pub fn rhs_instructions(&self) -> usize {
        self.compiled.dynamics.instruction_count()
    }

    /// Hands `body` the right-hand side `(t, (q, q̇)) → (q̇, q̈)` as the integrator sees it
    /// (buffers allocated once, outside `body`), for benchmarks and checks.
    pub fn with_rhs<R>(&mut self, body: impl FnOnce(&mut dyn OdeSystem) -> R) -> R {
        let mut system = SecondOrder::new(&mut self.compiled);
        body(&mut system)
    }

    /// Runs the simulation, handing each output row (see [`Simulation::columns`]) to
    /// `on_row`. With constraints, each written state is projected onto them (positions, then
    /// velocities), as the integrator's step ends are. The energy error is `(E − E₀)/|E₀|`, or `E − E₀` when `|E₀| < 1e-12`.
    pub fn run(&mut self, on_row: &mut dyn FnMut(&[f64])) -> Outcome {
        let n = self.coordinates.len();
        let method = self.method;
        let (t0, t1, options) = (self.t_start, self.t_end, self.options);
        let energy0 = self.initial_energy;
        let scale = if energy0.abs() < 1e-12 {
            1.0
        } else {
            energy0.abs()
        };
        let mut row = vec![0.0; 2 * n + 3];
        // The observer needs the compiled equations too (energy, drift, and for the canonical
        // form the rates); a clone keeps it apart from the integrated system.
        let mut monitor = self.compiled.clone();
        let constrained = self.compiled.m > 0;
        let mut projected = vec![0.0; 2 * n];
        let mut emit = |t: f64, q: &[f64], qd: &[f64]| {
            // Outputs between steps come from the dense output, which leaves the constraint
            // manifold by about the local error; the written state is projected back like the
            // step ends (when that fails, the state is written as it is and its drift shows).
            let (q, qd) = if constrained {
                projected[..n].copy_from_slice(q);
                projected[n..].copy_from_slice(qd);
                let saved = projected.clone();
                if SecondOrder::new(&mut monitor)
                    .project(t, &mut projected)
                    .is_err()
                {
                    projected.copy_from_slice(&saved);
                }
                (&projected[..n], &projected[n..])
            } else {
                (q, qd)
            };
            monitor.set_state(q, qd, t);
            let (energy, drift) = monitor.energy_and_drift();
            row[0] = t;
            row[1..=n].copy_from_slice(q);
            row[n + 1..=2 * n].copy_from_slice(qd);
            row[2 * n + 1] = (energy - energy0) / scale;
            row[2 * n + 2] = drift;
            on_row(&row);
        };
        match method {
            MethodName::Dopri5 | MethodName::Sdirk => {
                let mut system = SecondOrder::new(&mut self.compiled);
                integrate(
                    &mut system,
                    if method == MethodName::Sdirk {
                        Method::Sdirk
                    } else {
                        Method::Dopri5
                    },
                    t0,
                    &self.initial,
                    t1,
                    &options,
                    &mut |t, y| emit(t, &y[..n], &y[n..]),
                )
            }
            MethodName::Gauss => {
                // p = M q̇ + p₀ at the start.
                let mut converter = self.compiled.clone();
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
                let mut rates = Canonical::new(&mut converter);
                let mut system = Canonical::new(&mut self.compiled);
                integrate(
                    &mut system,
                    Method::Gauss,
                    t0,
                    &y0,
                    t1,
                    &options,
                    &mut |t, y| {
                        let qd = rates.velocity(t, y).unwrap_or_else(|_| vec![f64::NAN; n]);
                        emit(t, &y[..n], &qd);
                    },
                )
            }
        }
    }
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
