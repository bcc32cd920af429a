//! A whole question about rest states, asked at once: the equilibria, their linearization, a
//! parameter sweep, a steady motion of a nonholonomic system or a Floquet analysis of a
//! periodic one. The question is checked for parts that do not go together, answered from one
//! derivation, and written in the format asked for, with its figure drawn. A front end (the
//! command line, the Python package) fills one from its own options; an error says which
//! [`QuestionPart`] it comes from, so the front end can name its own option there.

use std::path::{Path, PathBuf};

use crate::formats::{json_text, Linearized, ResultFormat, Written};
use crate::steady_print::{
    plot_sweep, steady_json, steady_text, sweep_json, sweep_text, SteadyExtras,
};
use crate::{Analysis, Error, FloquetOptions, Search};

/// What is asked. Every list holds the texts as given (`NAME=VALUE`, `NAME=A..B`).
#[derive(Debug, Clone, Copy, Default)]
pub struct EquilibriumQuestion<'a> {
    /// Text or JSON.
    pub format: ResultFormat,
    /// Constant rates of cyclic coordinates (`phi=2`): relative equilibria.
    pub steady: &'a [String],
    /// Search ranges of coordinates that are not angles (`x=-2..2`).
    pub ranges: &'a [String],
    /// Parameters to sweep (`Omega=0..10`): one, or two for a Floquet chart.
    pub sweeps: &'a [String],
    /// Steps of a sweep.
    pub steps: usize,
    /// Where to draw the sweep's diagram (a bifurcation diagram, a stability chart, the
    /// eigenvalues against a speed).
    pub plot: Option<&'a Path>,
    /// Only this equilibrium (or periodic motion), by its index in the list.
    pub only: Option<usize>,
    /// `Some` asks for the linearization, with these initial deviations (`theta=0.01`,
    /// `theta'=0.1`) for the free response.
    pub linearize: Option<&'a [String]>,
    /// `Some` asks for a Floquet analysis over this period (an expression such as `2*pi`; empty
    /// for the period of the driving).
    pub periodic: Option<&'a str>,
}

/// The part of an [`EquilibriumQuestion`] an error comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QuestionPart {
    /// [`EquilibriumQuestion::steady`].
    Steady,
    /// [`EquilibriumQuestion::ranges`].
    Range,
    /// [`EquilibriumQuestion::sweeps`].
    Sweep,
    /// [`EquilibriumQuestion::plot`].
    Plot,
    /// [`EquilibriumQuestion::only`].
    Only,
    /// The initial deviations of [`EquilibriumQuestion::linearize`].
    Initial,
    /// [`EquilibriumQuestion::periodic`].
    Periodic,
}

impl std::fmt::Display for QuestionPart {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            QuestionPart::Steady => "a steady rate",
            QuestionPart::Range => "a search range",
            QuestionPart::Sweep => "a sweep",
            QuestionPart::Plot => "a plot",
            QuestionPart::Only => "an index",
            QuestionPart::Initial => "initial deviations",
            QuestionPart::Periodic => "a Floquet analysis",
        })
    }
}

/// Parts of a question that do not make sense as given ([`Error::Misuse`]).
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Misuse {
    /// `part` has no meaning together with `with`.
    NotWith {
        /// The part refused.
        part: QuestionPart,
        /// What it does not go with.
        with: QuestionPart,
    },
    /// More parameters swept than this kind of question sweeps.
    TooManySweeps {
        /// How many it takes.
        most: usize,
    },
    /// A plot asked for without a sweep to draw.
    PlotWithoutSweep,
    /// A periodic motion asked for by an index beyond the list.
    NoSuchMotion {
        /// The index asked for.
        index: usize,
        /// How many there are.
        count: usize,
    },
}

impl Misuse {
    /// The part of the question at fault.
    #[must_use]
    pub fn part(&self) -> QuestionPart {
        match self {
            Misuse::NotWith { part, .. } => *part,
            Misuse::TooManySweeps { .. } => QuestionPart::Sweep,
            Misuse::PlotWithoutSweep => QuestionPart::Plot,
            Misuse::NoSuchMotion { .. } => QuestionPart::Only,
        }
    }

    /// The sentence, with each part named by `name` (a front end's option names).
    pub fn sentence(&self, name: impl Fn(QuestionPart) -> String) -> String {
        match self {
            Misuse::NotWith { part, with } => {
                format!("{} does not go with {}", name(*part), name(*with))
            }
            Misuse::TooManySweeps { most: 1 } => {
                format!("{} takes one parameter here", name(QuestionPart::Sweep))
            }
            Misuse::TooManySweeps { most } => format!(
                "{} takes at most {most} parameters here",
                name(QuestionPart::Sweep)
            ),
            Misuse::PlotWithoutSweep => format!(
                "{} draws the diagram of {}; add {} P=a..b",
                name(QuestionPart::Plot),
                name(QuestionPart::Sweep),
                name(QuestionPart::Sweep)
            ),
            Misuse::NoSuchMotion { index, count } => format!(
                "there are {count} periodic motion(s), numbered from 0; {index} is not one of them"
            ),
        }
    }
}

