//! The `lagrange` binary: parses flags, calls the `lagrange` library, prints, and owns the
//! exit code (the contract is in docs/cli.md). Nothing else prints or exits.

mod args;
mod commands;
mod exit;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    restore_default_sigpipe();
    let cli = match args::Cli::try_parse() {
        Ok(cli) => cli,
        Err(error) => {
            // Help and version are answers, not mistakes; a wrong flag is the user's mistake.
            let code = if error.use_stderr() {
                exit::Exit::Input
            } else {
                exit::Exit::Success
            };
            let _ = error.print();
            return code.into();
        }
    };
    if let Some(factor) = cli.work_limit {
        if !(factor.is_finite() && factor > 0.0) {
            return exit::Failure::input(format!(
                "--work-limit: {factor} is not a positive factor; give a number such as 10"
            ))
            .report();
        }
        lagrange::cas::set_work_limits(lagrange::cas::WorkLimits::default().scaled(factor));
    }
    match commands::run(cli.command) {
        Ok(code) => code.into(),
        Err(failure) => failure.report(),
    }
}

/// Rust ignores SIGPIPE, so `lagrange eom M | head` would make `println!` panic once `head`
/// has closed the pipe. A command-line filter should instead stop quietly, as `cat` does.
#[cfg(unix)]
fn restore_default_sigpipe() {
    // SAFETY: called first thing in `main`, before any other thread exists; SIG_DFL is a
    // valid disposition for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(unix))]
fn restore_default_sigpipe() {}
