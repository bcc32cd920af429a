//! `lagrange eom MODEL`: Lagrange's equations of motion, for people or as JSON.

use std::path::Path;
use std::process::ExitCode;

use cas::print::to_unicode;
use report::document::Notation;

use crate::args::EomFormat;

/// Derives and prints the equations of motion of a model file.
pub fn run(path: &Path, format: EomFormat, set: &[String]) -> anyhow::Result<ExitCode> {
    let (model, _source) = match super::check::load_with_overrides(path, set)? {
        Ok(loaded) => loaded,
        Err(code) => return Ok(code),
    };
    let (system, equations) = match super::check::derive(path, &model)? {
        Ok(derived) => derived,
        Err(code) => return Ok(code),
    };
    match format {
        EomFormat::Json => {
            let value = report::eom_json(&system, &equations);
            println!("{}", serde_json::to_string_pretty(&value)?);
        }
        EomFormat::Text => {
            // The model's constants by name, denominators spread, as in `solve`.
            let notation = Notation::of(&system);
            let shown = |e: cas::Expr| notation.math(e).unicode;
            for e in equations.eliminated() {
                println!(
                    "{} eliminated by constraint `{}`: {} = {}",
                    e.coordinate,
                    e.constraint,
                    e.coordinate,
                    to_unicode(e.value)
                );
            }
            println!("K = {}", shown(equations.kinetic_energy()));
            println!("V = {}", shown(equations.potential_energy()));
            println!();
            // M q̈ + Aᵀλ = f is printed as d/dt ∂L/∂q̇ − ∂L/∂q = Q − Σ λ_i A_ij.
            let multipliers: Vec<cas::Expr> = (1..=equations.constraint_names().len())
                .map(|i| cas::Expr::symbol(&format!("lambda{i}")))
                .collect();
            for (j, (lhs, q)) in equations
                .lagrange_lhs()
                .iter()
                .zip(equations.generalized_forces())
                .enumerate()
            {
                let reactions = equations
                    .constraint_matrix()
                    .iter()
                    .zip(&multipliers)
                    .filter_map(|(row, lambda)| row.get(j).map(|a| *lambda * *a))
                    .sum::<cas::Expr>();
                println!("{} = {}", shown(*lhs), shown(*q - reactions));
            }
            for (name, ((row, b), lambda)) in equations.constraint_names().iter().zip(
                equations
                    .constraint_matrix()
                    .iter()
                    .zip(equations.constraint_rhs())
                    .zip(&multipliers),
            ) {
                let lhs = row
                    .iter()
                    .zip(equations.coordinates())
                    .map(|(a, q)| *a * cas::Expr::rate(q, 2))
                    .sum::<cas::Expr>();
                println!(
                    "constraint `{name}` ({}): {} = {}",
                    to_unicode(*lambda),
                    to_unicode(lhs),
                    to_unicode(*b)
                );
            }
            if let Some(accelerations) = equations.accelerations() {
                println!();
                println!("solved for the accelerations:");
                for (j, (q, a)) in equations
                    .coordinates()
                    .iter()
                    .zip(accelerations)
                    .enumerate()
                {
                    println!(
                        "  {} = {}",
                        to_unicode(cas::Expr::rate(q, 2)),
                        report::solution::acceleration(&equations, &notation, j, *a).unicode
                    );
                }
            }
            if !equations.first_integrals().is_empty() {
                println!();
            }
            for f in equations.first_integrals() {
                let condition = report::solution::conditions_text(f)
                    .map(|c| format!(" while {c}"))
                    .unwrap_or_default();
                match &f.coordinate {
                    Some(q) => println!("conserved{condition}: p_{q} = {}", shown(f.value)),
                    None => println!("conserved ({}){condition}: h = {}", f.kind, shown(f.value)),
                }
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}