impl std::fmt::Display for Misuse {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.sentence(|part| part.to_string()))
    }
}

/// An error of an answer, with the part of the question it comes from when it comes from one.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{error}")]
pub struct QuestionError {
    /// The part at fault, if one is.
    pub part: Option<QuestionPart>,
    /// What went wrong (boxed: an answer's result stays small).
    pub error: Box<Error>,
}

impl From<Error> for QuestionError {
    fn from(error: Error) -> Self {
        let part = match &error {
            Error::Misuse(misuse) => Some(misuse.part()),
            _ => None,
        };
        QuestionError {
            part,
            error: Box::new(error),
        }
    }
}

/// `Err(QuestionError)` with `part` at fault.
fn at<T>(part: QuestionPart, result: Result<T, impl Into<Error>>) -> Result<T, QuestionError> {
    result.map_err(|e| QuestionError {
        part: Some(part),
        error: Box::new(e.into()),
    })
}

fn misuse<T>(misuse: Misuse) -> Result<T, QuestionError> {
    Err(Error::Misuse(misuse).into())
}

/// The answer: the text to print and the figure written, if one was.
#[derive(Debug, Clone, PartialEq)]
pub struct Answer {
    /// In the format asked for.
    pub text: String,
    /// The diagram drawn.
    pub figure: Option<PathBuf>,
}

impl Analysis {
    /// Answers `question`.
    ///
    /// # Errors
    /// A [`QuestionError`] naming the part at fault: a value that does not read, parts that do
    /// not go together ([`Error::Misuse`]), or the mechanics' own refusal.
    pub fn answer(&self, question: &EquilibriumQuestion) -> Result<Answer, QuestionError> {
        if let Some(period) = question.periodic {
            return self.answer_periodic(question, period);
        }
        if question.linearize.is_some() && self.describes_steady_motion() {
            return self.answer_steady(question);
        }
        let search = Search {
            steady: read_each(question.steady, QuestionPart::Steady, |s| {
                self.read_number(s)
            })?,
            ranges: read_each(question.ranges, QuestionPart::Range, |s| self.read_range(s))?,
        };
        match question.sweeps {
            [] => {}
            [sweep] => return self.answer_sweep(question, &search, sweep),
            _ => return misuse(Misuse::TooManySweeps { most: 1 }),
        }
        if question.plot.is_some() {
            return misuse(Misuse::PlotWithoutSweep);
        }
        let found = self.equilibria_with(&search)?;
        if let Some(i) = question.only {
            at(QuestionPart::Only, found.check_index(i))?;
        }
        let text = match question.linearize {
            None => found.written(question.format),
            Some(initial) => {
                let deviations = (!initial.is_empty())
                    .then(|| self.read_deviations(initial, &found.rest.coordinates))
                    .transpose();
                let deviations = at(QuestionPart::Initial, deviations)?;
                Linearized {
                    equilibria: &found,
                    only: question.only,
                    deviations: deviations.as_ref().map(|(q, v)| (&q[..], &v[..])),
                }
                .written(question.format)
            }
        };
        Ok(Answer { text, figure: None })
    }

    /// One swept parameter: the equilibria and their stability at each step.
    fn answer_sweep(
        &self,
        question: &EquilibriumQuestion,
        search: &Search,
        sweep: &str,
    ) -> Result<Answer, QuestionError> {
        let range = at(QuestionPart::Sweep, self.read_range(sweep))?;
        let table = at(
            QuestionPart::Sweep,
            self.equilibrium_sweep(search, &range, question.steps),
        )?;
        if let Some(plot) = question.plot {
            table.plot(plot).map_err(Error::from)?;
        }
        Ok(Answer {
            text: table.written(question.format),
            figure: question.plot.map(Path::to_path_buf),
        })
    }

