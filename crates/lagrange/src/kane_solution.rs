//! The solution of a nonholonomic system by Kane's method (issue 18), for models whose
//! equations with multipliers are over the symbolic work limits (the Whipple bicycle), where
//! the Lagrange route would spend seconds finding that out: the system, the generalized
//! speeds, the reduced equations (symbolic under the printing limit, else their values at
//! the initial state), the steady motion's linearization with its canonical form, and the
//! model's own simulation. Which route is taken is [`Analysis::simulation_method`]'s choice.

use report::document::{Document, Equation, Notation, Section};
use report::solution_kane::{
    reduced_numeric_section, reduced_symbolic_section, speeds_section, steady_section,
    system_section, Canonical, ReducedAt, Speeds, SteadyPart,
};

use crate::kane_eom::KaneEom;
use crate::solve::{Figures, Solution};
use crate::{cas, Analysis, Error};

impl Analysis {
    /// The solution by Kane's method (see the module's documentation).
    ///
    /// # Errors
    /// As [`Analysis::kane_equations`]: without the reduced equations there is no solution.
    /// The later parts say in the document why they are missing.
    pub(crate) fn kane_solution(&self, figures: Option<&Figures>) -> Result<Solution, Error> {
        let system = self.system();
        let notation = Notation::of(system);
        let eom = self.kane_equations()?;
        let mut document = Document {
            title: self.title(),
            sections: vec![self.kane_system_section(&eom, &notation)],
        };
        if let (Some(figures), Some(section)) = (figures, document.sections.first_mut()) {
            self.figure_part(figures, section);
        }
        let holonomic = self.kane_system().map_or(0, |(k, _)| k.holonomic_count());
        document
            .sections
            .push(kane_speeds(&eom, holonomic, &notation));
        document.sections.push(reduced(&eom, &notation));
        if self.describes_steady_motion() {
            document.sections.push(self.steady_part(&notation));
        }
        if self
            .source()
            .is_some_and(|s| s.model.simulation().is_some())
        {
            document.sections.push(self.simulation_part(figures));
        }
        document.sections.splice(0..0, self.prose_sections());
        Ok(Solution {
            document,
            disagree: false,
        })
    }

    /// The JSON of a solution by Kane's method: Kane's equations (docs/json.md, "Kane's
    /// method") with the document under `report`.
    pub(crate) fn kane_solution_json(
        &self,
        solution: &Solution,
    ) -> Result<serde_json::Value, Error> {
        let mut value = crate::kane_json(&self.kane_equations()?);
        if let Some(object) = value.as_object_mut() {
            object.insert("report".into(), solution.document.to_json());
        }
        Ok(value)
    }

    fn kane_system_section(&self, eom: &KaneEom, notation: &Notation) -> Section {
        let n = self.system().coordinates().len();
        let limit = match eom {
            KaneEom::Numeric { why, .. } => {
                format!(", which are themselves over the size limits for a symbolic form ({why})")
            }
            _ => String::new(),
        };
        let why = format!(
            "Solved by Kane's method: Lagrange's equations with multipliers in all {n} \
             coordinates are larger than Kane's reduced equations{limit}, so Lagrange's \
             route would pass the symbolic core's work limits."
        );
        let summary = self.source().map(|s| s.model.summary());
        let dof = summary.as_ref().map_or_else(
            || "not counted".to_string(),
            |s| {
                let line = s.to_string();
                let first = line.lines().next().unwrap_or_default();
                first
                    .strip_prefix("degrees of freedom: ")
                    .unwrap_or(first)
                    .to_string()
            },
        );
        let constraints = summary.map(|s| s.constraints).unwrap_or_default();
        system_section(&why, &dof, self.system(), &constraints, notation)
    }

    /// The steady motion's linearization, with the canonical form when one parameter sets
    /// the steady rates; why not, when it cannot be found.
    fn steady_part(&self, notation: &Notation) -> Section {
        let lin = match self.steady_linearization() {
            Ok(lin) => lin,
            Err(why) => {
                let mut s = Section::new("Steady motion and its stability", 2);
                s.paragraph(format!("Not linearized: {why}."));
                return s;
            }
        };
        let canonical = self
            .steady_speed_parameter()
            .and_then(|v| self.canonical_form(&v).ok());
        let coordinates = self.system().coordinates();
        let rates: Vec<(String, f64)> = coordinates
            .iter()
            .zip(&lin.rates)
            .filter(|(_, r)| r.abs() > 0.0)
            .map(|(q, r)| (q.clone(), *r))
            .collect();
        let part = SteadyPart {
            rates: &rates,
            states: &lin.states,
            eigenvalues: &lin.eigenvalues,
            stable: crate::steady_print::is_stable(&lin),
            canonical: canonical.as_ref().map(|c| Canonical {
                speed: &c.speed,
                coordinates: &c.coordinates,
                matrices: [&c.mass, &c.c1, &c.k0, &c.k2],
            }),
        };
        steady_section(&part, notation)
    }
}

/// The speeds of Kane's equations, the dependent rates and the holonomically fixed
/// coordinates (the dependent ones whose row is a holonomic constraint's).
fn kane_speeds(eom: &KaneEom, holonomic_rows: usize, notation: &Notation) -> Section {
    let (coordinates, split) = match eom {
        KaneEom::Symbolic { equations, .. } => (&equations.coordinates, &equations.split),
        KaneEom::Numeric {
            coordinates, split, ..
        } => (coordinates, split),
    };
    let names = |idx: &[usize]| -> Vec<String> {
        let mut sorted = idx.to_vec();
        sorted.sort_unstable();
        sorted.iter().map(|k| coordinates[*k].clone()).collect()
    };
    let independent: Vec<String> = (split.independent.iter())
        .map(|k| coordinates[*k].clone())
        .collect();
    let fixed: Vec<usize> = (split.rows.iter().zip(&split.dependent))
        .filter(|(r, _)| **r < holonomic_rows)
        .map(|(_, c)| *c)
        .collect();
    let rolling: Vec<usize> = (split.dependent.iter())
        .copied()
        .filter(|c| !fixed.contains(c))
        .collect();
    speeds_section(
        &Speeds {
            independent: &independent,
            dependent: &names(&rolling),
            holonomic: &names(&fixed),
        },
        notation,
    )
}

/// The reduced equations: symbolic, or their values at the initial state.
fn reduced(eom: &KaneEom, notation: &Notation) -> Section {
    match eom {
        KaneEom::Symbolic { equations: eq, .. } => {
            let lines = (eq.split.independent.iter().enumerate())
                .map(|(i, _)| {
                    let lhs =
                        cas::Expr::add_all(eq.split.independent.iter().enumerate().map(
                            |(k, jk)| eq.mass[i][k] * cas::Expr::rate(&eq.coordinates[*jk], 2),
                        ));
                    Equation::new(notation.math(lhs), notation.math(eq.forcing[i]))
                })
                .collect();
            reduced_symbolic_section(lines)
        }
        KaneEom::Numeric {
            why,
            coordinates,
            configuration,
            reduced,
            ..
        } => {
            let at: Vec<(String, f64)> = coordinates
                .iter()
                .cloned()
                .zip(configuration.iter().copied())
                .collect();
            let rates: Vec<(String, f64)> = coordinates
                .iter()
                .cloned()
                .zip(reduced.rates.iter().copied())
                .collect();
            reduced_numeric_section(
                &ReducedAt {
                    why: why.to_string(),
                    configuration: &at,
                    rates: &rates,
                    mass: &reduced.mass,
                    forcing: &reduced.forcing,
                },
                notation,
            )
        }
    }
}
