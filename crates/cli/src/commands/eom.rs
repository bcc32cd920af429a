//! `lagrange eom MODEL`: Lagrange's equations of motion, for people or as JSON.

use std::path::Path;

use lagrange::ResultFormat;

use crate::exit::{print, Exit, Failure};

/// Derives and prints the equations of motion of a model file.
pub fn run(path: &Path, format: ResultFormat, set: &[String]) -> Result<Exit, Failure> {
    let analysis = super::load(path, set)?;
    let text = analysis.equations_written(format);
    print(text.map_err(|e| Failure::of(e, path))?)?;
    Ok(Exit::Success)
}
