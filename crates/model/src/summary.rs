//! The summary `lagrange check MODEL` prints: degrees of freedom, coordinates, bodies, loads
//! and constraints, as data with a `Display` impl.

use std::fmt;

use crate::model::{Connection, Constraint, ConstraintKind, Load, Model, ReactionTarget};

/// What a checked model contains, for people.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct Summary {
    /// Free coordinates minus the independent constraint rows (saturating at zero), as
    /// `lagrange solve` counts them: a 3-D rolling contact is one statement with two or three
    /// rows, and rows that restate others do not count.
    pub degrees_of_freedom: usize,
    /// The independent constraint rows (the rank of the constraint matrix at a generic
    /// state; the number of constraint statements when the model cannot be lowered).
    pub constraint_rows: usize,
    /// The free coordinates.
    pub coordinates: Vec<String>,
    /// The time-driven coordinates, with their motion.
    pub driven: Vec<String>,
    /// Particles (`particle at A, mass m_A`) and bodies (`body disc, mass m`).
    pub bodies: Vec<String>,
    /// Loads, one line each (`spring`, `force at A`, …).
    pub loads: Vec<String>,
    /// Constraints, one line each, with their kind.
    pub constraints: Vec<String>,
    /// Holonomic constraints (they eliminate coordinates).
    pub holonomic_constraints: usize,
    /// Other (velocity) constraints.
    pub velocity_constraints: usize,
    /// Reactions asked for.
    pub reactions: Vec<String>,
}

impl Model {
    /// Summarize the model for `lagrange check`.
    #[must_use]
    pub fn summary(&self) -> Summary {
        let holonomic = self.constraints.iter().filter(|c| c.is_holonomic()).count();
        let free: Vec<String> = self
            .free_coordinates()
            .map(|(_, c)| c.name.name.clone())
            .collect();
        let driven = self
            .coordinates
            .iter()
            .filter_map(|c| {
                c.driven
                    .as_ref()
                    .map(|motion| format!("{} = {}", c.name.name, self.display(motion)))
            })
            .collect();
        let loads = self
            .loads
            .iter()
            .map(|item| self.describe_load(&item.load))
            .collect();
        let constraints = self
            .constraints
            .iter()
            .map(|c| self.describe_constraint(c))
            .collect();
        // As `solve` counts them (`Equations::degrees_of_freedom`): the independent virtual
        // displacements, so a velocity constraint takes one away too, and a contact with
        // several rows as many as are independent (the rank, from the lowered system's graph).
        let constraint_rows = crate::lower::lower(self)
            .ok()
            .and_then(|system| mechanics::kane::constraint_rank(&system))
            .unwrap_or(self.constraints.len());
        Summary {
            degrees_of_freedom: free.len().saturating_sub(constraint_rows),
            constraint_rows,
            coordinates: free,
            driven,
            bodies: self.describe_bodies(),
            loads,
            constraints,
            holonomic_constraints: holonomic,
            velocity_constraints: self.constraints.len() - holonomic,
            reactions: self.describe_reactions(),
        }
    }

    /// The particles, then the bodies, one line each.
    fn describe_bodies(&self) -> Vec<String> {
        let mut bodies: Vec<String> = self
            .particles
            .iter()
            .map(|p| {
                format!(
                    "particle at {}, mass {}",
                    self.point(p.point).name.name,
                    self.display(&p.mass)
                )
            })
            .collect();
        bodies.extend(self.bodies.iter().map(|b| {
            format!(
                "body {}, mass {}, centre {}, frame {}",
                b.name.name,
                self.display(&b.mass),
                self.point(b.centre).name.name,
                self.frame(b.frame).name.name
            )
        }));
        bodies
    }

    /// One constraint's line: its name, if any, its kind and its equation.
    fn describe_constraint(&self, c: &Constraint) -> String {
        let name = c
            .name
            .as_ref()
            .map_or_else(String::new, |n| format!("{}: ", n.name));
        let what = match &c.kind {
            ConstraintKind::Holonomic { lhs, rhs } => {
                format!("holonomic, {} = {}", self.display(lhs), self.display(rhs))
            }
            ConstraintKind::Velocity { lhs, rhs } => {
                format!("velocity, {} = {}", self.display(lhs), self.display(rhs))
            }
            ConstraintKind::Rolling { body, contact } => format!(
                "rolling, {} at {}",
                self.body(*body).name.name,
                self.point(*contact).name.name
            ),
            ConstraintKind::Gear {
                driver,
                driven,
                ratio,
            } => format!(
                "gear, {}' = ({})·{}'",
                self.coordinate(*driven).name.name,
                self.display(ratio),
                self.coordinate(*driver).name.name
            ),
        };
        format!("{name}{what}")
    }

