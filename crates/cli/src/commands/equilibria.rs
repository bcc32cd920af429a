//! `lagrange equilibria MODEL` and `lagrange linearize MODEL`: the flags turned into one
//! question about rest states (`lagrange::EquilibriumQuestion`), its answer printed, and an
//! error's part named by its flag.

use lagrange::{EquilibriumQuestion, Error, QuestionError, QuestionPart};

use crate::args::{EquilibriumOptions, ModelInput};
use crate::exit::{print, Exit, Failure};

/// `lagrange equilibria` (`linearize` is `None`) or `lagrange linearize` (its `--initial`
/// deviations, `--periodic` period).
pub fn run(
    input: &ModelInput,
    options: &EquilibriumOptions,
    only: Option<usize>,
    linearize: Option<(&[String], Option<&str>)>,
) -> Result<Exit, Failure> {
    let path = input.model.as_path();
    let analysis = super::load(path, &input.set)?;
    let question = EquilibriumQuestion {
        format: options.format,
        steady: &options.steady,
        ranges: &options.range,
        sweeps: &options.sweep,
        steps: options.steps,
        plot: options.plot.as_deref(),
        only,
        linearize: linearize.map(|(initial, _)| initial),
        periodic: linearize.and_then(|(_, period)| period),
    };
    let answer = analysis.answer(&question).map_err(|e| failure(e, path))?;
    if let Some(figure) = &answer.figure {
        eprintln!("wrote {}", figure.display());
    }
    print(answer.text)?;
    Ok(Exit::Success)
}

/// The flag of each part of the question.
fn flag(part: QuestionPart) -> &'static str {
    match part {
        QuestionPart::Steady => "--steady",
        QuestionPart::Range => "--range",
        QuestionPart::Sweep => "--sweep",
        QuestionPart::Plot => "--plot",
        QuestionPart::Only => "--equilibrium",
        QuestionPart::Initial => "--initial",
        QuestionPart::Periodic => "--periodic",
    }
}

/// The library's error with its flag named.
fn failure(error: QuestionError, path: &std::path::Path) -> Failure {
    match (error.part, *error.error) {
        (_, Error::Misuse(misuse)) => {
            Failure::input(misuse.sentence(|part| flag(part).to_string()))
        }
        (Some(part), error @ Error::Assignment(_)) => Failure::flag(flag(part), error),
        (Some(part), error) => Failure::of(error, path).prefixed(flag(part)),
        (None, error) => Failure::of(error, path),
    }
}
