//! Diagnostics: what is wrong with a model, where, and how to mend it.
//!
//! A [`Diagnostic`] is a typed value: its [`DiagnosticKind`] carries the facts (names, counts,
//! expected and found types) and gives the message; the diagnostic adds the primary [`Span`], a
//! `help` line saying how to fix it, and secondary [`Label`]s pointing at related places (the
//! first definition of a duplicate name, say). [`crate::render`] turns them into text.

use std::fmt;

use crate::span::{LineCol, LineIndex, Span};

/// How serious a diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Severity {
    /// The model is unusable until this is fixed.
    Error,
    /// The model works, but something is probably not what was meant.
    Warning,
}

/// What kind of thing a name stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum NameKind {
    /// A generalized coordinate (`coordinates`).
    Coordinate,
    /// A time-driven coordinate (`driven`).
    DrivenCoordinate,
    /// A parameter (`parameters`).
    Parameter,
    /// An input, possibly a function of time (`inputs`).
    Input,
    /// A named constant (`constants`).
    Constant,
    /// A reference frame (`frame`).
    Frame,
    /// A point (`point`, or the built-in `origin`).
    Point,
    /// A rigid body (`body`).
    Body,
    /// A named constraint (`constraint NAME: …`).
    Constraint,
    /// A built-in: `t`, `pi`, `origin` or a function name.
    Builtin,
}

impl NameKind {
    /// The noun used in messages, with its article: "a coordinate".
    #[must_use]
    pub fn with_article(self) -> &'static str {
        match self {
            NameKind::Coordinate => "a coordinate",
            NameKind::DrivenCoordinate => "a driven coordinate",
            NameKind::Parameter => "a parameter",
            NameKind::Input => "an input",
            NameKind::Constant => "a constant",
            NameKind::Frame => "a frame",
            NameKind::Point => "a point",
            NameKind::Body => "a body",
            NameKind::Constraint => "a constraint",
            NameKind::Builtin => "a built-in name",
        }
    }
}

impl fmt::Display for NameKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let noun = self.with_article();
        f.write_str(noun.split_once(' ').map_or(noun, |(_, noun)| noun))
    }
}

/// The type of an expression: the language has scalars and 3-vectors (points are position
/// vectors from `origin`). Deliberately exhaustive: a third type would change every rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Type {
    /// A real number.
    Scalar,
    /// A vector of 3-space.
    Vector,
}

impl fmt::Display for Type {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Type::Scalar => "scalar",
            Type::Vector => "vector",
        })
    }
}

