//! Reactions evaluated numerically, state by state (issue 17): the route taken where the
//! closed form would be large (a size limit, [`ReactionRoute::Auto`]) or when asked
//! ([`ReactionRoute::Numeric`]). The reactions are compiled once
//! ([`mechanics::ReactionEvaluator`]); at each state the accelerations and multipliers come
//! from the compiled equations of a [`Simulation`], so no closed form is ever built.
//!
//! What uses them: `lagrange reactions` (the values at the initial state), the CSV of
//! `lagrange simulate` (one column per component, by name: docs/reactions.md), the solution's
//! reactions section and figure, and the values at each equilibrium.

use std::sync::Arc;

use mechanics::{Quantity, ReactionColumn, ReactionEvaluator, ReactionState};
use report::document::{Block, Cell, Section};
use simulation::{MethodName, NumericContacts, Simulation};

use crate::{Analysis, Error, SimulationOptions};

/// How reactions are computed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum ReactionRoute {
    /// In closed form while the closed form stays small, else numerically per state (the size
    /// limit is [`CLOSED_FORM_WORK`]).
    #[default]
    Auto,
    /// Always in closed form (may be slow, or refused as too large).
    ClosedForm,
    /// Always numerically, per state.
    Numeric,
}

/// The size limit of [`ReactionRoute::Auto`]: the closed form of a released reaction is
/// derived while the work it needs, estimated as `Σ s·k²` over the released systems (`s` the
/// operations of a released system's compiled geometry, `k` its coordinates: the
/// Lagrangian's terms grow with `s` and its equations with `k²`), stays at or below this.
/// Chosen from the examples (docs/performance.md, "Reactions by the numbers"): every seed
/// exercise keeps its closed form, which a course solution prints (7.2's rolling cone, work
/// 5,632, is the largest), as do the pendulums, contacts and the clamp (work 60–4,416); the
/// rolling disk on the incline (7,936) and larger are evaluated numerically.
pub const CLOSED_FORM_WORK: usize = 6_000;

/// The largest KKT system `[M Aᵀ; A 0]` whose multipliers [`ReactionRoute::Auto`] solves in
/// closed form when the constraint rows `A` depend on the coordinates (constant rows, as an
/// Atwood machine's rope, stay cheap at any size): the slider-crank's 5×5 takes 4 s, the
/// four-bar's is refused as too large.
pub const CLOSED_FORM_KKT: usize = 4;

/// The columns' names, and at each equilibrium every column's value (`None` for an
/// equilibrium whose coordinates are not the equations' own).
pub type AtEquilibria = (Vec<String>, Vec<Option<Vec<f64>>>);

/// The reactions at one state, evaluated numerically.
#[derive(Debug, Clone, PartialEq)]
pub struct ReactionValues {
    /// Time.
    pub t: f64,
    /// The state: the coordinates, then their rates.
    pub state: Vec<f64>,
    /// The coordinates' names.
    pub coordinates: Vec<String>,
    /// Each column's name and value (see [`mechanics::ReactionColumn`]).
    pub values: Vec<(String, f64)>,
}

impl ReactionValues {
    /// The values as text: the state, then one line per column.
    #[must_use]
    pub fn to_text(&self) -> String {
        let n = self.coordinates.len();
        let state: Vec<String> = (self.coordinates.iter().zip(&self.state))
            .map(|(q, x)| format!("{q} = {x}"))
            .chain(
                (self.coordinates.iter().zip(&self.state[n..])).map(|(q, x)| format!("{q}' = {x}")),
            )
            .collect();
        let mut text = format!(
            "reactions evaluated numerically at t = {} ({}):\n",
            self.t,
            state.join(", ")
        );
        for (name, value) in &self.values {
            text.push_str(&format!("  {name} = {value:.9e}\n"));
        }
        text
    }

    /// The values as JSON: `t`, `state` by name, `values` by column name.
    #[must_use]
    pub fn to_json(&self) -> serde_json::Value {
        let n = self.coordinates.len();
        let mut state = serde_json::Map::new();
        for (k, q) in self.coordinates.iter().enumerate() {
            state.insert(q.clone(), json_number(self.state[k]));
            state.insert(format!("{q}_d"), json_number(self.state[n + k]));
        }
        let values: serde_json::Map<String, serde_json::Value> = (self.values.iter())
            .map(|(name, v)| (name.clone(), json_number(*v)))
            .collect();
        serde_json::json!({ "t": self.t, "state": state, "values": values })
    }
}

/// A finite number, or `null`.
pub(crate) fn json_number(x: f64) -> serde_json::Value {
    serde_json::Number::from_f64(x).map_or(serde_json::Value::Null, serde_json::Value::Number)
}

/// The reactions compiled with the current values, for the states of one simulation.
#[derive(Debug, Clone)]
pub struct ReactionProbe {
    evaluator: ReactionEvaluator,
    values: Vec<f64>,
}

