//! The run-time statements: initial values, `simulate` settings and `output` items; and the
//! report's `title` (one per file).

use super::expr::Place;
use super::scope::Target;
use super::{name, Checker};
use crate::ast;
use crate::diagnostic::{Diagnostic, DiagnosticKind, NameKind, Type};
use crate::model::*;
use crate::span::Span;

impl Checker {
    pub(super) fn initial(&mut self, value: &ast::InitialValue) {
        let checked = self.expr(
            &value.value,
            Type::Scalar,
            Place::constant("an initial value"),
        );
        let ident = &value.name;
        let Some(entry) = self.scope.get(&ident.name).copied() else {
            self.diagnostics
                .push(self.scope.not_found(ident, Some(NameKind::Coordinate)));
            return;
        };
        let coordinate = match entry.target {
            Target::Coordinate(id) if entry.kind == NameKind::Coordinate => id,
            Target::Poisoned => return,
            _ => {
                let help = if entry.kind == NameKind::DrivenCoordinate {
                    format!("`{}` is driven: its motion is prescribed, so it takes no initial condition.", ident.name)
                } else {
                    "Initial conditions are given for coordinates (`x = 0.1`) and their rates (`x' = 0`).".to_string()
                };
                self.diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::InitialNotCoordinate {
                            name: ident.name.clone(),
                            kind: entry.kind,
                        },
                        ident.span,
                    )
                    .with_help(help),
                );
                return;
            }
        };
        if self
            .model
            .initial
            .iter()
            .any(|i| i.coordinate == coordinate && i.rate == value.rate)
        {
            self.diagnostics.push(
                Diagnostic::new(
                    DiagnosticKind::DuplicateInitial {
                        name: ident.name.clone(),
                        what: if value.rate { "rate" } else { "value" },
                    },
                    ident.span,
                )
                .with_help("Give each initial value once."),
            );
            return;
        }
        if let Some(checked) = checked {
            self.model.initial.push(InitialValue {
                coordinate,
                rate: value.rate,
                value: checked,
            });
        }
    }

    /// `title "…"`: one per file.
    pub(super) fn title(&mut self, text: &str, span: Span) {
        if let Some((_, first)) = &self.model.prose.title {
            let first = *first;
            self.diagnostics.push(
                Diagnostic::new(DiagnosticKind::DuplicateTitle { first }, span)
                    .with_related(first, "the first `title`")
                    .with_help("Keep one `title`; put more words into `problem` or `note`."),
            );
            return;
        }
        self.model.prose.title = Some((text.to_string(), span));
    }

    pub(super) fn simulate(&mut self, settings: &[ast::Setting], span: Span) {
        if let Some(first) = &self.model.simulation {
            let first = first.span;
            self.diagnostics.push(
                Diagnostic::new(DiagnosticKind::DuplicateSimulate { first }, span)
                    .with_related(first, "the first `simulate`")
                    .with_help("Merge the settings into one `simulate` statement."),
            );
            return;
        }
        let mut simulation = Simulation {
            span,
            ..Simulation::default()
        };
        let mut seen: Vec<&str> = Vec::new();
        for setting in settings {
            let key = setting.key.name.as_str();
            if seen.contains(&key) {
                self.diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::DuplicateClause {
                            clause: key.to_string(),
                        },
                        setting.key.span,
                    )
                    .with_help("Give each setting once."),
                );
                continue;
            }
            seen.push(key);
            if key == "method" {
                match &setting.value.kind {
                    ast::ExprKind::Name(method) => simulation.method = Some(name(method)),
                    _ => self.diagnostics.push(
                        Diagnostic::new(
                            DiagnosticKind::InvalidSimulation {
                                reason: "the method must be a name",
                            },
                            setting.value.span,
                        )
                        .with_help(
                            "Write `method rk45`, `method symplectic` or `method implicit`.",
                        ),
                    ),
                }
                continue;
            }
            let Some(value) = self.expr(
                &setting.value,
                Type::Scalar,
                Place::constant("a simulation setting"),
            ) else {
                continue;
            };
            let literal = self.model.evaluate_constant(&value);
            if matches!(key, "step" | "rtol" | "atol") && literal.is_some_and(|v| v <= 0.0) {
                self.diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::InvalidSimulation {
                            reason: "steps and tolerances must be positive",
                        },
                        value.span,
                    )
                    .with_help("Use a positive number, e.g. `rtol 1e-8`."),
                );
                continue;
            }
            let slot = match key {
                "from" => &mut simulation.from,
                "to" => &mut simulation.to,
                "step" => &mut simulation.step,
                "rtol" => &mut simulation.rtol,
                _ => &mut simulation.atol,
            };
            *slot = Some(value);
        }
        let literal = |e: &Option<Expr>| e.as_ref().and_then(|e| self.model.evaluate_constant(e));
        let from = if simulation.from.is_some() {
            literal(&simulation.from)
        } else {
            Some(0.0)
        };
        if let (Some(from), Some(to)) = (from, literal(&simulation.to)) {
            if to <= from {
                let span = simulation.to.as_ref().map_or(span, |e| e.span);
                self.diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::InvalidSimulation {
                            reason: "the end time must be after the start time",
                        },
                        span,
                    )
                    .with_help("Write e.g. `simulate from 0 to 10`."),
                );
            }
        }
        self.model.simulation = Some(simulation);
    }

    pub(super) fn output(&mut self, item: &ast::OutputItem) {
        let label = item
            .name
            .as_ref()
            .map_or_else(|| item.value.to_string(), |n| n.name.clone());
        // Energies and reactions are written as bare names; a declared name of the same
        // spelling wins, so these words are not reserved.
        let special = match &item.value.kind {
            ast::ExprKind::Name(ident) => {
                match (ident.name.as_str(), self.scope.get(&ident.name)) {
                    ("energy", None) => Some(Quantity::Energy),
                    ("kinetic_energy", None) => Some(Quantity::KineticEnergy),
                    ("potential_energy", None) => Some(Quantity::PotentialEnergy),
                    (_, Some(entry)) => match entry.target {
                        Target::Constraint(id) => {
                            Some(Quantity::Reaction(ReactionTarget::Constraint(id)))
                        }
                        _ => None,
                    },
                    _ => None,
                }
            }
            _ => None,
        };
        let quantity = match special {
            Some(quantity) => quantity,
            None => match self.any_expr(&item.value, Place::motion("an output")) {
                Some(value) => Quantity::Expr(value),
                None => return,
            },
        };
        self.model.outputs.push(Output {
            label,
            quantity,
            span: item.value.span,
        });
    }
}
