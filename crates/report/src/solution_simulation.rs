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
    /// When inputs and non-conservative forces do work: at the last row, the energy balance
    /// `(E − E₀ − W)/|E₀|` and the work `W` done since the start (then the relative energy
    /// error is mostly that work, and is not what tells the run's accuracy).
    pub balance: Option<(f64, f64)>,
    /// The model's outputs in the plot, for its caption.
    pub outputs: Vec<String>,
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
            .map(|(c, v)| format!("{} = {}", display_name(c), signed(*v)))
            .collect();
        let column = |back: usize| {
            last.get(run.columns.len().wrapping_sub(back))
                .copied()
                .unwrap_or(f64::NAN)
        };
        let energy = match run.balance {
            Some((balance, work)) => format!(
                "The inputs did work W = {} on the system; the energy balance (E − E₀ − W)/|E₀| \
                 is {} (the energy itself changed by {} of |E₀|)",
                signed(work),
                scientific(balance),
                scientific(column(2))
            ),
            None => format!("Relative energy error {}", scientific(column(2))),
        };
        section.paragraph(format!(
            "At t = {:.6}: {}. {energy}, constraint drift {}.",
            last[0],
            state.join(", "),
            scientific(column(1))
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
            caption: caption(run),
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

/// The figure's caption: what its panels show.
fn caption(run: &RunReport<'_>) -> String {
    let outputs = if run.outputs.is_empty() {
        String::new()
    } else {
        format!(" the model's outputs ({}),", run.outputs.join(", "))
    };
    let energy = if run.balance.is_some() {
        "energy balance"
    } else {
        "energy error"
    };
    format!("Time histories,{outputs} phase portraits and {energy} of the run.")
}

/// A state column's name as the report writes it: `theta` → `θ`, `x_d` → `ẋ`.
fn display_name(column: &str) -> String {
    let expr = match column.strip_suffix("_d") {
        Some(q) => cas::Expr::rate(q, 1),
        None => cas::Expr::coordinate(column),
    };
    cas::print::to_unicode(expr)
}

/// A number with six decimals and a true minus sign (`−9.600807`), as the report's formulas
/// write it.
fn signed(v: f64) -> String {
    format!("{v:.6}").replace('-', "−")
}

/// A small number in three digits, in E notation (`-1.61e-10`: plain text, which the
/// Markdown and LaTeX renderers leave as it is, unlike a true minus sign that they set as
/// mathematics).
fn scientific(v: f64) -> String {
    format!("{v:.2e}")
}

/// The names of the state columns: the coordinates, then their rates.
fn state_names(columns: &[String], n: usize) -> impl Iterator<Item = &String> {
    columns.iter().skip(1).take(2 * n)
}
