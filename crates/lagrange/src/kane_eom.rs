//! The equations of motion by Kane's method (`lagrange eom --method kane`): the generalized
//! speeds, the dependent rates eliminated, `Fr + Fr* = 0` per speed and the kinematic
//! differential equations, symbolic where the model is small enough, and compared with
//! Lagrange's equations where both apply. Over the size limit (the Whipple bicycle), the
//! reduced mass matrix and forcing at the initial state instead.

use mechanics::kane::{
    Agreement, KaneEquations, KaneError, KaneMotion, KaneSystem, Reduced, SpeedSplit,
};
use serde_json::{json, Value};

use crate::{cas, Analysis, Error};

/// How the equations of motion are derived.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Method {
    /// Lagrange's equations of the second kind, `M q̈ = f` (constraints by multipliers).
    #[default]
    Lagrange,
    /// Kane's method: generalized speeds, dependent speeds eliminated, `Fr + Fr* = 0`.
    Kane,
}

/// Kane's equations of a model.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub enum KaneEom {
    /// Symbolic, and how they compare with Lagrange's.
    Symbolic {
        /// The reduced equations.
        equations: Box<KaneEquations>,
        /// The comparison with Lagrange's equations, or why there is none.
        agreement: Result<Agreement, Error>,
    },
    /// Too large to print symbolically: the reduced equations at the initial state.
    Numeric {
        /// Why the symbolic form is not printed.
        why: KaneError,
        /// The coordinates.
        coordinates: Vec<String>,
        /// The speeds and dependent rates.
        split: SpeedSplit,
        /// The state: coordinates, then the speeds.
        configuration: Vec<f64>,
        /// The reduced equations there.
        reduced: Box<Reduced<f64>>,
    },
}

impl KaneEom {
    /// Whether Lagrange's equations, projected on the speeds, differ from Kane's: two
    /// derivations of one system that disagree are a bug of lagrange.
    #[must_use]
    pub fn disagrees(&self) -> bool {
        matches!(
            self,
            KaneEom::Symbolic {
                agreement: Ok(Agreement::Differs { .. }),
                ..
            }
        )
    }
}

impl Analysis {
    /// Kane's equations of the model (see [`KaneEom`]).
    ///
    /// # Errors
    /// As [`Analysis::kane_system`], or a singular constraint matrix at the sample or the
    /// initial state.
    pub fn kane_equations(&self) -> Result<KaneEom, Error> {
        let (system, values) = self.kane_system()?;
        let sample: Vec<f64> = (0..system.coordinates().len())
            .map(|k| 0.31 + 0.137 * ((k * 7 + 3) % 11) as f64)
            .collect();
        match system.symbolic(&sample, &values) {
            Ok(equations) => {
                let agreement = self.compare_with_lagrange(&equations);
                Ok(KaneEom::Symbolic {
                    equations: Box::new(equations),
                    agreement,
                })
            }
            Err(why @ (KaneError::TooLarge { .. } | KaneError::WorkLimit(_))) => {
                self.kane_at_initial_state(&system, &values, why)
            }
            Err(e) => Err(e.into()),
        }
    }

    /// Lagrange's equations projected on the speeds against Kane's; an error when Lagrange's
    /// route does not give them (its work limit) or eliminated coordinates.
    fn compare_with_lagrange(&self, kane: &KaneEquations) -> Result<Agreement, Error> {
        let lagrange = self.equations()?;
        if lagrange.coordinates() != kane.coordinates.as_slice() {
            return Err(Error::Kane(KaneError::Value(
                "Lagrange's equations eliminated coordinates: the two sets differ".to_string(),
            )));
        }
        let values = self.values()?;
        Ok(kane.agreement(lagrange.mass_matrix(), lagrange.forcing(), &values))
    }

