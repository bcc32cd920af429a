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
    if method == Method::Lagrange {
        let text = analysis.equations_written(format);
        print(text.map_err(|e| Failure::of(e, path))?)?;
        return Ok(Exit::Success);
    }
    let kane = analysis
        .kane_equations()
        .map_err(|e| Failure::of(e, path))?;
    print(lagrange::kane_written(&kane, format))?;
    // Kane's and Lagrange's equations that differ are a bug in lagrange, and the exit code
    // says so (as for reactions).
    Ok(if kane.disagrees() {
        Exit::Internal
    } else {
        Exit::Success
    })
}
