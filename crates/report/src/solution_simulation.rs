//! The "Simulation" section of a solution: how the model's own `simulate` settings ran, the
//! state where the run ended, why it stopped early if it did, and the plot beside the report.

use crate::document::{Block, Section};

/// Why a run ended, as the section tells it.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum RunEnd {
    /// At the end time.
    Finished,
    /// A one-sided constraint was lost at `t`.
    ContactLost {
        /// The constraint.
        constraint: String,
        /// When.
        t: f64,
    },
    /// Its stop condition was met at `t`.
    Condition {
        /// When.
        t: f64,
    },
    /// The integration failed ("at t = …: why").
    Failed(String),
}

/// What the section reports of one run.
#[derive(Debug, Clone)]
pub struct RunReport<'a> {
    /// The method's name.
    pub method: String,
    /// The time span asked for.
    pub span: (f64, f64),
    /// Steps, rejected steps, right-hand-side evaluations.
    pub work: (u64, u64, u64),
    /// The column names of the rows.
    pub columns: &'a [String],
    /// The last row written, if any.
    pub last: Option<&'a [f64]>,
    /// How it ended.
    pub end: RunEnd,
    /// How the initial state was moved onto the constraints (`name = given → corrected`, …),
    /// when it was.
    pub corrected: Option<String>,
    /// The plot file (relative to the report) or why it was not written; `None` without a
    /// directory for figures.
    pub figure: Option<Result<String, String>>,
}

/// The section; `Err(why)` when the run could not be prepared.
#[must_use]
pub fn simulation_section(run: Result<&RunReport<'_>, String>) -> Section {
    let mut section = Section::new("Simulation", 2);
    let run = match run {
        Ok(run) => run,
        Err(why) => {
            section.paragraph(format!("Not simulated: {why}."));
            return section;
        }
    };
    let (steps, rejected, evaluations) = run.work;
    let n = run.columns.len().saturating_sub(3) / 2;
    section.paragraph(format!(
        "The nonlinear equations of motion integrated from t = {} to t = {} by {} from the \
         model's initial state: {steps} steps ({rejected} rejected), {evaluations} evaluations \
         of the right-hand side.",
        run.span.0, run.span.1, run.method
    ));
    if let Some(moved) = &run.corrected {
        section.remark(format!(
            "The initial state given does not satisfy the constraints kept with multipliers; \
             the run starts from the nearest state that does: {moved}."
        ));
    }
    if let Some(last) = run.last {
        let state: Vec<String> = state_names(run.columns, n)
            .zip(last.iter().skip(1))
            .map(|(c, v)| format!("{c} = {v:.6}"))
            .collect();
        section.paragraph(format!(
            "At t = {:.6}: {}. Relative energy error {:.2e}, constraint drift {:.2e}.",
            last[0],
            state.join(", "),
            last.get(run.columns.len().wrapping_sub(2))
                .copied()
                .unwrap_or(f64::NAN),
            last.get(run.columns.len().wrapping_sub(1))
                .copied()
                .unwrap_or(f64::NAN)
        ));
    }
    match &run.end {
        RunEnd::Finished => {}
        RunEnd::ContactLost { constraint, t } => {
            section.remark(format!(
                "The run stopped at t = {t:.6}: the one-sided constraint `{constraint}` is lost \
                 there (its reaction changes sign), and past that point the equations describe \
                 a motion that cannot happen."
            ));
        }
        RunEnd::Condition { t } => {
            section.remark(format!(
                "The run stopped at t = {t:.6}: its stop condition was met."
            ));
        }
        RunEnd::Failed(why) => {
            section.remark(format!(
                "The run stopped {why}; what is shown was computed up to then."
            ));
        }
    }
    match &run.figure {
        Some(Ok(path)) => section.blocks.push(Block::Figure {
            path: path.clone(),
            caption: "Time histories, phase portraits and energy error of the run.".into(),
            width: 90,
        }),
        Some(Err(error)) => {
            section.paragraph(format!("The plot could not be written: {error}."));
        }
        None => {
            section.paragraph("A report written into a directory has the plots beside it.");
        }
    }
    section
}

/// The names of the state columns: the coordinates, then their rates.
fn state_names(columns: &[String], n: usize) -> impl Iterator<Item = &String> {
    columns.iter().skip(1).take(2 * n)
}