    fn kane_at_initial_state(
        &self,
        system: &KaneSystem,
        values: &[f64],
        why: KaneError,
    ) -> Result<KaneEom, Error> {
        let coordinates = system.coordinates().to_vec();
        // The state a run starts from: the holonomically fixed coordinates on their
        // constraints, the rates the model gives kept and the others from the constraints
        // (a bicycle given only `x' = v` has its wheels spinning).
        let motion = self.steady_motion()?;
        let start = KaneMotion::new(system.clone(), values.to_vec(), &motion.configuration, 0.0)?;
        let state = start.initial_state(&motion.rates, 0.0)?;
        let q = start.configuration().to_vec();
        let split = start.split().clone();
        let u = state[start.free().len()..].to_vec();
        let reduced = system.reduced(&split, &q, &u, 0.0, values)?;
        Ok(KaneEom::Numeric {
            why,
            coordinates,
            split,
            configuration: q,
            reduced: Box::new(reduced),
        })
    }
}

/// The speeds' names as rates (`phi'`).
fn speed_names(coordinates: &[String], split: &SpeedSplit) -> Vec<String> {
    split
        .independent
        .iter()
        .map(|j| format!("{}'", coordinates[*j]))
        .collect()
}

/// Kane's equations as text.
#[must_use]
pub fn kane_text(eom: &KaneEom) -> String {
    match eom {
        KaneEom::Symbolic {
            equations,
            agreement,
        } => symbolic_text(equations, agreement),
        KaneEom::Numeric {
            why,
            coordinates,
            split,
            configuration,
            reduced,
        } => numeric_text(why, coordinates, split, configuration, reduced),
    }
}

fn header(coordinates: &[String], split: &SpeedSplit) -> String {
    let p = split.independent.len();
    let mut out = format!(
        "equations of motion by Kane's method: {} coordinate{}, {} independent constraint row{}, {p} generalized speed{}\n",
        coordinates.len(),
        if coordinates.len() == 1 { "" } else { "s" },
        split.rows.len(),
        if split.rows.len() == 1 { "" } else { "s" },
        if p == 1 { "" } else { "s" },
    );
    let speeds: Vec<String> = speed_names(coordinates, split)
        .iter()
        .enumerate()
        .map(|(k, s)| format!("u{} = {s}", k + 1))
        .collect();
    out.push_str(&format!("generalized speeds: {}\n", speeds.join(", ")));
    out
}

fn symbolic_text(eq: &KaneEquations, agreement: &Result<Agreement, Error>) -> String {
    let mut out = header(&eq.coordinates, &eq.split);
    if !eq.split.dependent.is_empty() {
        out.push_str("dependent rates, eliminated (kinematic differential equations):\n");
        let mut dependent = eq.split.dependent.clone();
        dependent.sort_unstable();
        for d in &dependent {
            let rate = cas::Expr::rate(&eq.coordinates[*d], 1);
            out.push_str(&format!(
                "  {} = {}\n",
                cas::print::to_unicode(rate),
                cas::print::to_unicode(eq.rates[*d])
            ));
        }
    }
    out.push_str("Fr + Fr* = 0, one equation per speed (M_r u̇ = f_r):\n");
    for (i, j) in eq.split.independent.iter().enumerate() {
        let lhs = cas::Expr::add_all(
            eq.split
                .independent
                .iter()
                .enumerate()
                .map(|(k, jk)| eq.mass[i][k] * cas::Expr::rate(&eq.coordinates[*jk], 2)),
        );
        out.push_str(&format!(
            "  [{}]  {} = {}\n",
            eq.coordinates[*j],
            cas::print::to_unicode(lhs),
            cas::print::to_unicode(eq.forcing[i])
        ));
    }
    out.push_str(&agreement_line(agreement));
    out
}

