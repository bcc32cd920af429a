//! The right-hand side on Kane's route ([`mechanics::kane::KaneMotion`]): the reduced
//! equations `M_r u̇ = f_r` evaluated numerically at each state, for systems whose equations
//! with multipliers are over the symbolic work limits (the Whipple bicycle). The integrated
//! state is `y = (q_F, u)` (the coordinates no holonomic constraint fixes, the independent
//! speeds); output rows, events and the energy are read at the full state `(q, q̇)` that
//! [`KaneMotion::full_state`] rebuilds, so a run's columns are those of the Lagrange route.

use cas::Expr;
use mechanics::kane::{KaneError, KaneMotion};
use numeric::{OdeSystem, RhsError};

use crate::compiled::{input_layout, Evaluator, Folder};
use crate::run::Drift;

/// A system on Kane's route with its events compiled over `[q, q̇, t, parameters]`.
#[derive(Clone, Debug)]
pub(crate) struct KaneRoute {
    pub(crate) motion: KaneMotion,
    pub(crate) n: usize,
    events: Option<Evaluator>,
    pub(crate) event_outputs: usize,
    pub(crate) stopping_events: usize,
    inputs: Vec<f64>,
    /// The integrated state at the start, `(q_F, u)`.
    pub(crate) start: Vec<f64>,
    /// The full state at the start, `(q, q̇)`.
    pub(crate) start_full: Vec<f64>,
}

impl KaneRoute {
    /// Compiles the events (the first `stopping_events` stop the run, the others are recorded).
    pub(crate) fn new(
        motion: KaneMotion,
        coordinates: &[String],
        parameters: &[(String, f64)],
        events: &[Expr],
        stopping_events: usize,
    ) -> Result<KaneRoute, numeric::TapeError> {
        let (layout, inputs) = input_layout(coordinates, parameters);
        let fold = Folder::new(parameters, &[]);
        let compiled = if events.is_empty() {
            None
        } else {
            Some(Evaluator::new(&fold.all(events), &layout)?)
        };
        Ok(KaneRoute {
            motion,
            n: coordinates.len(),
            events: compiled,
            event_outputs: events.len(),
            stopping_events,
            inputs,
            start: Vec::new(),
            start_full: Vec::new(),
        })
    }

    /// `(q, q̇)` of the reduced state `y` at `t`, one vector.
    pub(crate) fn full(&mut self, t: f64, y: &[f64]) -> Result<Vec<f64>, RhsError> {
        let (mut q, qd) = self.motion.full_state(t, y).map_err(rhs_error)?;
        q.extend(qd);
        Ok(q)
    }

    /// The energy at a full state.
    pub(crate) fn energy(&self, t: f64, state: &[f64]) -> f64 {
        self.motion.energy(&state[..self.n], &state[self.n..], t)
    }
}

/// A Kane error as the integrator's: singular matrices as such, a failed Newton step on the
/// holonomic constraints as a failed projection.
pub(crate) fn rhs_error(error: KaneError) -> RhsError {
    match error {
        KaneError::NoConfiguration(_) => RhsError::ProjectionFailed,
        KaneError::Singular(_) => RhsError::SingularMatrix { column: 0 },
        _ => RhsError::NotFinite,
    }
}

/// The reduced equations as the integrator sees them.
pub(crate) struct KaneOde<'r> {
    pub(crate) route: &'r mut KaneRoute,
}

impl OdeSystem for KaneOde<'_> {
    fn dimension(&self) -> usize {
        self.route.motion.dimension()
    }

    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        self.route.motion.derivative(t, y, dy).map_err(rhs_error)?;
        if dy.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(RhsError::NotFinite)
        }
    }

    fn event_count(&self) -> usize {
        self.route.event_outputs
    }

    fn event_stops(&self, index: usize) -> bool {
        index < self.route.stopping_events
    }

    fn events(&mut self, t: f64, y: &[f64], g: &mut [f64]) {
        let n = self.route.n;
        let Ok(state) = self.route.full(t, y) else {
            g.fill(f64::NAN);
            return;
        };
        let route = &mut *self.route;
        route.inputs[..2 * n].copy_from_slice(&state);
        route.inputs[2 * n] = t;
        if let Some(events) = route.events.as_mut() {
            g.copy_from_slice(&events.eval(&route.inputs)[..g.len()]);
        }
    }
}

/// Output rows `[t, q…, q̇…, energy error, constraint drift]` of a run on Kane's route, from
/// its own copy of the motion (Newton's start there follows the rows, not the steps).
pub(crate) struct KaneRows {
    route: KaneRoute,
    energy0: f64,
    scale: f64,
    pub(crate) drift: Drift,
    row: Vec<f64>,
}

impl KaneRows {
    pub(crate) fn new(route: &KaneRoute, energy0: f64) -> KaneRows {
        KaneRows {
            route: route.clone(),
            energy0,
            scale: if energy0.abs() < 1e-12 {
                1.0
            } else {
                energy0.abs()
            },
            drift: Drift::default(),
            row: vec![0.0; 2 * route.n + 3],
        }
    }

    /// The row at `(t, y)`; NaN where the full state cannot be rebuilt.
    pub(crate) fn row(&mut self, t: f64, y: &[f64]) -> &[f64] {
        let n = self.route.n;
        self.row[0] = t;
        match self.route.full(t, y) {
            Ok(state) => {
                let energy = self.route.energy(t, &state);
                let (position, velocity) = self.route.motion.drift(&state[..n], &state[n..], t);
                self.drift.note(position, velocity);
                self.row[1..=2 * n].copy_from_slice(&state);
                self.row[2 * n + 1] = (energy - self.energy0) / self.scale;
                self.row[2 * n + 2] = position.max(velocity);
            }
            Err(_) => self.row[1..].fill(f64::NAN),
        }
        &self.row
    }
}
