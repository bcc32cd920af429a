//! `lagrange solve MODEL`: the whole solution, step by step, as the course writes it — for the
//! terminal, as MyST Markdown, as a standalone LaTeX document, or as JSON.

use std::path::Path;

use crate::exit::{emit, Exit, Failure};
use lagrange::{Figures, ReportFormat};

/// `lagrange solve MODEL [--format …] [--out DIR]`.
pub fn run(
    path: &Path,
    format: ReportFormat,
    out: Option<&Path>,
    set: &[String],
) -> Result<Exit, Failure> {
    let analysis = super::load(path, set)?;
    // Before the sections: the simulation writes its plots into the directory.
    let figures = out
        .map(|dir| Figures::prepare(dir, path, format.extension()))
        .transpose()
        .map_err(|e| Failure::of(e, path))?
        .map(|(figures, replaced)| {
            for file in replaced {
                eprintln!("replacing {}", file.display());
            }
            figures
        });
    let solution = analysis
        .solution(figures.as_ref())
        .map_err(|e| Failure::of(e, path))?;
    let text = analysis.solution_written(&solution, format);
    let text = text.map_err(|e| Failure::of(e, path))?;
    let file = figures.map(|f| f.report_file(format.extension()));
    emit(file.as_deref(), text)?;
    // Two methods that disagree on a reaction are a bug in lagrange, and the exit code says so.
    Ok(if solution.disagree {
        Exit::Internal
    } else {
        Exit::Success
    })
}
