//! The subcommands, one module each; what they share: loading a model with `--set` values.

use lagrange::model;
pub mod animate;
mod check;
pub mod draw;
mod eom;
mod equilibria;
mod expression;
mod reactions;
pub mod simulate;
mod solve;

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
        Command::Reactions {
            input,
            format,
            symbolic,
        } => reactions::run(&input.model, format, &input.set, symbolic),
        Command::Equilibria { input, options } => equilibria::run(&input, &options, None, None),
        Command::Linearize {
            input,
            options,
            equilibrium,
            initial,
            periodic,
        } => {
            let linearize = (&initial[..], periodic.as_deref());
            equilibria::run(&input, &options, equilibrium, Some(linearize))
        }
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

/// Colour when stderr is a terminal.
pub fn render_options() -> model::RenderOptions {
    use std::io::IsTerminal;
    model::RenderOptions::default().with_color(std::io::stderr().is_terminal())
}
