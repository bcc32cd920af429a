//! The errors of the pipeline, each with its [`ErrorKind`]: whose mistake it is decides the
//! exit code of the command line (docs/cli.md) and how a program should react.

use std::path::PathBuf;

/// Whose mistake an [`Error`] is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// The user's input is wrong: the model, a value, a name, a setting. Mend the input.
    Input,
    /// The input is well formed but the mechanics is degenerate or not supported (a singular
    /// mass matrix, conflicting constraints, equilibria of a time-dependent system…).
    Mechanics,
    /// lagrange disagrees with itself (two methods give different answers): a bug.
    Internal,
    /// An output could not be written (a full disk, a closed stream).
    Output,
}

/// A model file or text with errors: its diagnostics and the text they point into.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelErrors {
    /// Every mistake found, with its location and how to mend it.
    pub diagnostics: Vec<model::Diagnostic>,
    /// The model text.
    pub source: String,
}

impl ModelErrors {
    /// The diagnostics rendered with the file name, line, column and the source line.
    #[must_use]
    pub fn render(&self, file: &str, options: model::RenderOptions) -> String {
        model::render(&self.diagnostics, file, &self.source, options)
    }

    /// How many of the diagnostics are errors.
    #[must_use]
    pub fn error_count(&self) -> usize {
        self.diagnostics
            .iter()
            .filter(|d| d.severity == model::Severity::Error)
            .count()
    }
}