/// Everything that can be wrong with a model. The message of each variant is its `Display`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DiagnosticKind {
    // --- syntax -----------------------------------------------------------------------------
    /// A character that is not part of the language.
    #[error("unexpected character `{text}`")]
    InvalidCharacter {
        /// The offending characters.
        text: String,
    },
    /// The parser expected one thing and found another.
    #[error("expected {expected}, found {found}")]
    UnexpectedToken {
        /// What would have been valid here.
        expected: String,
        /// What was there.
        found: String,
    },
    /// A line starts with a word that is not a statement keyword.
    #[error("unknown statement `{word}`")]
    UnknownStatement {
        /// The first word of the line.
        word: String,
    },
    /// An opening parenthesis without its closing one.
    #[error("unclosed parenthesis")]
    UnclosedParenthesis,
    /// A text (`"…"`) whose line ends before its closing quote.
    #[error("unclosed text: the line ends before the closing `\"`")]
    UnclosedText,
    /// Expression nested deeper than the parser allows.
    #[error("expression is nested too deeply (more than {limit} levels)")]
    TooDeep {
        /// The nesting limit.
        limit: usize,
    },
    /// A number literal that does not fit in a finite `f64`.
    #[error("number `{text}` is out of range")]
    NumberOutOfRange {
        /// The literal.
        text: String,
    },
    /// A non-zero number literal too small for a double-precision value (it would read as a
    /// subnormal number or as 0).
    #[error("number `{text}` is too small for numeric work")]
    NumberUnderflow {
        /// The literal.
        text: String,
    },
    /// A clause given twice in one statement (`mass` twice in a `body`, say).
    #[error("`{clause}` is given twice")]
    DuplicateClause {
        /// The clause keyword.
        clause: String,
    },
    /// A keyword-value option that the statement does not know.
    #[error("unknown option `{option}` for `{statement}`")]
    UnknownOption {
        /// The option word.
        option: String,
        /// The statement keyword.
        statement: &'static str,
    },

    // --- names ------------------------------------------------------------------------------
    /// A name that is not declared (anywhere in the file).
    #[error("unknown name `{name}`")]
    UnknownName {
        /// The name as written.
        name: String,
    },
    /// A name declared twice.
    #[error("`{name}` is already defined")]
    DuplicateName {
        /// The name.
        name: String,
        /// Where it was first defined.
        first: Span,
    },
    /// A declaration that uses a reserved name (`t`, `pi`, `origin`, a function).
    #[error("`{name}` is a reserved name")]
    ReservedName {
        /// The name.
        name: String,
    },
    /// A name used on a line above its declaration.
    #[error("`{name}` is used before it is defined")]
    UsedBeforeDefinition {
        /// The name.
        name: String,
        /// Where it is defined.
        definition: Span,
    },
    /// A name of the wrong kind (a frame where a point is needed, say).
    #[error("`{name}` is {}, but {} is needed here", found.with_article(), expected.with_article())]
    WrongKind {
        /// The name.
        name: String,
        /// The kind the context needs.
        expected: NameKind,
        /// The kind the name has.
        found: NameKind,
    },
    /// A particle placed at a name that is not a defined point.
    #[error("particle at undefined point `{name}`")]
    UndefinedPoint {
        /// The name.
        name: String,
    },
    /// A call of a function the language does not have.
    #[error("unknown function `{name}`")]
    UnknownFunction {
        /// The name.
        name: String,
    },
    /// A function called with the wrong number of arguments.
    #[error("`{function}` takes {expected} argument{}, but {found} {} given",
        if *expected == 1 { "" } else { "s" }, if *found == 1 { "was" } else { "were" })]
    WrongArity {
        /// The function.
        function: &'static str,
        /// The number it takes.
        expected: usize,
        /// The number given.
        found: usize,
    },
    /// `N.w`: a unit vector other than `x`, `y`, `z`.
    #[error("frame `{frame}` has no axis `{axis}`")]
    UnknownAxis {
        /// The frame.
        frame: String,
        /// The axis as written.
        axis: String,
    },
    /// `rotated … about w`: a rotation axis other than `x`, `y`, `z`.
    #[error("cannot rotate about `{axis}`: there is no such axis")]
    UnknownRotationAxis {
        /// The axis as written.
        axis: String,
    },
    /// A frame, body or constraint (or a function name) used as a value.
    #[error("`{name}` is {}, not a value", kind.with_article())]
    NotAValue {
        /// The name.
        name: String,
        /// What it is.
        kind: NameKind,
    },
    /// A second inertial frame.
    #[error("there is already an inertial frame, `{first_name}`")]
    SecondInertialFrame {
        /// The first inertial frame's name.
        first_name: String,
        /// Where it is declared.
        first: Span,
    },

    // --- types ------------------------------------------------------------------------------
    /// An expression of the wrong type for its place.
    #[error("expected a {expected}, found a {found}")]
    TypeMismatch {
        /// The type the place needs.
        expected: Type,
        /// The type of the expression.
        found: Type,
    },
    /// An operator applied to operands of types it does not accept.
    #[error("cannot {operation} a {lhs} and a {rhs}")]
    InvalidOperands {
        /// The operation in words ("add", "multiply", …).
        operation: &'static str,
        /// Type of the left operand.
        lhs: Type,
        /// Type of the right operand.
        rhs: Type,
    },
    /// A rate `q'` of something that is not a coordinate.
    #[error("`{name}'`: only coordinates have rates, and `{name}` is {}", kind.with_article())]
    RateOfNonCoordinate {
        /// The name.
        name: String,
        /// What it is.
        kind: NameKind,
    },
    /// A rate `q'` where only positions may appear (points, frames, potentials, holonomic
    /// constraints…).
    #[error("rates such as `{name}'` cannot appear in {place}")]
    RateNotAllowed {
        /// The coordinate.
        name: String,
        /// The kind of statement.
        place: &'static str,
    },
    /// A value that must be constant (or a function of time only) depends on more.
    #[error("{place} can depend only on {allowed}, not on `{name}`")]
    NotConstant {
        /// The kind of value ("a parameter value", …).
        place: &'static str,
        /// What it may depend on ("numbers, parameters and constants").
        allowed: &'static str,
        /// The offending name.
        name: String,
    },
    /// A velocity constraint or a Rayleigh function of the wrong degree in the rates.
    #[error("{place} must be {requirement} in the rates")]
    WrongDegreeInRates {
        /// The kind of statement.
        place: &'static str,
        /// "linear", "at most quadratic".
        requirement: &'static str,
    },

    // --- statements -------------------------------------------------------------------------
    /// A body without one of its required clauses.
    #[error("body `{body}` has no {clause}")]
    BodyMissing {
        /// The body.
        body: String,
        /// The missing clause: "mass", "inertia", "frame" or "centre of mass".
        clause: &'static str,
    },
    /// `constraint f(q)` without `= …`.
    #[error("a constraint must be an equation")]
    NotAnEquation,
    /// `initial` for a name that is not a free coordinate.
    #[error("initial condition for `{name}`, which is {} and not a coordinate", kind.with_article())]
    InitialNotCoordinate {
        /// The name.
        name: String,
        /// What it is.
        kind: NameKind,
    },
    /// The same initial value given twice.
    #[error("initial {what} of `{name}` is given twice")]
    DuplicateInitial {
        /// The coordinate.
        name: String,
        /// "value" or "rate".
        what: &'static str,
    },
    /// More (scalar) constraints than coordinates.
    #[error("{constraints} constraints on {coordinates} coordinate{}: the system cannot move",
        if *coordinates == 1 { "" } else { "s" })]
    TooManyConstraints {
        /// Number of scalar constraint equations.
        constraints: usize,
        /// Number of free coordinates.
        coordinates: usize,
    },
    /// The model has no free coordinate at all.
    #[error("the model declares no coordinates")]
    NoCoordinates,
    /// A `reactions` entry that names no constraint.
    #[error("no reaction for `{name}`: it is {}, not a constraint or a driven coordinate", kind.with_article())]
    ReactionNotConstraint {
        /// The name.
        name: String,
        /// What it is.
        kind: NameKind,
    },
    /// A reaction at a point that is not declared.
    #[error("reaction at unknown point `{name}`")]
    UnknownReactionPoint {
        /// The name.
        name: String,
    },
    /// A reaction's member that is neither a body nor a particle.
    #[error("`{name}` is not a body or a particle: a reaction acts on bodies and particles")]
    NotABodyOrParticle {
        /// The name.
        name: String,
    },
    /// `reaction NAME: rolling C normal n` where `C` is not a rolling constraint.
    #[error("`{name}` is not a rolling constraint")]
    NotARollingConstraint {
        /// The name.
        name: String,
    },
    /// A simulation setting that is not a valid value.
    #[error("invalid simulation setting: {reason}")]
    InvalidSimulation {
        /// Why.
        reason: &'static str,
    },
    /// A second `simulate` statement.
    #[error("`simulate` is given twice")]
    DuplicateSimulate {
        /// The first one.
        first: Span,
    },
    /// A second `title` statement.
    #[error("`title` is given twice")]
    DuplicateTitle {
        /// The first one.
        first: Span,
    },
    /// A constraint that involves no free coordinate (`l = 1`, `t = 0`).
    #[error("this constraint does not involve any coordinate")]
    ConstraintWithoutCoordinates,
    /// A mass that evaluates to zero or less.
    #[error("a mass must be positive, but this one is {value}")]
    NonPositiveMass {
        /// Its value.
        value: f64,
    },
    /// A moment of inertia (a diagonal component) that evaluates to less than zero.
    #[error("a moment of inertia cannot be negative, but this one is {value}")]
    NegativeMoment {
        /// Its value.
        value: f64,
    },

    // --- warnings ---------------------------------------------------------------------------
    /// A free coordinate that no position, frame, constraint or energy depends on: its
    /// equation of motion would be empty (a singular mass matrix).
    #[error("coordinate `{name}` is never used")]
    UnusedCoordinate {
        /// The coordinate.
        name: String,
    },
    /// A parameter that no expression uses.
    #[error("parameter `{name}` is never used")]
    UnusedParameter {
        /// The parameter.
        name: String,
    },
    /// Several parameters that no expression uses, in one warning.
    #[error("{} parameters are never used: {}{}", .names.len() + .more, list_names(.names), if *.more > 0 { format!(" and {} more", .more) } else { String::new() })]
    UnusedParameters {
        /// The first few of them.
        names: Vec<String>,
        /// How many more there are.
        more: usize,
    },

    // --- values (from `Model::require_values`) ----------------------------------------------
    /// A parameter or input without a numeric value, when numbers are needed.
    #[error("{} `{name}` has no value", if *kind == NameKind::Input { "input" } else { "parameter" })]
    MissingValue {
        /// The name.
        name: String,
        /// Parameter or input.
        kind: NameKind,
    },
    /// A constant value that numeric work cannot use: it divides by zero, overflows or
    /// underflows double precision, or is not a real number.
    #[error("this value {reason}")]
    UnusableValue {
        /// What is wrong with it ("divides by zero", …).
        reason: &'static str,
    },
    /// `simulate` needs an end time.
    #[error("the simulation has no end time")]
    MissingEndTime,
}

