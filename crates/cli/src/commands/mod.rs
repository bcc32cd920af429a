//! The subcommands, one module each.

mod check;
mod eom;
mod equilibria;
mod expression;
mod reactions;
pub mod simulate;
mod solve;
mod sweep;

use std::process::ExitCode;

use crate::args::Command;

/// Runs one subcommand; the exit code says whether the input was good.
pub fn run(command: Command) -> anyhow::Result<ExitCode> {
    match command {
        Command::Solve {
            model,
            format,
            out,
            set,
        } => solve::run(&model, format, out.as_deref(), &set),
        Command::Check { model } => check::run(&model),
        Command::Eom { model, format, set } => eom::run(&model, format, &set),
        Command::Reactions { model, format, set } => reactions::run(&model, format, &set),
        Command::Equilibria { model, options } => {
            equilibria::run(&model, &options, None, false, &[])
        }
        Command::Linearize {
            model,
            options,
            equilibrium,
            initial,
        } => equilibria::run_linearize(&model, &options, equilibrium, &initial),
        Command::Simulate(args) => simulate::run(&args),
        Command::Simplify {
            expr,
            format,
            coords,
        } => expression::simplify(&expr, format, &coords),
        Command::Diff {
            expr,
            var,
            format,
            coords,
        } => expression::diff(&expr, &var, format, &coords),
    }
}
