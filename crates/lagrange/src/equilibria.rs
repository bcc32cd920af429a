//! Equilibria of an [`Analysis`] with their stability, the linearized dynamics about each,
//! steady motions (cyclic coordinates spinning at a set rate) and parameter sweeps.

use mechanics::equilibria::{
    find_equilibria, rest_equations_of, spin_rate, EquilibriumSet, RestEquations, Values,
};
use mechanics::keep_distinct_configurations;
use mechanics::linearize::{linear_model, linearize_at, LinearModel, LinearizeError, Linearized};

use report::equilibria as print;
use serde_json::Value;

use crate::assign::{AssignmentError, Range};
use crate::chart::AtPole;
use crate::chart_modes::ChartModes;
use crate::equilibria_conditions::{with_condition_lines, Conditions};
use crate::{Analysis, Error};

/// The search range of a coordinate that is not an angle, unless one is given.
pub const DEFAULT_RANGE: (f64, f64) = (-10.0, 10.0);

/// How to look for equilibria.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Search {
    /// Cyclic coordinates turning at a constant rate: `(coordinate, rate)`; their relative
    /// equilibria are found, with stability by Routh's reduced potential. The rate is then
    /// the parameter `q_d` (which a sweep may vary).
    pub steady: Vec<(String, f64)>,
    /// Search ranges of coordinates that are not angles (default [`DEFAULT_RANGE`]).
    pub ranges: Vec<Range>,
}

/// The equilibria found, and the linearized dynamics about each.
#[derive(Debug, Clone)]
pub struct Equilibria {
    /// The rest (or steady-motion) equations.
    pub rest: RestEquations,
    /// The equilibria, with how completely they were found.
    pub set: EquilibriumSet,
    /// The linearization about each equilibrium, in the same order.
    pub linearized: Vec<Result<Linearized, LinearizeError>>,
    /// The inputs, in the order of the columns of `B0`.
    pub inputs: Vec<String>,
    /// At an equilibrium on a pole of the coordinates, where the linearization cannot
    /// decide, the stability decided in a regular chart (`None` elsewhere; crate::chart).
    pub at_poles: Vec<Option<AtPole>>,
    /// At a rest state on a pole of the coordinates, the linearization in the regular chart
    /// (`None` elsewhere; crate::chart_modes).
    pub pole_modes: Vec<Option<ChartModes>>,
    /// At each equilibrium known in closed form, the stability condition in the parameters
    /// (crate::equilibria_conditions).
    pub conditions: Conditions,
}

/// One step of a parameter sweep: the value, the equilibria there, the linearization about
/// each.
pub use report::equilibria::SweepRow as SweepStep;

/// Equilibria and their stability along a parameter sweep.
#[derive(Debug, Clone)]
pub struct EquilibriumSweep {
    /// The rest (or steady-motion) equations, the same at every step.
    pub rest: RestEquations,
    /// The parameter, input or steady rate that varies.
    pub parameter: String,
    /// One per value, in order.
    pub steps: Vec<SweepStep>,
}

impl EquilibriumSweep {
    /// The bifurcation table, as `lagrange equilibria --sweep` prints it.
    #[must_use]
    pub fn to_text(&self) -> String {
        print::sweep_text(&self.rest, &self.parameter, &self.steps)
    }

    /// The sweep as JSON (docs/json.md).
    #[must_use]
    pub fn to_json(&self) -> Value {
        print::sweep_json(&self.rest, &self.parameter, &self.steps)
    }

    /// Draws the bifurcation diagram (equilibria against the parameter; stable filled) to an
    /// `.svg` or `.png` file.
    ///
    /// # Errors
    /// A [`report::PlotError`]: the file cannot be written, or its extension is neither.
    pub fn plot(&self, path: &std::path::Path) -> Result<(), report::PlotError> {
        let points = print::bifurcation_points(&self.steps);
        report::plot_bifurcation(path, &self.parameter, &self.rest.coordinates, &points)
    }
}

