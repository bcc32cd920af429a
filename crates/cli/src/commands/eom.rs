//! `lagrange eom MODEL`: Lagrange's equations of motion, for people or as JSON.

use lagrange::report;
use std::path::Path;

use crate::args::EomFormat;
use crate::exit::{print, println, Exit, Failure};

/// Derives and prints the equations of motion of a model file.
pub fn run(path: &Path, format: EomFormat, set: &[String]) -> Result<Exit, Failure> {
    let analysis = super::load(path, set)?;
    let equations = analysis.equations().map_err(|e| Failure::of(e, path))?;
    match format {
        EomFormat::Json => println(&json(&report::eom_json(analysis.system(), equations)))?,
        EomFormat::Text => print(report::eom_text(analysis.system(), equations))?,
    }
    Ok(Exit::Success)
}

/// Pretty JSON text.
pub fn json(value: &serde_json::Value) -> String {
    serde_json::to_string_pretty(value).unwrap_or_else(|e| format!("\"{e}\""))
}