impl DiagnosticKind {
    /// A short note for the underline of the offending text, where the message alone would
    /// be repeated; `None` means "use the message".
    #[must_use]
    pub fn underline_note(&self) -> Option<String> {
        use DiagnosticKind::*;
        Some(match self {
            InvalidCharacter { .. } => "not part of the language".to_string(),
            UnexpectedToken { expected, .. } => format!("expected {expected}"),
            UnknownStatement { .. } => "not a statement keyword".to_string(),
            TooDeep { .. } => "nested too deeply".to_string(),
            NumberOutOfRange { .. } => "too large".to_string(),
            NumberUnderflow { .. } => "too small".to_string(),
            DuplicateClause { .. } => "given again here".to_string(),
            UnknownOption { .. } => "not an option here".to_string(),
            UnknownName { .. } => "not declared".to_string(),
            ReservedName { .. } => "reserved".to_string(),
            UsedBeforeDefinition { .. } => "used here".to_string(),
            WrongKind { found, .. } => format!("this is {}", found.with_article()),
            UndefinedPoint { .. } | UnknownReactionPoint { .. } => "no such point".to_string(),
            NotABodyOrParticle { .. } => "not a body or particle".to_string(),
            NotARollingConstraint { .. } => "not `rolling BODY at P`".to_string(),
            UnknownFunction { .. } => "no such function".to_string(),
            WrongArity { found, .. } => {
                format!("{found} argument{}", if *found == 1 { "" } else { "s" })
            }
            UnknownAxis { .. } | UnknownRotationAxis { .. } => "not `x`, `y` or `z`".to_string(),
            SecondInertialFrame { .. } => "a second inertial frame".to_string(),
            NotAValue { kind, .. } => format!("this is {}", kind.with_article()),
            TypeMismatch { found, .. } => format!("this is a {found}"),
            InvalidOperands { .. } => "here".to_string(),
            RateOfNonCoordinate { .. } | RateNotAllowed { .. } => "a rate".to_string(),
            NotConstant { .. } => "not constant enough".to_string(),
            BodyMissing { clause, .. } => format!("no {clause}"),
            NotAnEquation => "no `=`".to_string(),
            InitialNotCoordinate { kind, .. } | ReactionNotConstraint { kind, .. } => {
                format!("this is {}", kind.with_article())
            }
            DuplicateInitial { .. } => "given again here".to_string(),
            ConstraintWithoutCoordinates => "no coordinate here".to_string(),
            NonPositiveMass { value } | NegativeMoment { value } => format!("= {value}"),
            UnusedCoordinate { .. } | UnusedParameter { .. } | UnusedParameters { .. } => {
                "declared here".to_string()
            }
            MissingValue { .. } => "no value".to_string(),
            UnusableValue { reason } => (*reason).to_string(),
            _ => return None,
        })
    }

