//! The subcommands, one module each.

mod check;
mod eom;
mod expression;
mod solve;

use std::process::ExitCode;

use crate::args::Command;

/// Runs one subcommand; the exit code says whether the input was good.
pub fn run(command: Command) -> anyhow::Result<ExitCode> {
    match command {
        Command::Solve { model } => solve::run(&model),
        Command::Check { model } => check::run(&model),
        Command::Eom { model, format } => eom::run(&model, format),
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
