//! `lagrange solve MODEL`: the whole solution, step by step, as the course writes it — for the
//! terminal, as MyST Markdown, as a standalone LaTeX document, or as JSON.

use std::path::Path;

use crate::exit::{emit, Exit, Failure};
use lagrange::ReportFormat;

/// `lagrange solve MODEL [--format …] [--out DIR]`.
pub fn run(
    path: &Path,
    format: ReportFormat,
    out: Option<&Path>,
    set: &[String],
) -> Result<Exit, Failure> {
    let analysis = super::load(path, set)?;
    let replacing = &mut |file: &Path| eprintln!("replacing {}", file.display());
    let solved = analysis
        .solution_into(path, format, out, replacing)
        .map_err(|e| Failure::of(e, path))?;
    emit(solved.file.as_deref(), solved.text)?;
    // Two methods that disagree on a reaction are a bug in lagrange, and the exit code says so.
    Ok(if solved.disagree {
        Exit::Internal
    } else {
        Exit::Success
    })
}
