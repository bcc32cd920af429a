//! Times one derivation in-process: read the model file, check it, lower it, derive the
//! equations of motion (mass matrix, forcing, first integrals). Used by bench/compare to
//! compare the same work with SymPy's mechanics module, without process start or printing.
//! `cargo run --release -p lagrange-model --example derive_timing -- MODEL` prints seconds.

use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: derive_timing MODEL");
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
    let equations = match mechanics::derive(&system) {
        Ok(eq) => eq,
        Err(e) => {
            eprintln!("{path}: {e}");
            return ExitCode::from(1);
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    std::hint::black_box(equations.forcing());
    println!("{seconds}");
    ExitCode::SUCCESS
}
