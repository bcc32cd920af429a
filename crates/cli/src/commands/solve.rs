//! `lagrange solve MODEL`: the whole solution, as far as the engine derives it today.
//!
//! Today that is the checked model (what the file describes and how many degrees of freedom
//! it has) and the equations of motion (Lagrange II); each later stage (reactions,
//! equilibria, linearization, simulation, report) adds its section here as it lands.

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
    println!("\n## Equations of motion (Lagrange II)\n");
    super::eom::run(path, crate::args::EomFormat::Text)
}
