//! `lagrange check MODEL`: the model's summary, or every mistake in it.

use std::io::IsTerminal;
use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;

/// [`load`], then `--set NAME=VALUE` overrides (a parameter, an input, an initial value `q` or
/// a rate `q_d`/`q'`), in order. A bad override is printed and becomes exit code 2.
pub fn load_with_overrides(
    path: &Path,
    set: &[String],
) -> anyhow::Result<Result<(model::Model, String), ExitCode>> {
    let (model, source) = match load(path)? {
        Ok(loaded) => loaded,
        Err(code) => return Ok(Err(code)),
    };
    let mut overrides = Vec::new();
    for item in set {
        match parse_assignment(item) {
            Ok(pair) => overrides.push(pair),
            Err(message) => {
                eprintln!("error: --set {item}: {message}");
                return Ok(Err(ExitCode::from(2)));
            }
        }
    }
    match model.with_overrides(&overrides) {
        Ok(model) => Ok(Ok((model, source))),
        Err(error) => {
            eprintln!("error: --set: {error}");
            Ok(Err(ExitCode::from(2)))
        }
    }
}

/// Lowers a loaded model and derives its equations of motion; a model the mechanics cannot
/// take (a singular mass matrix, …) is printed with the file's name and becomes exit code 1.
pub fn derive(
    path: &Path,
    model: &model::Model,
) -> anyhow::Result<Result<(mechanics::System, mechanics::Equations), ExitCode>> {
    let system = model::lower(model).context("cannot lower the model")?;
    match mechanics::derive(&system) {
        Ok(equations) => Ok(Ok((system, equations))),
        Err(error) => {
            eprintln!("error: {}: {error}", path.display());
            Ok(Err(ExitCode::from(1)))
        }
    }
}

/// `NAME=VALUE`, the value a number or a constant expression (`pi/4`).
fn parse_assignment(item: &str) -> Result<(String, f64), String> {
    let Some((name, value)) = item.split_once('=') else {
        return Err("expected NAME=VALUE".to_owned());
    };
    let (name, value) = (name.trim(), value.trim());
    if name.is_empty() {
        return Err("the name is empty".to_owned());
    }
    if let Ok(x) = value.parse::<f64>() {
        return Ok((name.to_owned(), x));
    }
    let expr = cas::parse(value, &cas::ParseContext::new()).map_err(|e| e.to_string())?;
    let x = expr
        .eval(&|_| None)
        .map_err(|e| format!("the value must be a number: {e}"))?;
    Ok((name.to_owned(), x))
}

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
