//! Reactions projected where the model asks (`reaction NAME: … in frame R`, `… along n`): the
//! computed inertial components of the force dotted with the frame's unit vectors or with the
//! unit direction — a rod's tension along the rod, a contact force in the body's frame — and
//! their values at the equilibria the model has.
//!
//! The reactions themselves are not touched (`mechanics::reactions` finds them in inertial
//! components); this is a change of basis for the report, exact in the symbolic core.

use cas::{Expr, Symbol, SymbolKind};
use mechanics::Vector;

use crate::analysis::located;
use crate::{Analysis, Error};

/// A reaction's force projected on the axes the model named.
#[derive(Clone, Debug)]
pub struct ProjectedReaction {
    /// The reaction's name.
    pub name: String,
    /// What it is projected on: `frame B`, or the direction as written (`A - B`).
    pub onto: String,
    /// Each axis's label (`B.x`, `along`) and the component `R · e`, in normal form.
    pub components: Vec<(String, Expr)>,
    /// At each equilibrium (in the order of [`Analysis::equilibria`]), the components' values
    /// (`None` where they do not evaluate).
    pub at_equilibria: Vec<Option<Vec<f64>>>,
}

impl Analysis {
    /// The projections the model's `reaction` statements ask for, of the reactions computed by
    /// [`Analysis::reactions`]; empty when none is asked for.
    ///
    /// # Errors
    /// As [`Analysis::reactions`], and a model error when a direction cannot be lowered.
    pub fn projected_reactions(&self) -> Result<Vec<ProjectedReaction>, Error> {
        let Some(source) = self.source() else {
            return Ok(Vec::new());
        };
        let asked =
            model::reaction_projections(&source.model).map_err(|e| located(&source.text, &e))?;
        if asked.is_empty() {
            return Ok(Vec::new());
        }
        let Some(reactions) = self.reactions()? else {
            return Ok(Vec::new());
        };
        let mut out = Vec::new();
        for projection in asked {
            let Some(force) = reactions
                .reactions
                .iter()
                .find(|r| r.name == projection.name)
                .and_then(|r| r.force)
            else {
                continue;
            };
            let positive = self.positive_parameters();
            let components: Vec<(String, Expr)> = projection
                .axes
                .iter()
                .map(|(label, axis)| {
                    let length = length(axis, &|s| positive.iter().any(|p| p == s.name()));
                    (label.clone(), (dot(&force, axis) / length).normal())
                })
                .collect();
            let at_equilibria = self.at_equilibria(&components);
            out.push(ProjectedReaction {
                name: projection.name,
                onto: projection.onto,
                components,
                at_equilibria,
            });
        }
        Ok(out)
    }

    /// The parameters whose values are positive: a length `√(ℓ²)` is `ℓ` when they are.
    pub(crate) fn positive_parameters(&self) -> Vec<String> {
        let Ok(values) = self.values() else {
            return Vec::new();
        };
        self.system()
            .parameters()
            .iter()
            .filter(|(name, _)| values.iter().any(|(n, v)| n == name && *v > 0.0))
            .map(|(name, _)| name.clone())
            .collect()
    }

    /// The components' values at each equilibrium (rates zero, inputs at their values); none
    /// when the equilibria are not known or a value does not evaluate.
    fn at_equilibria(&self, components: &[(String, Expr)]) -> Vec<Option<Vec<f64>>> {
        let (Ok(equilibria), Ok(values)) = (self.equilibria(), self.values()) else {
            return Vec::new();
        };
        let coordinates = &equilibria.rest.coordinates;
        equilibria
            .set
            .equilibria
            .iter()
            .map(|e| {
                let env = |s: Symbol| match s.kind() {
                    SymbolKind::TimeFunction { order: 0 } => coordinates
                        .iter()
                        .position(|q| q == s.name())
                        .and_then(|k| e.values.get(k).copied()),
                    SymbolKind::TimeFunction { .. } => Some(0.0),
                    _ => values.iter().find(|(n, _)| n == s.name()).map(|(_, v)| *v),
                };
                components
                    .iter()
                    .map(|(_, c)| c.eval(&env).ok())
                    .collect::<Option<Vec<f64>>>()
            })
            .collect()
    }
}

/// `|v|`: `√(v · v)`, taken exactly when `v · v` is a square of positive symbols and a
/// square number (`ℓ² sin² θ + ℓ² cos² θ` → `ℓ`).
fn length(v: &Vector, positive: &dyn Fn(Symbol) -> bool) -> Expr {
    let squared = dot(v, v);
    report::document::positive_root(squared, positive).unwrap_or_else(|| squared.sqrt())
}

/// `a · b`, in normal form.
fn dot(a: &Vector, b: &Vector) -> Expr {
    (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]).normal()
}
