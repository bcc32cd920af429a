//! Times one derivation in-process: read the model file, check it, lower it, derive the
//! equations of motion (mass matrix, forcing, first integrals). Used by bench/compare to
//! compare with SymPy's mechanics module, without process start or printing.
//! `cargo run --release -p lagrange-model --example derive_timing -- MODEL [--same-work]`
//! prints seconds. With `--same-work` only what SymPy's `LagrangesMethod` does is timed:
//! `K`, `V`, Lagrange's equations, `M` and `f` (no first integrals, no explicit `q̈`).
//! With `--terms` the size of the result follows the time: the number of terms of `M` and `f`
//! together (a sum counts its terms, anything else other than zero one), untimed.

use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let same_work = args.iter().any(|a| a == "--same-work");
    let count_terms = args.iter().any(|a| a == "--terms");
    let Some(path) = args.iter().find(|a| !a.starts_with("--")).cloned() else {
        eprintln!("usage: derive_timing MODEL [--same-work]");
        return ExitCode::from(2);
    };
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) => {
            eprintln!("cannot read {path}: {e}");
            return ExitCode::from(2);
        }
    };
    // One cold run: the symbolic core remembers results, so a second run in the same process
    // would measure its memo rather than the derivation.
    let start = Instant::now();
    let Ok(model) = model::load(&text) else {
        eprintln!("{path}: the model has errors (run `lagrange check {path}`)");
        return ExitCode::from(1);
    };
    let system = match model::lower(&model) {
        Ok(system) => system,
        Err(e) => {
            eprintln!("{path}: {e}");
            return ExitCode::from(1);
        }
    };
    let derived = if same_work {
        mechanics::derive_without_first_integrals(&system)
    } else {
        mechanics::derive(&system)
    };
    let equations = match derived {
        Ok(eq) => eq,
        Err(e) => {
            eprintln!("{path}: {e}");
            return ExitCode::from(1);
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    std::hint::black_box(equations.forcing());
    if count_terms {
        let entries = equations.mass_matrix().iter().flatten();
        let terms: usize = entries
            .chain(equations.forcing())
            .map(|e| terms_of(*e))
            .sum();
        println!("{seconds} {terms}");
    } else {
        println!("{seconds}");
    }
    ExitCode::SUCCESS
}

/// The number of terms of an expression: a sum's operands, zero for zero, one otherwise.
fn terms_of(e: cas::Expr) -> usize {
    match e.node() {
        cas::Node::Add(terms) => terms.len(),
        _ if e.is_literal_zero() => 0,
        _ => 1,
    }
}
