//! `lagrange solve MODEL`: the whole solution, as far as the engine derives it today.
//!
//! Today that is the checked model (what the file describes and how many degrees of freedom
//! it has); each later stage (equations of motion, reactions, equilibria, linearization,
//! simulation, report) adds its section here as it lands.

use std::path::Path;
use std::process::ExitCode;

/// `lagrange solve MODEL`.
pub fn run(path: &Path) -> anyhow::Result<ExitCode> {
    let (m, _source) = match super::check::load(path)? {
        Ok(loaded) => loaded,
        Err(code) => return Ok(code),
    };
    println!("# {}\n", path.display());
    println!("## The system\n");
    println!("{}", m.summary().to_string().trim_end());
    Ok(ExitCode::SUCCESS)
}