impl ReactionProbe {
    /// The columns' names.
    #[must_use]
    pub fn columns(&self) -> Vec<String> {
        self.evaluator
            .columns()
            .iter()
            .map(|c| c.name.clone())
            .collect()
    }

    /// The columns' descriptions.
    #[must_use]
    pub fn described(&self) -> &[ReactionColumn] {
        self.evaluator.columns()
    }

    /// Every column at `(t, state)` of `simulation` (the coordinates, then the rates): the
    /// accelerations and multipliers are solved there on the compiled equations. NaN where
    /// they cannot be (a singular mass or KKT matrix).
    pub fn at(&self, simulation: &mut Simulation, t: f64, state: &[f64]) -> Vec<f64> {
        let n = state.len() / 2;
        let mut derivative = vec![0.0; state.len()];
        let solved = simulation.with_rhs(|system| system.rhs(t, state, &mut derivative));
        let multipliers = simulation.multipliers_at(t, state);
        let (Ok(()), Ok(multipliers)) = (solved, multipliers) else {
            return vec![f64::NAN; self.evaluator.columns().len()];
        };
        self.evaluator.evaluate(&ReactionState {
            t,
            positions: &state[..n],
            rates: &state[n..],
            accelerations: &derivative[n..],
            multipliers: &multipliers,
            values: &self.values,
        })
    }
}

impl Analysis {
    /// Chooses how reactions are computed (default: [`ReactionRoute::Auto`]).
    pub fn set_reaction_route(&mut self, route: ReactionRoute) {
        self.reaction_route = route;
        self.forget_reactions();
    }

    /// How reactions are computed.
    #[must_use]
    pub fn reaction_route(&self) -> ReactionRoute {
        self.reaction_route
    }

    /// The reactions asked for, compiled for numeric evaluation; `None` when none is asked
    /// for. Compiling derives nothing (not counted by [`Analysis::reaction_derivations`]).
    ///
    /// # Errors
    /// As [`Analysis::equations`], or [`Error::Reactions`] for a reaction this route cannot
    /// evaluate.
    pub fn reaction_evaluator(&self) -> Result<Option<&ReactionEvaluator>, Error> {
        self.evaluator
            .get_or_init(|| {
                let requests = self.requests()?;
                if requests.is_empty() {
                    return Ok(None);
                }
                let names: Vec<String> = self.values()?.into_iter().map(|(n, _)| n).collect();
                let evaluator =
                    ReactionEvaluator::new(self.system(), self.equations()?, &requests, &names)?;
                Ok(Some(evaluator))
            })
            .as_ref()
            .map(Option::as_ref)
            .map_err(Clone::clone)
    }

    /// The reactions with the current values, for a simulation's states; `None` when none
    /// is asked for.
    ///
    /// # Errors
    /// As [`Analysis::reaction_evaluator`] and [`Analysis::values`].
    pub fn reaction_probe(&self) -> Result<Option<ReactionProbe>, Error> {
        let Some(evaluator) = self.reaction_evaluator()? else {
            return Ok(None);
        };
        Ok(Some(ReactionProbe {
            evaluator: evaluator.clone(),
            values: self.values()?.into_iter().map(|(_, v)| v).collect(),
        }))
    }

    /// Whether the reactions are evaluated numerically rather than in closed form: asked for,
    /// or with [`ReactionRoute::Auto`] past the size limit ([`CLOSED_FORM_WORK`]). A reaction
    /// that cannot be evaluated numerically keeps its closed form.
    pub(crate) fn numeric_reactions_chosen(&self) -> bool {
        let compiles = || matches!(self.reaction_evaluator(), Ok(Some(_)));
        match self.reaction_route {
            ReactionRoute::ClosedForm => false,
            ReactionRoute::Numeric => compiles(),
            ReactionRoute::Auto => {
                let Ok(equations) = self.equations() else {
                    return false;
                };
                let kkt = equations.coordinates().len() + equations.constraint_names().len();
                let symbols: Vec<cas::Symbol> = (equations.coordinates().iter())
                    .filter_map(|q| cas::Expr::coordinate(q).as_symbol())
                    .collect();
                let moving_rows = (equations.constraint_matrix().iter().flatten())
                    .any(|a| symbols.iter().any(|s| !a.diff(*s).is_zero()));
                let work = match self.reaction_evaluator() {
                    Ok(Some(evaluator)) => evaluator.closed_form_work(),
                    _ => return false,
                };
                (moving_rows && kkt > CLOSED_FORM_KKT) || work > CLOSED_FORM_WORK
            }
        }
    }

    /// A simulation to evaluate reactions on: the model's settings, or one time unit from the
    /// start when it gives none (only states are evaluated, nothing is run), and no stop
    /// event (a one-sided contact's closed form is not derived for it).
    pub(crate) fn probe_simulation(&self) -> Result<Simulation, Error> {
        let mut options = SimulationOptions {
            through_contact_loss: true,
            ..SimulationOptions::default()
        };
        if self.settings(&options).is_err() {
            options.t_end = Some(options.t_start.unwrap_or(0.0) + 1.0);
        }
        self.simulation(&options)
    }