/// Initial deviations `(δq₀, δq̇₀)` about an equilibrium, for the free response in closed form.
pub type Deviations<'a> = Option<(&'a [f64], &'a [f64])>;

impl Equilibria {
    /// Checks an index into the list of equilibria (as `lagrange equilibria` numbers them).
    ///
    /// # Errors
    /// [`Error::NoSuchEquilibrium`] when there is no equilibrium `index`.
    pub fn check_index(&self, index: usize) -> Result<(), Error> {
        let count = self.set.equilibria.len();
        if index < count {
            Ok(())
        } else {
            Err(Error::NoSuchEquilibrium { index, count })
        }
    }

    /// The equilibria and their stability, as `lagrange equilibria` prints them.
    #[must_use]
    pub fn to_text(&self) -> String {
        let text = print::equilibria_text(&self.rest, &self.set, &self.linearized);
        let text = crate::chart::with_pole_sentences(&text, &self.at_poles);
        with_condition_lines(&text, &self.conditions)
    }

    /// [`Equilibria::to_text`] as JSON (docs/json.md).
    #[must_use]
    pub fn to_json(&self) -> Value {
        let mut json = print::equilibria_json(&self.rest, &self.set, &self.linearized);
        if let Some(object) = json.as_object_mut() {
            object.insert(
                "at_poles".to_owned(),
                crate::chart::poles_json(&self.at_poles),
            );
            object.insert("stability_conditions".to_owned(), self.conditions.json());
        }
        json
    }

    /// The linearized dynamics about every equilibrium (or only the `only`-th), with the free
    /// response from `deviations` when given, as `lagrange linearize` prints them.
    #[must_use]
    pub fn linearized_text(&self, only: Option<usize>, deviations: Deviations<'_>) -> String {
        let (r, set, lin, inputs) = (&self.rest, &self.set, &self.linearized, &self.inputs);
        let text = print::linearized_text_with_response(r, set, lin, inputs, only, deviations);
        let text = crate::chart_modes::with_chart_modes(&text, &self.pole_modes);
        with_condition_lines(&text, &self.conditions)
    }

    /// [`Equilibria::linearized_text`] as JSON (docs/json.md).
    #[must_use]
    pub fn linearized_json(&self, only: Option<usize>, deviations: Deviations<'_>) -> Value {
        let (r, set, lin, inputs) = (&self.rest, &self.set, &self.linearized, &self.inputs);
        let mut json = print::linearized_json_with_response(r, set, lin, inputs, only, deviations);
        if let Some(object) = json.as_object_mut() {
            let modes = crate::chart_modes::chart_modes_json(&self.pole_modes, only);
            object.insert("at_poles".to_owned(), modes);
            object.insert("stability_conditions".to_owned(), self.conditions.json());
        }
        json
    }
}

/// What does not change along a sweep.
struct Prepared {
    rest: RestEquations,
    model: LinearModel,
    inputs: Vec<String>,
    bounds: Vec<(f64, f64)>,
    values: Values,
    known: Vec<String>,
    /// The system and its equations, to tell configurations apart.
    geometry: (mechanics::System, mechanics::Equations),
}

impl Prepared {
    fn at(
        &self,
        values: &Values,
    ) -> Result<(EquilibriumSet, Vec<Result<Linearized, LinearizeError>>), Error> {
        let mut set = find_equilibria(&self.rest, values, &self.bounds)?;
        let (system, equations) = &self.geometry;
        let periodic = &self.rest.periodic;
        keep_distinct_configurations(&mut set, system, equations, values, periodic);
        let linearized = set
            .equilibria
            .iter()
            .map(|e| {
                // With constraints kept by multipliers the stiffness holds the multipliers.
                let with = match &self.rest.constraints {
                    Some(kept) => kept.with_multipliers(values, &e.multipliers),
                    None => values.clone(),
                };
                linearize_at(
                    &self.model,
                    &self.rest,
                    &e.values,
                    e.exact.as_deref(),
                    &with,
                )
            })
            .collect();
        Ok((set, linearized))
    }
}

