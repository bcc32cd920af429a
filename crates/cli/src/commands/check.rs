//! `lagrange check MODEL`: the model's summary, or every mistake in it.

use std::path::Path;

use crate::exit::{println, Exit, Failure};

/// `lagrange check MODEL`.
pub fn run(path: &Path) -> Result<Exit, Failure> {
    let analysis = super::load(path, &[])?;
    if let Some(source) = analysis.source() {
        println(source.model.summary().to_string().trim_end())?;
    }
    Ok(Exit::Success)
}
