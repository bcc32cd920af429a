//! `lagrange reactions MODEL`: the constraint reactions a model asks for, by Lagrange I and
//! Newton–Euler, for people or as JSON.

use std::path::Path;

use lagrange::{ResultFormat, Written};

use crate::exit::{print, Exit, Failure};

/// Computes and prints the reactions of a model file.
pub fn run(path: &Path, format: ResultFormat, set: &[String]) -> Result<Exit, Failure> {
    let analysis = super::load(path, set)?;
    let Some(computed) = analysis.reactions().map_err(|e| Failure::of(e, path))? else {
        return Err(Failure::input(
            "the model asks for no reaction; add `reactions CONSTRAINT` or `reaction NAME: hinge P on BODY`",
        ));
    };
    print(computed.written(format))?;
    // Two methods that disagree on a reaction are a bug in lagrange, and the exit code says so.
    Ok(if computed.disagree() {
        Exit::Internal
    } else {
        Exit::Success
    })
}
