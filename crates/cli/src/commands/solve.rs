//! `lagrange solve MODEL`: the whole solution, step by step, as the course writes it — for the
//! terminal, as MyST Markdown, as a standalone LaTeX document, or as JSON.

use std::path::Path;

use lagrange::Figures;

use crate::args::ReportFormat;
use crate::exit::{emit, Exit, Failure};

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
    let document = &solution.document;
    let text = match format {
        ReportFormat::Text => document.to_text(),
        ReportFormat::Md => document.to_markdown(),
        ReportFormat::Tex => document.to_latex(),
        ReportFormat::Json => {
            let value = analysis
                .solution_json(&solution)
                .map_err(|e| Failure::of(e, path))?;
            super::eom::json(&value) + "\n"
        }
    };
    let file = figures.map(|f| f.report_file(format.extension()));
    emit(file.as_deref(), text)?;
    // Two methods that disagree on a reaction are a bug in lagrange, and the exit code says so.
    Ok(if solution.disagree {
        Exit::Internal
    } else {
        Exit::Success
    })
}