impl Analysis {
    /// All equilibria with the model's values and their stability, with the linearized
    /// dynamics about each; computed once.
    ///
    /// # Errors
    /// As [`Analysis::equations`], or [`Error::Equilibria`] (constraints kept with
    /// multipliers, time-dependent rest equations, a missing value).
    pub fn equilibria(&self) -> Result<&Equilibria, Error> {
        self.equilibria
            .get_or_init(|| self.equilibria_with(&Search::default()))
            .as_ref()
            .map_err(Clone::clone)
    }

    /// [`Analysis::equilibria`] with steady motions or search ranges (not kept).
    ///
    /// # Errors
    /// As [`Analysis::equilibria`], or an unknown coordinate in a range.
    pub fn equilibria_with(&self, search: &Search) -> Result<Equilibria, Error> {
        self.limited("finding the equilibria", || {
            let prepared = self.prepare_equilibria(search)?;
            let (set, linearized) = prepared.at(&prepared.values)?;
            let at_poles = poles(&prepared, search, &set, &linearized);
            let pole_modes = chart_modes(&prepared, search, &set, &at_poles);
            let positive: Vec<String> = self
                .system()
                .parameters()
                .iter()
                .map(|(n, _)| n.clone())
                .collect();
            let (model, rest, values) = (&prepared.model, &prepared.rest, &prepared.values);
            let pole = |i: usize, positive: &dyn Fn(cas::Symbol) -> bool| {
                pole_condition(&prepared, search, (&set, &at_poles), i, positive)
            };
            let conditions = Conditions::of((model, rest, &set), values, &positive, &pole);
            Ok(Equilibria {
                rest: prepared.rest,
                set,
                linearized,
                inputs: prepared.inputs,
                at_poles,
                pole_modes,
                conditions,
            })
        })
    }

    /// Equilibria and their stability at `steps + 1` values of the parameter, input or
    /// steady rate `range.name` from `range.low` to `range.high` (one derivation for all).
    ///
    /// # Errors
    /// As [`Analysis::equilibria_with`], or an unknown name.
    pub fn equilibrium_sweep(
        &self,
        search: &Search,
        range: &Range,
        steps: usize,
    ) -> Result<EquilibriumSweep, Error> {
        self.limited("sweeping the equilibria", || {
            self.sweep_equilibria(search, range, steps)
        })
    }

    fn sweep_equilibria(
        &self,
        search: &Search,
        range: &Range,
        steps: usize,
    ) -> Result<EquilibriumSweep, Error> {
        let prepared = self.prepare_equilibria(search)?;
        if !prepared.known.contains(&range.name) {
            return Err(unknown(&range.name, &prepared.known));
        }
        let steps = steps.clamp(1, 10_000);
        let mut rows = Vec::with_capacity(steps + 1);
        for k in 0..=steps {
            let value = range.low + (range.high - range.low) * k as f64 / steps as f64;
            let mut values = prepared.values.clone();
            values.insert(range.name.clone(), value);
            let (set, linearized) = prepared.at(&values)?;
            rows.push(SweepStep {
                value,
                set,
                lin: linearized,
            });
        }
        Ok(EquilibriumSweep {
            rest: prepared.rest,
            parameter: range.name.clone(),
            steps: rows,
        })
    }

    fn prepare_equilibria(&self, search: &Search) -> Result<Prepared, Error> {
        if let Some((name, _)) = self.timed_inputs().first() {
            return Err(Error::NotAvailable(format!(
                "the input `{name}` is a function of time: equilibria hold the inputs constant"
            )));
        }
        let equations = self.equations()?;
        let spinning: Vec<String> = search.steady.iter().map(|(q, _)| q.clone()).collect();
        let rest = rest_equations_of(self.system(), equations, &spinning)?;
        let mut values: Values = self.values()?.into_iter().collect();
        let mut known: Vec<String> = values.keys().cloned().collect();
        known.extend(self.system().parameters().iter().map(|(n, _)| n.clone()));
        for (q, rate) in &search.steady {
            if let Some(symbol) = spin_rate(q).as_symbol() {
                values.insert(symbol.name().to_owned(), *rate);
                known.push(symbol.name().to_owned());
            }
        }
        known.sort();
        known.dedup();
        let mut bounds = vec![DEFAULT_RANGE; rest.coordinates.len()];
        for range in &search.ranges {
            let i = rest
                .coordinates
                .iter()
                .position(|q| *q == range.name)
                .ok_or_else(|| unknown(&range.name, &rest.coordinates))?;
            bounds[i] = (range.low, range.high);
        }
        let inputs: Vec<String> = self
            .system()
            .inputs()
            .iter()
            .map(|(n, _)| n.clone())
            .collect();
        let model = linear_model(equations, &rest, &inputs);
        Ok(Prepared {
            rest,
            model,
            inputs,
            bounds,
            values,
            known,
            geometry: (self.system().clone(), equations.clone()),
        })
    }
}

