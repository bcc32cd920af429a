//! `lagrange check MODEL`: the model's summary, or every mistake in it.

use std::io::IsTerminal;
use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;

/// Reads a model file and loads it, printing the diagnostics when it has errors.
pub fn load(path: &Path) -> anyhow::Result<Result<(model::Model, String), ExitCode>> {
    let source = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read the model file `{}`", path.display()))?;
    let file = path.display().to_string();
    match model::load(&source) {
        Ok(m) => {
            if !m.warnings().is_empty() {
                eprint!(
                    "{}",
                    model::render(m.warnings(), &file, &source, render_options())
                );
            }
            Ok(Ok((m, source)))
        }
        Err(diagnostics) => {
            eprint!(
                "{}",
                model::render(&diagnostics.0, &file, &source, render_options())
            );
            let errors = diagnostics
                .0
                .iter()
                .filter(|d| d.severity == model::Severity::Error)
                .count();
            eprintln!(
                "{file}: {errors} error{} found",
                if errors == 1 { "" } else { "s" }
            );
            Ok(Err(ExitCode::from(1)))
        }
    }
}

fn render_options() -> model::RenderOptions {
    model::RenderOptions::default().with_color(std::io::stderr().is_terminal())
}

/// `lagrange check MODEL`.
pub fn run(path: &Path) -> anyhow::Result<ExitCode> {
    match load(path)? {
        Ok((m, _)) => {
            println!("{}", m.summary().to_string().trim_end());
            Ok(ExitCode::SUCCESS)
        }
        Err(code) => Ok(code),
    }
}
