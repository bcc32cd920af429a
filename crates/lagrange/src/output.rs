//! The files a command writes where the user says: their format read from the file name
//! ([`FileFormat`]), a solution's files prepared in their directory before any work
//! ([`Figures::prepare`]), and a drawing's state read from `NAME=VALUE` items with the time
//! among them ([`Analysis::set_state`]). Nothing here prints: a program decides what to say.

use std::path::{Path, PathBuf};

use crate::{check_output, parse_assignment, Analysis, Error, Figures};

/// The format of an output file, from its extension (any case).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum FileFormat {
    /// A vector figure.
    Svg,
    /// A raster figure.
    Png,
    /// A self-contained page (an animation).
    Html,
}

/// What an output file holds, and so which formats it may have.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Output {
    /// A figure of the system: SVG or PNG.
    Figure,
    /// An animation: HTML.
    Animation,
}

impl Output {
    /// The formats this output is written in.
    #[must_use]
    pub fn formats(self) -> &'static [FileFormat] {
        match self {
            Output::Figure => &[FileFormat::Svg, FileFormat::Png],
            Output::Animation => &[FileFormat::Html],
        }
    }
}

impl std::fmt::Display for Output {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Output::Figure => "a figure",
            Output::Animation => "an animation",
        })
    }
}

impl FileFormat {
    /// The file name's extension, lower case.
    #[must_use]
    pub fn extension(self) -> &'static str {
        match self {
            FileFormat::Svg => "svg",
            FileFormat::Png => "png",
            FileFormat::Html => "html",
        }
    }

    /// The format of `path` for `output`.
    ///
    /// # Errors
    /// [`Error::FileFormat`] when the extension is not one of `output`'s formats.
    pub fn of(path: &Path, output: Output) -> Result<FileFormat, Error> {
        let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        output
            .formats()
            .iter()
            .copied()
            .find(|f| f.extension().eq_ignore_ascii_case(extension))
            .ok_or_else(|| Error::FileFormat {
                path: path.to_owned(),
                output,
            })
    }
}

/// The formats' names and extensions for a message: `SVG or PNG` and `.svg or .png`.
pub(crate) fn format_names(output: Output) -> (String, String) {
    let formats = output.formats();
    let upper: Vec<String> = formats
        .iter()
        .map(|f| f.extension().to_uppercase())
        .collect();
    let dotted: Vec<String> = formats
        .iter()
        .map(|f| format!(".{}", f.extension()))
        .collect();
    (upper.join(" or "), dotted.join(" or "))
}

impl Figures {
    /// Prepares the directory of a solution written as `report_extension` (`md`, `tex`, …):
    /// creates it, and checks every file the solution will write there (the report, the figure
    /// of the system, its animation, the plots of the motion) before any work — none may be the
    /// model file. Gives the figures and the files that exist and will be replaced.
    ///
    /// # Errors
    /// [`Error::Create`] when the directory cannot be made; [`Error::OverwritesInput`].
    pub fn prepare(
        directory: &Path,
        model: &Path,
        report_extension: &str,
    ) -> Result<(Figures, Vec<PathBuf>), Error> {
        std::fs::create_dir_all(directory).map_err(|e| Error::Create {
            path: directory.to_owned(),
            reason: e.to_string(),
        })?;
        let stem = model
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("solution")
            .to_owned();
        // pdflatex cannot include SVG.
        let extension = if report_extension == "tex" {
            "png"
        } else {
            "svg"
        };
        let files = [
            format!("{stem}-motion.{extension}"),
            format!("{stem}.{extension}"),
            format!("{stem}.html"),
            format!("{stem}.{report_extension}"),
        ];
        let mut replaced = Vec::new();
        for name in files {
            let file = directory.join(name);
            if check_output(&file, model)? {
                replaced.push(file);
            }
        }
        let figures = Figures {
            directory: directory.to_owned(),
            stem,
            extension,
        };
        Ok((figures, replaced))
    }

    /// The report's file: `DIR/STEM.EXTENSION`.
    #[must_use]
    pub fn report_file(&self, report_extension: &str) -> PathBuf {
        self.directory
            .join(format!("{}.{report_extension}", self.stem))
    }
}

impl Analysis {
    /// Sets each `NAME=VALUE` in order, as [`Analysis::set`]; `t=VALUE` among them is the time
    /// (a number or a constant expression), which is given back (0 when absent).
    ///
    /// # Errors
    /// [`Error::Refused`]: the first item refused, with why.
    pub fn set_state(&mut self, items: &[String]) -> Result<f64, Error> {
        let mut time = 0.0;
        for item in items {
            let refused = |e: Error| Error::Refused {
                item: item.clone(),
                error: Box::new(e),
            };
            let assignment = parse_assignment(item).map_err(|e| refused(e.into()))?;
            if assignment.name == "t" {
                time = self.read_number(item).map_err(|e| refused(e.into()))?.1;
            } else {
                self.set(&assignment).map_err(refused)?;
            }
        }
        Ok(time)
    }

    /// Sets each `NAME=VALUE` in order, as [`Analysis::set`] (`t` is not a value to set).
    ///
    /// # Errors
    /// [`Error::Refused`]: the first item refused, with why.
    pub fn set_texts(&mut self, items: &[String]) -> Result<(), Error> {
        for item in items {
            let refused = |e: Error| Error::Refused {
                item: item.clone(),
                error: Box::new(e),
            };
            let assignment = parse_assignment(item).map_err(|e| refused(e.into()))?;
            self.set(&assignment).map_err(refused)?;
        }
        Ok(())
    }
}

/// A solution rendered for where it goes ([`Analysis::solution_into`]).
#[derive(Debug, Clone)]
pub struct SolutionOutput {
    /// The report in the format asked for.
    pub text: String,
    /// The report's file in the directory asked for (`None`: no directory, the caller prints
    /// it).
    pub file: Option<PathBuf>,
    /// Whether Lagrange I and Newton–Euler disagree on a reaction (a bug of lagrange).
    pub disagree: bool,
}

impl Analysis {
    /// The whole solution of the model read from `model`, rendered as `format`; with a
    /// directory `out`, its files prepared there first (each existing one that will be
    /// replaced is given to `replacing` before any work) and the figures and plots written
    /// into it. The report itself is left for the caller to write (`file`).
    ///
    /// # Errors
    /// As [`Figures::prepare`] and [`Analysis::solution`].
    pub fn solution_into(
        &self,
        model: &Path,
        format: crate::ReportFormat,
        out: Option<&Path>,
        replacing: &mut dyn FnMut(&Path),
    ) -> Result<SolutionOutput, Error> {
        let figures = match out {
            Some(dir) => {
                let (figures, replaced) = Figures::prepare(dir, model, format.extension())?;
                replaced.iter().for_each(|file| replacing(file));
                Some(figures)
            }
            None => None,
        };
        let solution = self.solution(figures.as_ref())?;
        Ok(SolutionOutput {
            text: self.solution_written(&solution, format)?,
            file: figures.map(|f| f.report_file(format.extension())),
            disagree: solution.disagree,
        })
    }
}