/// At each equilibrium whose linearization failed, the decision in a regular chart when it
/// sits at a pole of the coordinates (crate::chart).
fn poles(
    prepared: &Prepared,
    search: &Search,
    set: &EquilibriumSet,
    linearized: &[Result<Linearized, LinearizeError>],
) -> Vec<Option<AtPole>> {
    let (_, equations) = &prepared.geometry;
    let coordinates = equations.coordinates();
    let spinning: Vec<(usize, f64)> = search
        .steady
        .iter()
        .filter_map(|(q, rate)| Some((coordinates.iter().position(|c| c == q)?, *rate)))
        .collect();
    let at = |e: &mechanics::equilibria::Equilibrium| {
        if search.steady.is_empty() {
            let free = &prepared.rest.free;
            crate::chart::at_pole(equations, &e.values, free, &prepared.values).map(AtPole::Rest)
        } else {
            crate::chart::spin_at_pole(equations, &e.values, &spinning, &prepared.values)
                .map(AtPole::Spin)
        }
    };
    let zip = set.equilibria.iter().zip(linearized);
    zip.map(|(e, l)| l.as_ref().err().and_then(|_| at(e)))
        .collect()
}

/// The chart linearization at each rest state whose stability a pole's chart decided.
fn chart_modes(
    prepared: &Prepared,
    search: &Search,
    set: &EquilibriumSet,
    at_poles: &[Option<AtPole>],
) -> Vec<Option<ChartModes>> {
    let (_, equations) = &prepared.geometry;
    let values = &prepared.values;
    let zip = set.equilibria.iter().zip(at_poles);
    zip.map(|(e, pole)| {
        let at_rest = search.steady.is_empty() && matches!(pole, Some(AtPole::Rest(_)));
        at_rest
            .then(|| crate::chart_modes::pole_modes(equations, &e.values, values))
            .flatten()
    })
    .collect()
}

/// The condition in the parameters of the steady motion `i` at a pole, when the chart
/// decided it and found it isotropic (crate::chart::spin_condition_at_pole).
fn pole_condition(
    prepared: &Prepared,
    search: &Search,
    (set, at_poles): (&EquilibriumSet, &[Option<AtPole>]),
    i: usize,
    positive: &dyn Fn(cas::Symbol) -> bool,
) -> Option<mechanics::stability_condition::StabilityCondition> {
    let Some(Some(AtPole::Spin(spin))) = at_poles.get(i) else {
        return None;
    };
    spin.isotropic?;
    let e = set.equilibria.get(i)?;
    let exact = e.exact.as_deref()?;
    let (_, equations) = &prepared.geometry;
    let coordinates = equations.coordinates();
    let spinning: Vec<(usize, f64)> = search
        .steady
        .iter()
        .filter_map(|(q, rate)| Some((coordinates.iter().position(|c| c == q)?, *rate)))
        .collect();
    let values = &prepared.values;
    let point = (e.values.as_slice(), exact);
    crate::chart::spin_condition_at_pole(equations, point, &spinning, values, positive)
}

fn unknown(name: &str, known: &[String]) -> Error {
    AssignmentError::UnknownName {
        name: name.to_owned(),
        known: known.to_vec(),
    }
    .into()
}
