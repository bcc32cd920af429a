//! `lagrange eom MODEL`: Lagrange's equations of motion, for people or as JSON.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;
use cas::print::to_unicode;

use crate::args::EomFormat;

/// Derives and prints the equations of motion of a model file.
pub fn run(path: &Path, format: EomFormat) -> anyhow::Result<ExitCode> {
    let (model, _source) = match super::check::load(path)? {
        Ok(loaded) => loaded,
        Err(code) => return Ok(code),
    };
    let system = model::lower(&model).context("cannot lower the model")?;
    let equations = match mechanics::derive(&system) {
        Ok(eq) => eq,
        Err(error) => {
            eprintln!("error: {error}");
            return Ok(ExitCode::from(1));
        }
    };
    match format {
        EomFormat::Json => {
            let value = report::eom_json(&system, &equations);
            println!("{}", serde_json::to_string_pretty(&value)?);
        }
        EomFormat::Text => {
            for e in equations.eliminated() {
                println!(
                    "{} eliminated by constraint `{}`: {} = {}",
                    e.coordinate,
                    e.constraint,
                    e.coordinate,
                    to_unicode(e.value)
                );
            }
            println!("K = {}", to_unicode(equations.kinetic_energy()));
            println!("V = {}", to_unicode(equations.potential_energy()));
            println!();
            let lambdas = !equations.constraint_names().is_empty();
            for (j, (lhs, q)) in equations
                .lagrange_lhs()
                .iter()
                .zip(equations.generalized_forces())
                .enumerate()
            {
                let mut rhs = to_unicode(*q);
                if lambdas {
                    for (i, row) in equations.constraint_matrix().iter().enumerate() {
                        if let Some(a) = row.get(j).filter(|a| !a.is_zero()) {
                            rhs.push_str(&format!(" − λ{} ({})", i + 1, to_unicode(*a)));
                        }
                    }
                }
                println!("{} = {}", to_unicode(*lhs), rhs);
            }
            for (i, (name, (row, b))) in equations
                .constraint_names()
                .iter()
                .zip(
                    equations
                        .constraint_matrix()
                        .iter()
                        .zip(equations.constraint_rhs()),
                )
                .enumerate()
            {
                let terms: Vec<String> = row
                    .iter()
                    .zip(equations.coordinates())
                    .filter(|(a, _)| !a.is_zero())
                    .map(|(a, q)| format!("({}) {}̈", to_unicode(*a), q))
                    .collect();
                println!(
                    "constraint `{name}` (λ{}): {} = {}",
                    i + 1,
                    terms.join(" + "),
                    to_unicode(*b)
                );
            }
            if !equations.first_integrals().is_empty() {
                println!();
            }
            for f in equations.first_integrals() {
                match &f.coordinate {
                    Some(q) => println!("conserved: p_{q} = {}", to_unicode(f.value)),
                    None => println!("conserved ({}): h = {}", f.kind, to_unicode(f.value)),
                }
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}