    /// A stable code for the error catalogue in `docs/language.md` (`E101`, …).
    #[must_use]
    pub fn code(&self) -> &'static str {
        use DiagnosticKind::*;
        match self {
            InvalidCharacter { .. } => "E001",
            UnexpectedToken { .. } => "E002",
            UnknownStatement { .. } => "E003",
            UnclosedParenthesis => "E004",
            UnclosedText => "E010",
            TooDeep { .. } => "E005",
            NumberOutOfRange { .. } => "E006",
            NumberUnderflow { .. } => "E009",
            DuplicateClause { .. } => "E007",
            UnknownOption { .. } => "E008",
            UnknownName { .. } => "E101",
            DuplicateName { .. } => "E102",
            ReservedName { .. } => "E103",
            UsedBeforeDefinition { .. } => "E104",
            WrongKind { .. } => "E105",
            UndefinedPoint { .. } => "E106",
            UnknownFunction { .. } => "E107",
            WrongArity { .. } => "E108",
            UnknownAxis { .. } => "E109",
            UnknownRotationAxis { .. } => "E110",
            SecondInertialFrame { .. } => "E111",
            NotAValue { .. } => "E112",
            TypeMismatch { .. } => "E201",
            InvalidOperands { .. } => "E202",
            RateOfNonCoordinate { .. } => "E203",
            RateNotAllowed { .. } => "E204",
            NotConstant { .. } => "E205",
            WrongDegreeInRates { .. } => "E206",
            BodyMissing { .. } => "E301",
            NotAnEquation => "E302",
            InitialNotCoordinate { .. } => "E303",
            DuplicateInitial { .. } => "E304",
            TooManyConstraints { .. } => "E305",
            NoCoordinates => "E306",
            ReactionNotConstraint { .. } => "E307",
            UnknownReactionPoint { .. } => "E313",
            NotABodyOrParticle { .. } => "E314",
            NotARollingConstraint { .. } => "E315",
            InvalidSimulation { .. } => "E308",
            DuplicateSimulate { .. } => "E309",
            DuplicateTitle { .. } => "E316",
            ConstraintWithoutCoordinates => "E310",
            NonPositiveMass { .. } => "E311",
            NegativeMoment { .. } => "E312",
            UnusedCoordinate { .. } => "W001",
            UnusedParameter { .. } | UnusedParameters { .. } => "W002",
            MissingValue { .. } => "E401",
            MissingEndTime => "E402",
            UnusableValue { .. } => "E403",
        }
    }
}