    /// A steady motion of a nonholonomic system: its linearization, or a sweep of one
    /// parameter with the speeds where stability changes.
    fn answer_steady(&self, question: &EquilibriumQuestion) -> Result<Answer, QuestionError> {
        let as_json = question.format == ResultFormat::Json;
        let range = match question.sweeps {
            [] => None,
            [sweep] => Some(at(QuestionPart::Sweep, self.read_range(sweep))?),
            _ => return misuse(Misuse::TooManySweeps { most: 1 }),
        };
        let Some(range) = range else {
            if question.plot.is_some() {
                return misuse(Misuse::PlotWithoutSweep);
            }
            let lin = self.steady_linearization()?;
            let canonical = self
                .steady_speed_parameter()
                .and_then(|v| self.canonical_form(&v).ok());
            let spectrum = lin.spectrum().ok();
            let condition = match &spectrum {
                Some(s) => self.steady_condition(&lin, s)?,
                None => None,
            };
            let extras = SteadyExtras {
                canonical: canonical.as_ref(),
                spectrum: spectrum.as_ref(),
                condition: condition.as_ref(),
            };
            let coordinates = self.system().coordinates();
            let text = if as_json {
                json_text(&steady_json(coordinates, &lin, extras))
            } else {
                steady_text(coordinates, &lin, extras)
            };
            return Ok(Answer { text, figure: None });
        };
        let swept = |steps| self.steady_sweep(&range.name, range.low, range.high, steps);
        let table = at(QuestionPart::Sweep, swept(question.steps))?;
        let changes = at(QuestionPart::Sweep, self.steady_crossings(&table))?;
        if let Some(plot) = question.plot {
            plot_sweep(plot, &table)?;
        }
        let text = if as_json {
            json_text(&sweep_json(&table, &changes))
        } else {
            sweep_text(&table, &changes)
        };
        Ok(Answer {
            text,
            figure: question.plot.map(Path::to_path_buf),
        })
    }

    /// Floquet analysis, or with sweeps its stability chart as CSV.
    fn answer_periodic(
        &self,
        question: &EquilibriumQuestion,
        period: &str,
    ) -> Result<Answer, QuestionError> {
        let refused = [
            (QuestionPart::Steady, !question.steady.is_empty()),
            (QuestionPart::Range, !question.ranges.is_empty()),
            (
                QuestionPart::Initial,
                question.linearize.is_some_and(|i| !i.is_empty()),
            ),
        ];
        if let Some((part, _)) = refused.into_iter().find(|(_, given)| *given) {
            let with = QuestionPart::Periodic;
            return misuse(Misuse::NotWith { part, with });
        }
        let floquet = FloquetOptions {
            period: self.read_period(period)?,
            ..FloquetOptions::default()
        };
        if question.sweeps.len() > 2 {
            return misuse(Misuse::TooManySweeps { most: 2 });
        }
        if !question.sweeps.is_empty() {
            return self.answer_chart(question, &floquet);
        }
        if question.plot.is_some() {
            return misuse(Misuse::PlotWithoutSweep);
        }
        let mut found = at(QuestionPart::Periodic, self.floquet(&floquet))?;
        if let Some(index) = question.only {
            let count = found.results.len();
            if index >= count {
                return misuse(Misuse::NoSuchMotion { index, count });
            }
            found.results = vec![found.results.swap_remove(index)];
        }
        Ok(Answer {
            text: found.written(question.format),
            figure: None,
        })
    }

    /// The period of a Floquet analysis: a number or a constant expression, or `None` (empty)
    /// for the driving's.
    fn read_period(&self, text: &str) -> Result<Option<f64>, QuestionError> {
        if text.trim().is_empty() {
            return Ok(None);
        }
        let read = self.read_number(&format!("T={text}"));
        at(QuestionPart::Periodic, read.map(|(_, v)| Some(v)))
    }

    /// The stability chart of a Floquet analysis on the grid of one or two swept parameters.
    fn answer_chart(
        &self,
        question: &EquilibriumQuestion,
        floquet: &FloquetOptions,
    ) -> Result<Answer, QuestionError> {
        let ranges = read_each(question.sweeps, QuestionPart::Sweep, |s| self.read_range(s))?;
        let chart = at(
            QuestionPart::Sweep,
            self.floquet_chart(floquet, &ranges, question.steps),
        )?;
        if let Some(plot) = question.plot {
            let index = question.only.unwrap_or(0);
            let count = chart.motions.len();
            if index >= count {
                return misuse(Misuse::NoSuchMotion { index, count });
            }
            chart.plot(plot, index).map_err(Error::from)?;
        }
        Ok(Answer {
            text: chart.to_csv(),
            figure: question.plot.map(Path::to_path_buf),
        })
    }
}

/// Reads every item of one part of a question.
fn read_each<T>(
    items: &[String],
    part: QuestionPart,
    read: impl Fn(&str) -> Result<T, crate::AssignmentError>,
) -> Result<Vec<T>, QuestionError> {
    items.iter().map(|item| at(part, read(item))).collect()
}
