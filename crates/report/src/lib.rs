//! Report writers. For now: the JSON rendering of Lagrange's equations, [`eom_json`]
//! (schema in `docs/json.md`, `"schema": 1`).
#![warn(missing_docs)]

pub mod accelerations;
pub mod document;
pub mod reaction_working;
mod reactions;
pub mod solution;
pub mod solution_equilibria;
pub mod solution_kane;
pub mod solution_reactions;
pub mod solution_simulation;

pub use eom_text::eom_text;
pub use reactions::{reaction_text, reactions_json, UnilateralReport};
mod bifurcation;
mod eom_text;
mod plot;

pub use bifurcation::{plot_bifurcation, BifurcationPoint};
pub use plot::{
    plot_run, plot_run_with, plot_run_with_reactions, OutputSeries, PlotError, PlotExtras,
};

use cas::print::to_sympy;
use mechanics::{Equations, System};
use serde_json::{json, Value};

pub mod equilibria;
pub mod floquet;

/// The JSON schema version written by [`eom_json`].
pub const SCHEMA: u32 = 1;

/// The equations of motion as JSON: every expression in SymPy syntax, rates `q_d`,
/// accelerations `q_dd`; `M q_dd = forcing` (with `− Aᵀλ` when `constraints` is not empty).
#[must_use]
pub fn eom_json(system: &System, equations: &Equations) -> Value {
    let s = |e: &cas::Expr| Value::String(to_sympy(*e));
    let rows = |m: &[Vec<cas::Expr>]| -> Value {
        m.iter()
            .map(|row| row.iter().map(s).collect::<Vec<_>>())
            .collect()
    };
    let parameters: Vec<Value> = system
        .parameters()
        .iter()
        .map(|(name, value)| json!({ "name": name, "value": value.as_ref().map(s) }))
        .collect();
    let first_integrals: Vec<Value> = equations
        .first_integrals()
        .iter()
        .map(|f| {
            let conditions: Vec<Value> = f.conditions.iter().map(s).collect();
            json!({ "kind": f.kind, "coordinate": f.coordinate, "value": s(&f.value), "conditions": conditions })
        })
        .collect();
    let eliminated: Vec<Value> = equations
        .eliminated()
        .iter()
        .map(|e| json!({ "coordinate": e.coordinate, "constraint": e.constraint, "value": s(&e.value) }))
        .collect();
    let explicit = accelerations::explicit(equations);
    let constraints: Vec<Value> = equations
        .constraint_names()
        .iter()
        .zip(equations.constraint_matrix())
        .zip(equations.constraint_rhs())
        .map(|((name, row), rhs)| {
            json!({ "name": name, "row": row.iter().map(s).collect::<Vec<_>>(), "rhs": s(rhs) })
        })
        .collect();
    json!({
        "schema": SCHEMA,
        "coordinates": equations.coordinates(),
        "driven": system.driven().iter().map(|(n, f)| json!({ "name": n, "motion": s(f) })).collect::<Vec<_>>(),
        "parameters": parameters,
        "kinetic_energy": s(&equations.kinetic_energy()),
        "potential_energy": s(&equations.potential_energy()),
        "lagrangian": s(&equations.lagrangian()),
        "generalized_forces": equations.generalized_forces().iter().map(s).collect::<Vec<_>>(),
        "mass_matrix": rows(equations.mass_matrix()),
        "forcing": equations.forcing().iter().map(s).collect::<Vec<_>>(),
        "accelerations": explicit.accelerations.as_ref().map(|a| a.iter().map(s).collect::<Vec<_>>()),
        "acceleration_form": explicit.form.as_ref().map(|f| json!({
            "determinant": s(&f.determinant),
            "adjugate": rows(&f.adjugate),
        })),
        "accelerations_note": explicit.note,
        "eliminated": eliminated,
        "constraints": constraints,
        "first_integrals": first_integrals,
    })
}