fn agreement_line(agreement: &Result<Agreement, Error>) -> String {
    match agreement {
        Ok(Agreement::Exact) => {
            "Lagrange's equations projected on the speeds: equal, exactly\n".to_string()
        }
        Ok(Agreement::AtStates { states, largest }) => format!(
            "Lagrange's equations projected on the speeds: equal at {states} sample states (largest relative difference {largest:.1e}; the exact comparison passed the work limits)\n"
        ),
        Ok(Agreement::Differs { part, row }) => format!(
            "Lagrange's equations projected on the speeds: DIFFER in the {part}, equation {} (a bug of lagrange)\n",
            row + 1
        ),
        Ok(_) => String::new(),
        Err(e) => format!("Lagrange's equations: not compared ({e})\n"),
    }
}

fn numeric_text(
    why: &KaneError,
    coordinates: &[String],
    split: &SpeedSplit,
    configuration: &[f64],
    reduced: &Reduced<f64>,
) -> String {
    let mut out = header(coordinates, split);
    out.push_str(&format!(
        "not printed symbolically: {why}.\nThe reduced equations M_r u̇ = f_r at the initial state instead (`lagrange linearize` linearizes about a steady motion):\n"
    ));
    let state: Vec<String> = coordinates
        .iter()
        .zip(configuration)
        .map(|(c, v)| format!("{c} = {}", v + 0.0))
        .collect();
    out.push_str(&format!("  at {}\n", state.join(", ")));
    let rates: Vec<String> = coordinates
        .iter()
        .zip(&reduced.rates)
        .map(|(c, v)| format!("{c}' = {}", v + 0.0))
        .collect();
    out.push_str(&format!("  rates {}\n", rates.join(", ")));
    out.push_str("  M_r =\n");
    for row in &reduced.mass {
        let cells: Vec<String> = row.iter().map(|x| format!("{x:>14.6e}")).collect();
        out.push_str(&format!("    [{}]\n", cells.join(" ")));
    }
    let f: Vec<String> = reduced.forcing.iter().map(|x| format!("{x:.6e}")).collect();
    out.push_str(&format!("  f_r = [{}]\n", f.join(", ")));
    out
}

/// Kane's equations as JSON (docs/json.md, "Kane's method"): expressions in SymPy syntax.
#[must_use]
pub fn kane_json(eom: &KaneEom) -> Value {
    let sympy = |e: &cas::Expr| cas::print::to_sympy(*e);
    match eom {
        KaneEom::Symbolic {
            equations: eq,
            agreement,
        } => json!({
            "schema": 1,
            "method": "kane",
            "coordinates": eq.coordinates,
            "speeds": speed_names(&eq.coordinates, &eq.split),
            "dependent": eq.split.dependent.iter().map(|d| json!({
                "rate": format!("{}_d", eq.coordinates[*d]),
                "equals": sympy(&eq.rates[*d]),
            })).collect::<Vec<_>>(),
            "mass_matrix": eq.mass.iter().map(|r| r.iter().map(sympy).collect::<Vec<_>>()).collect::<Vec<_>>(),
            "forcing": eq.forcing.iter().map(sympy).collect::<Vec<_>>(),
            "lagrange_agreement": agreement_json(agreement),
        }),
        KaneEom::Numeric {
            why,
            coordinates,
            split,
            configuration,
            reduced,
        } => json!({
            "schema": 1,
            "method": "kane",
            "coordinates": coordinates,
            "speeds": speed_names(coordinates, split),
            "symbolic": why.to_string(),
            "at": configuration,
            "rates": reduced.rates,
            "mass_matrix": reduced.mass,
            "forcing": reduced.forcing,
        }),
    }
}

fn agreement_json(agreement: &Result<Agreement, Error>) -> Value {
    match agreement {
        Ok(Agreement::Exact) => json!({ "result": "exact" }),
        Ok(Agreement::AtStates { states, largest }) => {
            json!({ "result": "at_states", "states": states, "largest": largest })
        }
        Ok(Agreement::Differs { part, row }) => {
            json!({ "result": "differ", "part": part, "equation": row })
        }
        Ok(_) => Value::Null,
        Err(e) => json!({ "result": "not_compared", "why": e.to_string() }),
    }
}
