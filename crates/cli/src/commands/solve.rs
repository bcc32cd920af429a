//! `lagrange solve MODEL`: the whole solution, step by step, as the course writes it — for the
//! terminal, as MyST Markdown, as a standalone LaTeX document, or as JSON.

use std::path::Path;

use lagrange::Figures;

use crate::args::ReportFormat;
use crate::exit::{check_output, print, println, Exit, Failure};

/// `lagrange solve MODEL [--format …] [--out DIR]`.
pub fn run(
    path: &Path,
    format: ReportFormat,
    out: Option<&Path>,
    set: &[String],
) -> Result<Exit, Failure> {
    let analysis = super::load(path, set)?;
    let stem = path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("solution")
        .to_owned();
    let figures = match out {
        Some(dir) => {
            // Before the sections: the simulation writes its plots there.
            std::fs::create_dir_all(dir).map_err(|e| {
                Failure::input(format!(
                    "cannot create the directory `{}`: {e}",
                    dir.display()
                ))
            })?;
            let extension = if format == ReportFormat::Tex {
                "png"
            } else {
                "svg"
            };
            check_output(&dir.join(format!("{stem}-motion.{extension}")), path)?;
            // The figure of the system and its animation, at the top of the document.
            check_output(&dir.join(format!("{stem}.{extension}")), path)?;
            check_output(&dir.join(format!("{stem}.html")), path)?;
            check_output(&dir.join(format!("{stem}.{}", format.extension())), path)?;
            Some(Figures {
                directory: dir.to_owned(),
                stem: stem.clone(),
                extension,
            })
        }
        None => None,
    };
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
    match out {
        None => print(&text)?,
        Some(dir) => {
            let file = dir.join(format!("{stem}.{}", format.extension()));
            std::fs::write(&file, text)
                .map_err(|e| crate::exit::output_error(&format!("`{}`", file.display()), &e))?;
            println(&format!("wrote {}", file.display()))?;
        }
    }
    // Two methods that disagree on a reaction are a bug in lagrange, and the exit code says so.
    Ok(if solution.disagree {
        Exit::Internal
    } else {
        Exit::Success
    })
}
