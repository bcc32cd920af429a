//! Names in scope while checking: what each declared name stands for, where it was declared,
//! and how much it may vary ([`Level`]), plus the list of every declaration in the file so that
//! a name used above its declaration gets "used before it is defined" instead of "unknown".

use std::collections::HashMap;

use crate::ast::{Ast, Ident, StatementKind};
use crate::diagnostic::{suggest, Diagnostic, DiagnosticKind, NameKind, Type};
use crate::model::{
    BodyId, ConstantId, ConstraintId, CoordinateId, FrameId, InputId, ParameterId, PointId,
};
use crate::span::Span;

/// How much a quantity may vary; ordered from least to most.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Level {
    /// Numbers, parameters and constants.
    Constant,
    /// Also time and inputs (and driven coordinates, which are functions of time).
    Time,
    /// Also coordinates.
    Configuration,
}

/// What a name resolves to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Target {
    Coordinate(CoordinateId),
    Parameter(ParameterId),
    Input(InputId),
    Constant(ConstantId, Type),
    Frame(FrameId),
    Point(PointId),
    Body(BodyId),
    Constraint(ConstraintId),
    /// A declaration whose definition had errors: uses of it are not reported again.
    Poisoned,
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct Entry {
    pub kind: NameKind,
    pub target: Target,
    pub span: Span,
    pub level: Level,
}

/// Names that cannot be declared.
pub(crate) const RESERVED: &[&str] = &["t", "pi", "origin"];

#[derive(Default)]
pub(crate) struct Scope {
    entries: HashMap<String, Entry>,
    /// Every declaration in the file (first one wins): name → (kind, span).
    everything: HashMap<String, (NameKind, Span)>,
}

impl Scope {
    pub(crate) fn new(ast: &Ast) -> Scope {
        let mut everything = HashMap::new();
        let mut add = |ident: &Ident, kind: NameKind| {
            everything
                .entry(ident.name.clone())
                .or_insert((kind, ident.span));
        };
        for statement in &ast.statements {
            match &statement.kind {
                StatementKind::Coordinates(names) => {
                    names.iter().for_each(|n| add(n, NameKind::Coordinate))
                }
                StatementKind::Parameters(b) => {
                    b.iter().for_each(|b| add(&b.name, NameKind::Parameter))
                }
                StatementKind::Inputs(b) => b.iter().for_each(|b| add(&b.name, NameKind::Input)),
                StatementKind::Constants(b) => {
                    b.iter().for_each(|b| add(&b.name, NameKind::Constant))
                }
                StatementKind::Driven(b) => b
                    .iter()
                    .for_each(|b| add(&b.name, NameKind::DrivenCoordinate)),
                StatementKind::Frame { name, .. } => add(name, NameKind::Frame),
                StatementKind::Point { name, .. } => add(name, NameKind::Point),
                StatementKind::Body { name, .. } => add(name, NameKind::Body),
                StatementKind::Constraint {
                    name: Some(name), ..
                } => add(name, NameKind::Constraint),
                _ => {}
            }
        }
        Scope {
            entries: HashMap::new(),
            everything,
        }
    }

    /// Declare `ident`; on a clash, report it and return false (the first declaration stays).
    pub(crate) fn declare(
        &mut self,
        ident: &Ident,
        kind: NameKind,
        target: Target,
        level: Level,
        diagnostics: &mut Vec<Diagnostic>,
    ) -> bool {
        let name = ident.name.as_str();
        if RESERVED.contains(&name) || crate::model::Function::from_name(name).is_some() {
            let help = match name {
                "t" => "`t` is time. Choose another name.".to_string(),
                "pi" => "`pi` is π. Choose another name.".to_string(),
                "origin" => {
                    "`origin` is the fixed origin of the inertial frame. Choose another name."
                        .to_string()
                }
                _ => format!("`{name}` is a built-in function. Choose another name."),
            };
            diagnostics.push(
                Diagnostic::new(
                    DiagnosticKind::ReservedName {
                        name: name.to_string(),
                    },
                    ident.span,
                )
                .with_help(help),
            );
            return false;
        }
        if let Some(first) = self.entries.get(name) {
            let kind_first = first.kind;
            diagnostics.push(
                Diagnostic::new(
                    DiagnosticKind::DuplicateName {
                        name: name.to_string(),
                        first: first.span,
                    },
                    ident.span,
                )
                .with_label("defined again here")
                .with_related(
                    first.span,
                    format!("first defined here as {}", kind_first.with_article()),
                )
                .with_help(format!(
                    "Rename one of the two, or remove the second declaration of `{name}`."
                )),
            );
            return false;
        }
        self.entries.insert(
            ident.name.clone(),
            Entry {
                kind,
                target,
                span: ident.span,
                level,
            },
        );
        true
    }

