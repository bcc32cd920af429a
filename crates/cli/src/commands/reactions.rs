//! `lagrange reactions MODEL`: the constraint reactions a model asks for, by Lagrange I and
//! Newton–Euler, for people or as JSON.

use std::path::Path;

use lagrange::{ResultFormat, Written};

use crate::exit::{print, Exit, Failure};

/// Computes and prints the reactions of a model file.
pub fn run(
    path: &Path,
    format: ResultFormat,
    set: &[String],
    symbolic: bool,
) -> Result<Exit, Failure> {
    let mut analysis = super::load(path, set)?;
    if symbolic {
        analysis.set_reaction_route(lagrange::ReactionRoute::ClosedForm);
    }
    let computed = match analysis.reactions() {
        // Too large for closed form: the multipliers at the initial state, in numbers.
        Err(e) if e.is_too_large_for_closed_form() && format == ResultFormat::Text => {
            let numeric = analysis
                .multipliers_at_start()
                .map_err(|e| Failure::of(e, path))?;
            print(format!("{e}; instead:\n{}", numeric.to_text()))?;
            return Ok(Exit::Success);
        }
        other => other.map_err(|e| Failure::of(e, path))?,
    };
    let Some(computed) = computed else {
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
