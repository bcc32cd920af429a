//! `lagrange::Error` as a Python exception: the classes live in the pure-Python module
//! `lagrange._errors` (so that they pickle and carry `.line`, `.column` and `.kind` as plain
//! attributes); this file builds an instance of the right one.

use lagrange::{Error, ErrorKind};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// The exception for `error` about the model named `file` in messages: its rendered text
/// (the located diagnostic drawn under its source line), its kind and its place when known.
pub(crate) fn to_py(py: Python<'_>, error: &Error, file: &str) -> PyErr {
    let message = error.render(file, model_render_options());
    let message = message
        .strip_prefix("error: ")
        .unwrap_or(&message)
        .to_owned();
    let (line, column) = place(error).unzip();
    let kind = match error.kind() {
        ErrorKind::Input => "input",
        ErrorKind::Mechanics => "mechanics",
        ErrorKind::Internal => "internal",
        ErrorKind::Output => "output",
        // `ErrorKind` is non-exhaustive: a kind added later is reported as lagrange's own.
        _ => "internal",
    };
    let made = py
        .import("lagrange._errors")
        .and_then(|m| m.getattr("from_native"))
        .and_then(|f| f.call1((kind, message.clone(), line, column)));
    match made {
        Ok(instance) => PyErr::from_value(instance),
        Err(_) => PyRuntimeError::new_err(message),
    }
}

/// Plain text: no colours in an exception's message.
fn model_render_options() -> lagrange::model::RenderOptions {
    lagrange::model::RenderOptions::default().with_color(false)
}

/// The line and column (1-based) an error points at, when it points somewhere: the first
/// error diagnostic of a model with errors, or a located error.
fn place(error: &Error) -> Option<(usize, usize)> {
    match error {
        Error::Model(errors) => {
            let first = errors
                .diagnostics
                .iter()
                .find(|d| d.is_error())
                .or_else(|| errors.diagnostics.first())?;
            let at = first.line_col(&errors.source);
            Some((at.line, at.column))
        }
        Error::Located { line, column, .. } => Some((*line, *column)),
        Error::WorkLimit { at, .. } => *at,
        Error::Refused { error, .. } => place(error),
        _ => None,
    }
}
