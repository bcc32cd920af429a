//! The subcommands, one module each; what they share: loading a model with `--set` values.

use lagrange::model;
pub mod animate;
mod check;
pub mod draw;
mod eom;
mod equilibria;
mod expression;
mod linearize_periodic;
mod reactions;
pub mod simulate;
mod solve;
mod steady;

use std::path::Path;

use lagrange::Analysis;

use crate::args::Command;
use crate::exit::{Exit, Failure};

/// Runs one subcommand.
pub fn run(command: Command) -> Result<Exit, Failure> {
    match command {
        Command::Solve { input, format, out } => {
            solve::run(&input.model, format, out.as_deref(), &input.set)
        }
        Command::Check { model } => check::run(&model),
        Command::Eom {
            input,
            format,
            method,
        } => eom::run(&input.model, format, method, &input.set),
        Command::Reactions { input, format } => reactions::run(&input.model, format, &input.set),
        Command::Equilibria { input, options } => equilibria::run(&input, &options, None, None),
        Command::Linearize {
            input,
            options,
            equilibrium,
            initial,
            periodic: Some(period),
        } => linearize_periodic::run(&input, &options, equilibrium, &period, &initial),
        Command::Linearize {
            input,
            options,
            equilibrium,
            initial,
            periodic: None,
        } => equilibria::run(&input, &options, equilibrium, Some(&initial)),
        Command::Simulate(args) => simulate::run(&args),
        Command::Draw(args) => draw::run(&args),
        Command::Animate(args) => animate::run(&args),
        Command::Simplify { expr, options } => expression::simplify(&expr, &options),
        Command::Diff { expr, var, options } => expression::diff(&expr, &var, &options),
    }
}

/// Reads the model file, prints its warnings, and applies `--set NAME=VALUE` in order.
pub fn load(path: &Path, set: &[String]) -> Result<Analysis, Failure> {
    let mut analysis = Analysis::from_file(path).map_err(|e| Failure::of(e, path))?;
    eprint!(
        "{}",
        analysis.warnings(&path.display().to_string(), render_options())
    );
    analysis
        .set_texts(set)
        .map_err(|e| Failure::flag("--set", e))?;
    Ok(analysis)
}

/// Reads each item of a repeated flag; an error names the flag.
pub fn each<T>(
    items: &[String],
    flag: &str,
    read: impl Fn(&str) -> Result<T, lagrange::AssignmentError>,
) -> Result<Vec<T>, Failure> {
    let read = |item: &String| read(item).map_err(|e| Failure::input(format!("{flag} {e}")));
    items.iter().map(read).collect()
}

/// Colour when stderr is a terminal.
pub fn render_options() -> model::RenderOptions {
    use std::io::IsTerminal;
    model::RenderOptions::default().with_color(std::io::stderr().is_terminal())
}