fn list_names(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A secondary place shown with a diagnostic, with a short note.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    /// Where.
    pub span: Span,
    /// What about it ("first defined here").
    pub message: String,
}

/// One problem found in a model: what (the [`DiagnosticKind`]), where, and how to mend it.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// What is wrong; its `Display` is the message.
    pub kind: DiagnosticKind,
    /// How serious it is.
    pub severity: Severity,
    /// The offending text.
    pub span: Span,
    /// A short note under the primary underline (defaults to none).
    pub label: Option<String>,
    /// How to mend it, as a full sentence.
    pub help: Option<String>,
    /// Related places.
    pub labels: Vec<Label>,
}

impl Diagnostic {
    /// An error of `kind` at `span`, without help or labels.
    #[must_use]
    pub fn new(kind: DiagnosticKind, span: Span) -> Diagnostic {
        Diagnostic {
            kind,
            severity: Severity::Error,
            span,
            label: None,
            help: None,
            labels: Vec::new(),
        }
    }

    /// A warning of `kind` at `span`.
    #[must_use]
    pub fn warning(kind: DiagnosticKind, span: Span) -> Diagnostic {
        Diagnostic {
            severity: Severity::Warning,
            ..Diagnostic::new(kind, span)
        }
    }

    /// Add how to mend the problem.
    #[must_use]
    pub fn with_help(mut self, help: impl Into<String>) -> Diagnostic {
        self.help = Some(help.into());
        self
    }

