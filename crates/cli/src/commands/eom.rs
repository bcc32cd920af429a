//! `lagrange eom MODEL`: the equations of motion (Lagrange's or Kane's), for people or as
//! JSON.

use std::path::Path;

use lagrange::{Method, ResultFormat};

use crate::exit::{print, Exit, Failure};

/// Derives and prints the equations of motion of a model file.
pub fn run(
    path: &Path,
    format: ResultFormat,
    method: Method,
    set: &[String],
) -> Result<Exit, Failure> {
    let analysis = super::load(path, set)?;
    let text = analysis.equations_written_by(format, method);
    print(text.map_err(|e| Failure::of(e, path))?)?;
    Ok(Exit::Success)
}