    pub(crate) fn get(&self, name: &str) -> Option<&Entry> {
        self.entries.get(name)
    }

    /// The diagnostic for `ident`, which is not (yet) in scope. `wanted` filters suggestions.
    pub(crate) fn not_found(&self, ident: &Ident, wanted: Option<NameKind>) -> Diagnostic {
        let name = ident.name.as_str();
        if let Some(&(kind, definition)) = self.everything.get(name) {
            if definition.start > ident.span.start {
                return Diagnostic::new(
                    DiagnosticKind::UsedBeforeDefinition {
                        name: name.to_string(),
                        definition,
                    },
                    ident.span,
                )
                .with_related(
                    definition,
                    format!("`{name}` is defined here, as {}", kind.with_article()),
                )
                .with_help(format!(
                    "Move the declaration of `{name}` above its first use."
                ));
            }
        }
        let kind = match wanted {
            Some(NameKind::Point) => DiagnosticKind::UndefinedPoint {
                name: name.to_string(),
            },
            _ => DiagnosticKind::UnknownName {
                name: name.to_string(),
            },
        };
        let diagnostic = Diagnostic::new(kind, ident.span);
        let candidates = self
            .entries
            .iter()
            .filter(|(_, entry)| wanted.is_none_or(|kind| entry.kind == kind))
            .map(|(name, _)| name.as_str());
        let builtins: &[&str] = if wanted.is_none() { RESERVED } else { &[] };
        match suggest(name, candidates.chain(builtins.iter().copied())) {
            Some(best) => diagnostic.with_help(format!("Did you mean `{best}`?")),
            None => diagnostic.with_help(match wanted {
                Some(NameKind::Point) => format!("Define it first: `point {name} = …`."),
                Some(NameKind::Frame) => self.define_frame_help(name),
                Some(NameKind::Body) => {
                    format!("Define it first: `body {name} mass … at … frame … inertia …`.")
                }
                Some(NameKind::Coordinate) => format!("Declare it first: `coordinates {name}`."),
                Some(NameKind::Constraint) => {
                    format!("Name a constraint `{name}`: `constraint {name}: …`.")
                }
                _ => format!(
                    "Declare `{name}` first, e.g. `parameters {name} = 1` or `coordinates {name}`."
                ),
            }),
        }
    }

    /// How to define a missing frame: rotated from a frame already declared (the earliest,
    /// usually the inertial one), or, when there is none, as the inertial frame itself —
    /// never `frame N = N rotated …`, which refers to itself.
    fn define_frame_help(&self, name: &str) -> String {
        let parent = self
            .entries
            .iter()
            .filter(|(other, entry)| entry.kind == NameKind::Frame && other.as_str() != name)
            .min_by_key(|(_, entry)| entry.span.start)
            .map(|(other, _)| other.as_str());
        match parent {
            Some(parent) => {
                format!("Define it first: `frame {name} = {parent} rotated … about z`.")
            }
            None => format!(
                "Define it first: `frame {name}` (the first frame, without a rotation, is the inertial frame)."
            ),
        }
    }

    /// Resolve `ident`, which must be of `kind`; report and return `None` otherwise (also for a
    /// poisoned name, without a report).
    pub(crate) fn expect_kind(
        &self,
        ident: &Ident,
        kind: NameKind,
        diagnostics: &mut Vec<Diagnostic>,
    ) -> Option<Entry> {
        match self.get(&ident.name) {
            None if kind == NameKind::Point && ident.name == "origin" => Some(Entry {
                kind: NameKind::Point,
                target: Target::Point(PointId(0)),
                span: ident.span,
                level: Level::Constant,
            }),
            None => {
                diagnostics.push(self.not_found(ident, Some(kind)));
                None
            }
            Some(entry) if entry.target == Target::Poisoned => None,
            Some(entry) if entry.kind == kind => Some(*entry),
            Some(entry) => {
                let diagnostic = Diagnostic::new(
                    DiagnosticKind::WrongKind {
                        name: ident.name.clone(),
                        expected: kind,
                        found: entry.kind,
                    },
                    ident.span,
                )
                .with_related(entry.span, format!("`{}` is defined here", ident.name));
                let others = self
                    .entries
                    .iter()
                    .filter(|(_, e)| e.kind == kind)
                    .map(|(n, _)| n.as_str());
                let diagnostic = match suggest(&ident.name, others) {
                    Some(best) => diagnostic.with_help(format!("Did you mean `{best}`?")),
                    None => diagnostic
                        .with_help(format!("Use the name of {} here.", kind.with_article())),
                };
                diagnostics.push(diagnostic);
                None
            }
        }
    }
}