/// Everything that can stop the pipeline.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The model file could not be read.
    #[error("cannot read the model file `{}`: {reason}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// The model text has errors (rendered by [`ModelErrors::render`]).
    #[error("the model has {} error(s)", .0.error_count())]
    Model(ModelErrors),
    /// A line of the model could not be turned into mechanics.
    #[error("{message}")]
    Located {
        /// What is wrong.
        message: String,
        /// Line (1-based).
        line: usize,
        /// Column (1-based).
        column: usize,
        /// Whose mistake.
        kind: ErrorKind,
    },
    /// A value given for a name (`NAME=VALUE`) is refused.
    #[error(transparent)]
    Assignment(#[from] crate::assign::AssignmentError),
    /// The model could not be lowered into a system.
    #[error(transparent)]
    Lower(#[from] model::LowerError),
    /// The equations of motion could not be derived.
    #[error(transparent)]
    Mechanics(#[from] mechanics::MechanicsError),
    /// Constraints that contradict or restate one another.
    #[error(transparent)]
    Constraints(#[from] mechanics::ConstraintConflict),
    /// Kane's method or a steady motion failed.
    #[error(transparent)]
    Kane(#[from] mechanics::kane::KaneError),
    /// The reactions could not be derived.
    #[error(transparent)]
    Reactions(#[from] mechanics::ReactionError),
    /// Equilibria could not be looked for.
    #[error(transparent)]
    Equilibria(#[from] mechanics::equilibria::EquilibriumError),
    /// A Floquet analysis of a time-periodic system could not be made.
    #[error(transparent)]
    Floquet(#[from] crate::floquet::FloquetError),
    /// A simulation could not be prepared.
    #[error(transparent)]
    Simulation(#[from] simulation::SimulationError),
    /// A simulation needs an end time.
    #[error("no end time: give one, or write `simulate to T` in the model")]
    NoEndTime,
    /// An unknown integration method named in the model's `simulate` statement.
    #[error("unknown method `{name}` (available: dopri5, dop853, gauss, sdirk)")]
    UnknownMethod {
        /// The name.
        name: String,
    },
    /// A value the work needs is missing or not a number.
    #[error("{what} has no numeric value; give it one")]
    MissingValue {
        /// What (a parameter, an initial value…).
        what: String,
    },
    /// Something was asked that the model does not have.
    #[error("{0}")]
    NotAvailable(String),
    /// The figure could not be drawn.
    #[error(transparent)]
    Figure(#[from] draw::DrawError),
    /// An expression given on its own does not parse.
    #[error("{error}\n{}", error.render(text).trim_end())]
    Expression {
        /// The text.
        text: String,
        /// What is wrong, and where.
        error: cas::ParseError,
    },
    /// What an expression was to be differentiated by is not a variable.
    #[error("`{name}` is not a variable; write a symbol name such as `x`, a rate such as `theta_d`, or `t`")]
    NotAVariable {
        /// As given.
        name: String,
    },
    /// An output file would be the model file itself, which is never written over.
    #[error("`{}` is the model file: lagrange never writes over its input; choose another name", path.display())]
    OverwritesInput {
        /// The file.
        path: PathBuf,
    },
    /// An output file could not be created.
    #[error("cannot create `{}`: {reason}", path.display())]
    Create {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// An output could not be written.
    #[error("cannot write {what}: {reason}")]
    Write {
        /// What was being written (`the CSV`, `the summary`, a file name in backquotes).
        what: String,
        /// Why.
        reason: String,
    },
    /// A plot could not be drawn or written, or its file name does not say its format.
    #[error(transparent)]
    Plot(#[from] report::PlotError),
    /// An output file's name does not end in an extension of a format it can be written in.
    #[error("`{}`: {output} is written as {}; give a file name ending in {}", path.display(),
        crate::output::format_names(*output).0, crate::output::format_names(*output).1)]
    FileFormat {
        /// The file.
        path: PathBuf,
        /// What it would hold.
        output: crate::Output,
    },
    /// A `NAME=VALUE` given from outside the model was refused.
    #[error("{item}: {error}")]
    Refused {
        /// The item as given.
        item: String,
        /// Why.
        error: Box<Error>,
    },
    /// An equilibrium asked for by an index beyond the list.
    #[error("there are {count} equilibria (indices from 0); {index} is not one of them")]
    NoSuchEquilibrium {
        /// The index asked for.
        index: usize,
        /// How many equilibria there are.
        count: usize,
    },
    /// Parts of a question that do not go together.
    #[error("{0}")]
    Misuse(crate::question::Misuse),
    /// An output that describes one run was asked of a sweep.
    #[error("{0} one run; leave it out of a sweep")]
    OneRunOnly(OneRunOnly),
    /// lagrange disagrees with itself.
    #[error("internal inconsistency (a bug of lagrange): {0}")]
    Inconsistent(String),
    /// The symbolic work went past a limit of the symbolic core (`cas::WorkLimits`, raised
    /// with [`crate::Analysis::set_work_limits`]).
    #[error("{message}")]
    WorkLimit {
        /// What was being derived and the limit hit.
        message: String,
        /// The limit hit.
        error: cas::WorkLimitError,
        /// Line and column (1-based) of the model statement being derived, when known.
        at: Option<(usize, usize)>,
    },
}

/// What describes one run, and so has no meaning for a sweep ([`Error::OneRunOnly`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum OneRunOnly {
    /// A plot of the run.
    Plot,
    /// Recorded crossings (the expressions to record, or the file of events).
    Crossings,
    /// The JSON summary of the run.
    Summary,
}

impl std::fmt::Display for OneRunOnly {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            OneRunOnly::Plot => "a plot draws",
            OneRunOnly::Crossings => "recorded crossings belong to",
            OneRunOnly::Summary => "a summary describes",
        })
    }
}

impl Error {
    /// The error as a person reads it about the model file `file`: diagnostics drawn under
    /// their source lines (with a count), a located error as `file:line:column: …`, anything
    /// else as `file: …`; every line but the diagnostics' starts with `error: `.
    #[must_use]
    pub fn render(&self, file: &str, options: model::RenderOptions) -> String {
        match self {
            Error::Model(errors) => {
                let count = errors.error_count();
                format!(
                    "{}{file}: {count} error{} found",
                    errors.render(file, options),
                    if count == 1 { "" } else { "s" }
                )
            }
            Error::Located {
                message,
                line,
                column,
                ..
            } => format!("error: {file}:{line}:{column}: {message}"),
            Error::WorkLimit {
                message,
                at: Some((line, column)),
                ..
            } => format!("error: {file}:{line}:{column}: {message}"),
            Error::Read { .. }
            | Error::OverwritesInput { .. }
            | Error::Create { .. }
            | Error::Write { .. }
            | Error::Plot(_)
            | Error::FileFormat { .. }
            | Error::NoSuchEquilibrium { .. }
            | Error::Refused { .. }
            | Error::Misuse(_)
            | Error::OneRunOnly(_) => format!("error: {self}"),
            _ => format!("error: {file}: {self}"),
        }
    }

    /// The work limit hit, when this error is one.
    #[must_use]
    pub fn work_limit(&self) -> Option<&cas::WorkLimitError> {
        match self {
            Error::WorkLimit { error, .. } => Some(error),
            _ => None,
        }
    }

    /// Whose mistake this is.
    #[must_use]
    pub fn kind(&self) -> ErrorKind {
        use simulation::SimulationError as S;
        match self {
            Error::Read { .. }
            | Error::Model(_)
            | Error::Assignment(_)
            | Error::NoEndTime
            | Error::UnknownMethod { .. }
            | Error::MissingValue { .. }
            | Error::NotAvailable(_)
            | Error::Figure(_)
            | Error::Expression { .. }
            | Error::NotAVariable { .. }
            | Error::OverwritesInput { .. }
            | Error::Create { .. }
            | Error::Plot(report::PlotError::Format { .. })
            | Error::FileFormat { .. }
            | Error::NoSuchEquilibrium { .. }
            | Error::Misuse(_)
            | Error::OneRunOnly(_) => ErrorKind::Input,
            Error::Write { .. } | Error::Plot(_) => ErrorKind::Output,
            Error::Located { kind, .. } => *kind,
            Error::Refused { error, .. } => error.kind(),
            Error::Simulation(
                S::InvalidSetting { .. }
                | S::MissingValue(_)
                | S::InitialState { .. }
                | S::StopCondition { .. }
                | S::RecordCondition { .. }
                | S::GaussWithConstraints { .. }
                | S::EmptySpan { .. }
                | S::BeyondLimit { .. },
            ) => ErrorKind::Input,
            Error::Reactions(mechanics::ReactionError::UnknownConstraint(_)) => ErrorKind::Input,
            Error::Kane(e) if e.is_input() => ErrorKind::Input,
            Error::Equilibria(mechanics::equilibria::EquilibriumError::MissingValue { .. }) => {
                ErrorKind::Input
            }
            Error::Floquet(
                crate::FloquetError::NotPeriodic { .. }
                | crate::FloquetError::Autonomous
                | crate::FloquetError::NoCommonPeriod { .. }
                | crate::FloquetError::BadPeriod { .. }
                | crate::FloquetError::MissingValue { .. },
            ) => ErrorKind::Input,
            Error::Inconsistent(_) | Error::Simulation(S::UnsolvedDerivative { .. }) => {
                ErrorKind::Internal
            }
            _ => ErrorKind::Mechanics,
        }
    }
}