    /// The reactions asked for, then the releases.
    fn describe_reactions(&self) -> Vec<String> {
        self.reactions
            .iter()
            .map(|r| match r {
                ReactionTarget::Constraint(id) => {
                    let c = self.constraint(*id);
                    c.name
                        .as_ref()
                        .map_or_else(|| "(unnamed)".to_string(), |n| n.name.clone())
                }
                ReactionTarget::Driven(id) => {
                    format!("driving force of {}", self.coordinate(*id).name.name)
                }
            })
            .chain(self.releases.iter().map(|r| {
                let word = match r.word {
                    crate::ast::ReleaseWord::Hinge => "hinge",
                    crate::ast::ReleaseWord::Contact => "contact",
                    crate::ast::ReleaseWord::Rope => "rope",
                    crate::ast::ReleaseWord::Clamp => "clamp",
                    crate::ast::ReleaseWord::Rolling => "rolling",
                };
                format!(
                    "{} ({word} at {})",
                    r.name.name,
                    self.point(r.point).name.name
                )
            }))
            .collect()
    }

    fn describe_load(&self, load: &Load) -> String {
        let connection = |c: &Connection| match c {
            Connection::Points { from, to } => {
                format!("from {} to {}", self.display(from), self.display(to))
            }
            Connection::Scalar(value) => format!("on {}", self.display(value)),
        };
        match load {
            Load::Gravity(g) => format!("gravity {}", self.display(g)),
            Load::Spring {
                stiffness,
                connection: c,
                rest,
            } => {
                let rest = rest
                    .as_ref()
                    .map_or_else(String::new, |r| format!(", rest {}", self.display(r)));
                format!("spring {} {}{rest}", self.display(stiffness), connection(c))
            }
            Load::Damper {
                coefficient,
                connection: c,
            } => {
                format!("damper {} {}", self.display(coefficient), connection(c))
            }
            Load::Dissipation(d) => format!("dissipation {}", self.display(d)),
            Load::Potential(v) => format!("potential {}", self.display(v)),
            Load::Force { force, point } => {
                format!("force {} at {}", self.display(force), self.display(point))
            }
            Load::Couple { moment, body } => format!(
                "couple {} on {}",
                self.display(moment),
                self.body(*body).name.name
            ),
            Load::GeneralizedForce { force, coordinate } => {
                format!(
                    "generalized force {} on {}",
                    self.display(force),
                    self.coordinate(*coordinate).name.name
                )
            }
        }
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fn list(f: &mut fmt::Formatter<'_>, title: &str, items: &[String]) -> fmt::Result {
            if items.is_empty() {
                return writeln!(f, "{title}: none");
            }
            writeln!(f, "{title}:")?;
            items.iter().try_for_each(|item| writeln!(f, "  {item}"))
        }
        let plural = |n: usize| if n == 1 { "" } else { "s" };
        let velocity = if self.velocity_constraints > 0 {
            format!(
                " − {} velocity constraint{}",
                self.velocity_constraints,
                plural(self.velocity_constraints)
            )
        } else {
            String::new()
        };
        let statements = self.holonomic_constraints + self.velocity_constraints;
        // The rows are named only where they differ from the statements (a 3-D contact).
        let rows = if self.constraint_rows == statements {
            String::new()
        } else {
            format!(
                ", {} independent constraint row{} in all",
                self.constraint_rows,
                plural(self.constraint_rows)
            )
        };
        writeln!(
            f,
            "degrees of freedom: {} ({} coordinate{} − {} holonomic constraint{}{velocity}{rows})",
            self.degrees_of_freedom,
            self.coordinates.len(),
            plural(self.coordinates.len()),
            self.holonomic_constraints,
            plural(self.holonomic_constraints),
        )?;
        writeln!(
            f,
            "coordinates: {}",
            if self.coordinates.is_empty() {
                "none".to_string()
            } else {
                self.coordinates.join(", ")
            }
        )?;
        if !self.driven.is_empty() {
            list(f, "driven coordinates", &self.driven)?;
        }
        list(f, "bodies", &self.bodies)?;
        list(f, "forces", &self.loads)?;
        list(f, "constraints", &self.constraints)?;
        if !self.reactions.is_empty() {
            writeln!(f, "reactions: {}", self.reactions.join(", "))?;
        }
        Ok(())
    }
}