    /// Add a note under the primary underline.
    #[must_use]
    pub fn with_label(mut self, label: impl Into<String>) -> Diagnostic {
        self.label = Some(label.into());
        self
    }

    /// Point at a related place.
    #[must_use]
    pub fn with_related(mut self, span: Span, message: impl Into<String>) -> Diagnostic {
        self.labels.push(Label {
            span,
            message: message.into(),
        });
        self
    }

    /// The message: what is wrong.
    #[must_use]
    pub fn message(&self) -> String {
        self.kind.to_string()
    }

    /// Line and column where the diagnostic starts in `source`.
    #[must_use]
    pub fn line_col(&self, source: &str) -> LineCol {
        LineIndex::new(source).line_col(self.span.start)
    }

    /// Whether this is an error (rather than a warning).
    #[must_use]
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.kind)?;
        if let Some(help) = &self.help {
            write!(f, " (help: {help})")?;
        }
        Ok(())
    }
}

impl std::error::Error for Diagnostic {}

/// A non-empty list of diagnostics: the error type of [`crate::load`].
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostics(pub Vec<Diagnostic>);

impl fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let errors = self.0.iter().filter(|d| d.is_error()).count();
        write!(
            f,
            "{errors} error{} in the model",
            if errors == 1 { "" } else { "s" }
        )?;
        if let Some(first) = self.0.first() {
            write!(f, "; first: {first}")?;
        }
        Ok(())
    }
}

impl std::error::Error for Diagnostics {}

/// The closest of `candidates` to `name` by edit distance, if close enough to be a likely typo.
pub(crate) fn suggest<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    // Allow one edit for short names, more for long ones; never suggest a name that is as far
    // away as it is long (that is not a typo).
    let limit = match name.chars().count() {
        0..=2 => 1,
        3..=5 => 2,
        _ => 3,
    };
    candidates
        .into_iter()
        .filter(|candidate| *candidate != name)
        .map(|candidate| (edit_distance(name, candidate), candidate))
        .filter(|&(distance, candidate)| distance <= limit && distance < candidate.chars().count())
        .min_by_key(|&(distance, candidate)| (distance, candidate))
        .map(|(_, candidate)| candidate)
}

/// Optimal string alignment distance (Levenshtein plus adjacent transpositions), on characters.
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    // Three rolling rows: i-2, i-1, i.
    let mut before: Vec<usize> = vec![0; b.len() + 1];
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    let mut current = vec![0; b.len() + 1];
    for (i, &ca) in a.iter().enumerate() {
        current[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let substitution = previous[j] + usize::from(ca != cb);
            let mut best = substitution.min(previous[j + 1] + 1).min(current[j] + 1);
            if i > 0 && j > 0 && a[i - 1] == cb && ca == b[j - 1] {
                best = best.min(before[j - 1] + 1);
            }
            current[j + 1] = best;
        }
        std::mem::swap(&mut before, &mut previous);
        std::mem::swap(&mut previous, &mut current);
    }
    previous[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edit_distance_counts_typos() {
        assert_eq!(edit_distance("thta", "theta"), 1);
        assert_eq!(edit_distance("theta", "thaet"), 2);
        assert_eq!(edit_distance("ab", "ba"), 1);
        assert_eq!(edit_distance("", "abc"), 3);
    }

    #[test]
    fn suggestions_pick_the_closest_plausible_name() {
        assert_eq!(suggest("thta", ["theta", "x", "phi"]), Some("theta"));
        assert_eq!(suggest("q", ["x", "theta"]), None);
        assert_eq!(suggest("m_a", ["m_A", "m_B"]), Some("m_A"));
    }
}
