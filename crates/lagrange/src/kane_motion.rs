//! Which equations a run integrates (issue 18): Lagrange's with multipliers, or Kane's
//! reduced equations evaluated numerically ([`simulation::Simulation::prepare_kane`]) for
//! nonholonomic systems whose equations with multipliers are over the symbolic work limits
//! (the Whipple bicycle). docs/mechanics.md, "Simulating on Kane's route", says why the
//! choice is made this way.

use mechanics::kane::KaneError;
use simulation::{Setup, Simulation, StopEvent};

use crate::kane_eom::Method;
use crate::{Analysis, Error, SimulationOptions};

impl Analysis {
    /// The equations a run of this model integrates: [`Method::Kane`] when the system has
    /// velocity constraints (rolling, a blade, `vel(P)` rows) and Kane's reduced equations are
    /// themselves over the size limits for a symbolic form (then the equations with
    /// multipliers, in all the coordinates, are larger still: their derivation would run into
    /// the work limits after seconds), else [`Method::Lagrange`]. The test is one compilation
    /// of the geometry and one evaluation of the reduced equations over shared sub-expressions,
    /// milliseconds.
    #[must_use]
    pub fn simulation_method(&self) -> Method {
        if !self.has_velocity_constraints() {
            return Method::Lagrange;
        }
        let Ok((system, values)) = self.kane_system() else {
            return Method::Lagrange;
        };
        let Ok(motion) = self.steady_motion() else {
            return Method::Lagrange;
        };
        match system.symbolic(&motion.configuration, &values) {
            Err(KaneError::TooLarge { .. } | KaneError::WorkLimit(_)) => Method::Kane,
            _ => Method::Lagrange,
        }
    }

    /// Whether any constraint of the system is given at velocity level.
    pub(crate) fn has_velocity_constraints(&self) -> bool {
        self.system().constraints().iter().any(|c| {
            c.equations
                .iter()
                .any(|e| matches!(e, mechanics::ConstraintForm::Velocity(_)))
        })
    }

    /// A prepared run on Kane's route: the model's `initial` statement as the other route
    /// reads it (the rates it gives are kept exactly, the others follow from the
    /// constraints), the stop condition and the recorded expressions; one-sided contacts are
    /// not watched (their reactions need the multipliers this route does not have), so a
    /// model with one is refused unless the caller runs through contact loss.
    ///
    /// # Errors
    /// As [`Analysis::settings`]; [`Error::NotAvailable`] for a model with a one-sided
    /// constraint; [`Error::Simulation`] when the speeds, the initial configuration or the
    /// initial rates cannot be found.
    pub fn kane_simulation(&self, options: &SimulationOptions) -> Result<Simulation, Error> {
        let settings = self.settings(options)?;
        if !options.through_contact_loss && self.has_one_sided_constraint() {
            return Err(Error::NotAvailable(
                "a run on Kane's route does not watch one-sided contacts; run through contact loss to go on regardless".into(),
            ));
        }
        let motion = self.steady_motion()?;
        let given: Vec<bool> = motion.rates.iter().map(Option::is_some).collect();
        let mut initial = motion.configuration.clone();
        initial.extend(motion.rates.iter().map(|r| r.unwrap_or(0.0)));
        let setup = Setup {
            values: self.values()?,
            timed_inputs: self.timed_inputs().to_vec(),
            initial,
            stop_events: options
                .stop_when
                .iter()
                .map(|text| StopEvent::Condition(text.clone()))
                .collect(),
            record_when: options.record_when.clone(),
            numeric_contacts: None,
        };
        Simulation::prepare_kane(self.system(), &settings, setup, &given)
            .map_err(|e| self.locate_kane_error(e, options))
    }

    /// Whether a constraint of the model holds one way only (a contact, a rope).
    fn has_one_sided_constraint(&self) -> bool {
        self.requests()
            .is_ok_and(|requests| requests.iter().any(crate::reactions::one_sided))
    }

    /// A Kane error of the initial state, at the model's `initial` statement; others as the
    /// settings' are.
    fn locate_kane_error(
        &self,
        error: simulation::SimulationError,
        options: &SimulationOptions,
    ) -> Error {
        use simulation::SimulationError as S;
        let span = match &error {
            S::Kane(_) | S::Initial(_) => self
                .source()
                .and_then(|s| s.model.initial().first().map(|i| i.value.span)),
            _ => None,
        };
        let (Some(span), Some(source)) = (span, self.source()) else {
            return self.locate_setting(error, options);
        };
        let at = model::line_col(&source.text, span.start);
        let kind = Error::Simulation(error.clone()).kind();
        Error::Located {
            message: format!("starting the run: {error}"),
            line: at.line,
            column: at.column,
            kind,
        }
    }
}