    /// The reactions at the run's initial state (the model's `initial`, projected onto the
    /// constraints), evaluated numerically.
    ///
    /// # Errors
    /// As [`Analysis::reaction_probe`] and [`Analysis::simulation`]; [`Error::Reactions`]
    /// with [`mechanics::ReactionError::Unsolvable`] when none is asked for.
    pub fn reactions_at_start(&self) -> Result<ReactionValues, Error> {
        let probe = self
            .reaction_probe()?
            .ok_or(Error::Reactions(mechanics::ReactionError::Unsolvable))?;
        let mut simulation = self.probe_simulation()?;
        let t = simulation.span().0;
        let state = simulation.initial_state().to_vec();
        let values = probe.at(&mut simulation, t, &state);
        Ok(ReactionValues {
            t,
            coordinates: self.equations()?.coordinates().to_vec(),
            values: probe.columns().into_iter().zip(values).collect(),
            state,
        })
    }

    /// The reactions at each equilibrium (in the order of [`Analysis::equilibria`]; rates
    /// zero, `t` at the start), evaluated numerically; `None` for an equilibrium whose
    /// coordinates are not the equations' own.
    ///
    /// # Errors
    /// As [`Analysis::equilibria`], [`Analysis::reactions_at_start`].
    pub fn reactions_at_equilibria(&self) -> Result<AtEquilibria, Error> {
        let Some(probe) = self.reaction_probe()? else {
            return Ok((Vec::new(), Vec::new()));
        };
        let equilibria = self.equilibria()?;
        let mut simulation = self.probe_simulation()?;
        let t = simulation.span().0;
        let coordinates = self.equations()?.coordinates();
        let rest = &equilibria.rest.coordinates;
        let values = equilibria
            .set
            .equilibria
            .iter()
            .map(|e| {
                let mut state = vec![0.0; 2 * coordinates.len()];
                for (k, q) in coordinates.iter().enumerate() {
                    let at = rest.iter().position(|r| r == q)?;
                    state[k] = *e.values.get(at)?;
                }
                Some(probe.at(&mut simulation, t, &state))
            })
            .collect();
        Ok((probe.columns(), values))
    }
}

impl Analysis {
    /// The "Constraint reactions" section when they are evaluated numerically: why, then a
    /// table of every column at the initial state and at each equilibrium.
    pub(crate) fn numeric_reactions_section(&self, start: &ReactionValues) -> Section {
        let mut section = Section::new("Constraint reactions", 2);
        section.paragraph(format!(
            "The {}. The columns are named as in docs/reactions.md; forces in inertial components.",
            crate::reactions::NUMERIC_SENTENCE.trim_start_matches("the ")
        ));
        let mut header = vec!["reaction".to_string(), format!("at t = {}", start.t)];
        let (names, at_equilibria) = self
            .reactions_at_equilibria()
            .unwrap_or_else(|_| (Vec::new(), Vec::new()));
        let equilibria: Vec<Vec<f64>> = if names.len() == start.values.len() {
            at_equilibria.into_iter().flatten().collect()
        } else {
            Vec::new()
        };
        header.extend((1..=equilibria.len()).map(|k| format!("equilibrium {k}")));
        let rows = start
            .values
            .iter()
            .enumerate()
            .map(|(i, (name, value))| {
                let mut row = vec![Cell::Text(name.clone()), Cell::Text(number(*value))];
                row.extend(equilibria.iter().map(|e| Cell::Text(number(e[i]))));
                row
            })
            .collect();
        section.blocks.push(Block::Table { header, rows });
        section
    }
}

/// A value for a table: six significant digits, `—` when not finite.
fn number(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.6e}")
    } else {
        "—".to_string()
    }
}

impl Analysis {
    /// The one-sided reactions as numeric stop events of a run of `method`, when the
    /// reactions are evaluated numerically; `None` otherwise (or with `gauss`), and then their
    /// closed forms are the stop events.
    ///
    /// # Errors
    /// As [`Analysis::reaction_probe`].
    pub(crate) fn numeric_contacts(
        &self,
        method: MethodName,
    ) -> Result<Option<NumericContacts>, Error> {
        if method == MethodName::Gauss || !self.numeric_reactions_chosen() {
            return Ok(None);
        }
        let Some(probe) = self.reaction_probe()? else {
            return Ok(None);
        };
        let columns: Vec<(String, usize)> = (probe.described().iter().enumerate())
            .filter(|(_, c)| c.quantity == Quantity::Along)
            .map(|(k, c)| (c.reaction.clone(), k))
            .collect();
        if columns.is_empty() {
            return Ok(None);
        }
        Ok(Some(NumericContacts {
            evaluator: Arc::new(probe.evaluator),
            values: probe.values,
            columns,
        }))
    }
}
