//! Constraints, the reactions asked of them, and released constraints (`reaction NAME: …`).

use super::expr::{rate_degree, Place};
use super::scope::{Level, Target};
use super::{id, name, Checker};
use crate::ast::{self, Ident};
use crate::diagnostic::{Diagnostic, DiagnosticKind, NameKind, Type};
use crate::model::*;
use crate::span::Span;

impl Checker {
    pub(super) fn constraint(
        &mut self,
        ident: Option<&Ident>,
        spec: &ast::ConstraintSpec,
        span: Span,
    ) {
        let kind = match spec {
            ast::ConstraintSpec::Equation { lhs, rhs } => self.equation_constraint(lhs, rhs),
            ast::ConstraintSpec::Rolling { body, contact } => {
                let body = self.lookup(body, NameKind::Body);
                let contact = self.lookup(contact, NameKind::Point);
                match (body, contact) {
                    (Some(Target::Body(body)), Some(Target::Point(contact))) => {
                        Some(ConstraintKind::Rolling { body, contact })
                    }
                    _ => None,
                }
            }
            ast::ConstraintSpec::Gear {
                driver,
                driven,
                ratio,
            } => {
                let driver = self.gear_coordinate(driver);
                let driven = self.gear_coordinate(driven);
                let ratio = self.expr(ratio, Type::Scalar, Place::configuration("a gear ratio"));
                match (driver, driven, ratio) {
                    (Some(driver), Some(driven), Some(ratio)) => Some(ConstraintKind::Gear {
                        driver,
                        driven,
                        ratio,
                    }),
                    _ => None,
                }
            }
        };
        self.add_constraint(kind, ident, span);
    }

    /// `lhs = rhs`: holonomic when neither side has a rate, a velocity constraint when both
    /// are linear in the rates; refused without a coordinate or with rates beyond linear.
    fn equation_constraint(&mut self, lhs: &ast::Expr, rhs: &ast::Expr) -> Option<ConstraintKind> {
        let place = Place::motion("a constraint");
        let lhs = self.expr(lhs, Type::Scalar, place);
        let rhs = self.expr(rhs, Type::Scalar, place);
        match (lhs, rhs) {
            (Some(lhs), Some(rhs))
                if self.level_of(&lhs).max(self.level_of(&rhs)) < Level::Configuration =>
            {
                self.diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::ConstraintWithoutCoordinates,
                        lhs.span.to(rhs.span),
                    )
                    .with_help(
                        "A constraint restricts the motion, so it must involve a coordinate; \
                             a fixed relation among parameters belongs in `constants`.",
                    ),
                );
                None
            }
            (Some(lhs), Some(rhs)) => match (rate_degree(&lhs), rate_degree(&rhs)) {
                (Some(0), Some(0)) => Some(ConstraintKind::Holonomic { lhs, rhs }),
                (Some(a), Some(b)) if a <= 1 && b <= 1 => {
                    Some(ConstraintKind::Velocity { lhs, rhs })
                }
                _ => {
                    self.diagnostics.push(
                        Diagnostic::new(
                            DiagnosticKind::WrongDegreeInRates {
                                place: "a velocity constraint",
                                requirement: "linear",
                            },
                            lhs.span.to(rhs.span),
                        )
                        .with_help("Write it as a(q, t)·q' + b(q, t) = 0, with no products or functions of rates."),
                    );
                    None
                }
            },
            _ => None,
        }
    }

    /// Declares a checked constraint (under its name, when it has one), or poisons the name
    /// of one that failed so that later uses are not reported again.
    fn add_constraint(&mut self, kind: Option<ConstraintKind>, ident: Option<&Ident>, span: Span) {
        match (kind, ident) {
            (Some(kind), Some(ident)) => {
                let target = Target::Constraint(ConstraintId(id(self.model.constraints.len())));
                if self.declare(ident, NameKind::Constraint, target, Level::Configuration) {
                    self.model.constraints.push(Constraint {
                        name: Some(name(ident)),
                        kind,
                        span,
                    });
                }
            }
            (Some(kind), None) => {
                let constraint_id = ConstraintId(id(self.model.constraints.len()));
                self.model
                    .declarations
                    .push(Declaration::Constraint(constraint_id));
                let constraint = Constraint {
                    name: None,
                    kind,
                    span,
                };
                self.model.constraints.push(constraint);
            }
            (None, Some(ident)) => self.poison(ident, NameKind::Constraint),
            (None, None) => {}
        }
    }

    pub(super) fn reaction(&mut self, ident: &Ident) {
        let Some(entry) = self.scope.get(&ident.name).copied() else {
            self.diagnostics
                .push(self.scope.not_found(ident, Some(NameKind::Constraint)));
            return;
        };
        let target = match entry.target {
            Target::Constraint(id) => ReactionTarget::Constraint(id),
            Target::Coordinate(id) if entry.kind == NameKind::DrivenCoordinate => {
                ReactionTarget::Driven(id)
            }
            Target::Poisoned => return,
            _ => {
                self.diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::ReactionNotConstraint { name: ident.name.clone(), kind: entry.kind },
                        ident.span,
                    )
                    .with_help("Name the constraint (`constraint NAME: …`) and list that name in `reactions`."),
                );
                return;
            }
        };
        if !self.model.reactions.contains(&target) {
            self.model.reactions.push(target);
        }
    }

    pub(super) fn release(&mut self, ident: &Ident, spec: &ast::ReleaseSpec, span: Span) {
        if spec.word == ast::ReleaseWord::Rolling {
            self.rolling_release(ident, spec, span);
            return;
        }
        let point = if self.scope.get(&spec.point.name).is_none() && spec.point.name != "origin" {
            self.diagnostics.push(
                Diagnostic::new(
                    DiagnosticKind::UnknownReactionPoint {
                        name: spec.point.name.clone(),
                    },
                    spec.point.span,
                )
                .with_help(format!(
                    "Declare it first: `point {} = …`, or name a point the constraint acts at.",
                    spec.point.name
                )),
            );
            None
        } else {
            match self.lookup(&spec.point, NameKind::Point) {
                Some(Target::Point(id)) => Some(id),
                _ => None,
            }
        };
        let mut members = Vec::new();
        let mut complete = true;
        for member in &spec.members {
            let entry = self.scope.get(&member.name).copied();
            let found = match entry.map(|e| e.target) {
                Some(Target::Body(id)) => Some(ReleaseMember::Body(id)),
                Some(Target::Point(id)) => self
                    .model
                    .particles
                    .iter()
                    .position(|p| p.point == id)
                    .map(ReleaseMember::Particle),
                Some(Target::Poisoned) => {
                    complete = false;
                    continue;
                }
                _ => None,
            };
            match found {
                Some(m) if !members.contains(&m) => members.push(m),
                Some(_) => {}
                None => {
                    complete = false;
                    self.diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::NotABodyOrParticle {
                            name: member.name.clone(),
                        },
                        member.span,
                    )
                    .with_help(
                        "Name the bodies (`body NAME …`) or particles (`particle P …`, declared above) that the reaction acts on.",
                    ),
                    );
                }
            }
        }
        let direction = spec.direction.as_ref().and_then(|d| {
            self.expr(
                d,
                Type::Vector,
                Place::configuration("a reaction's direction"),
            )
        });
        if spec.direction.is_some() && direction.is_none() {
            return;
        }
        let Some(projection) = self.projection(spec, point) else {
            return;
        };
        if let Some(point) = point {
            if complete {
                self.model.releases.push(Release {
                    name: name(ident),
                    word: spec.word,
                    point,
                    members,
                    direction,
                    constraint: None,
                    projection,
                    span,
                });
            }
        }
    }

    /// The projection of a `reaction NAME: …` statement resolved: `Some(None)` without one,
    /// `None` when it has errors (reported). `along BODY`, a body's name, is the direction from
    /// the body's centre to the reaction's point `point` (a rod's axis).
    fn projection(
        &mut self,
        spec: &ast::ReleaseSpec,
        point: Option<PointId>,
    ) -> Option<Option<Projection>> {
        if let (Some(ast::ReleaseProjection::Along(d)), Some(point)) = (&spec.projection, point) {
            if let Some(along) = self.along_body(d, point) {
                return Some(Some(along));
            }
        }
        match &spec.projection {
            None => Some(None),
            Some(ast::ReleaseProjection::Frame(frame)) => {
                match self.lookup(frame, NameKind::Frame) {
                    Some(Target::Frame(id)) => Some(Some(Projection::Frame(id))),
                    _ => None,
                }
            }
            Some(ast::ReleaseProjection::Along(d)) => self
                .expr(
                    d,
                    Type::Vector,
                    Place::configuration("the direction a reaction is projected on"),
                )
                .map(|e| Some(Projection::Along(e))),
        }
    }

    /// `along BODY`: the unit vector from the body's centre to the reaction's point, when `d` is
    /// a body's bare name (a body is no value, so the name means nothing else there).
    fn along_body(&self, d: &ast::Expr, point: PointId) -> Option<Projection> {
        let ast::ExprKind::Name(ident) = &d.kind else {
            return None;
        };
        let Some(Target::Body(id)) = self.scope.get(&ident.name).map(|e| e.target) else {
            return None;
        };
        let body = &self.model.bodies[id.index()];
        let at = |p: PointId| crate::model::Expr {
            kind: ExprKind::Point(p),
            span: d.span,
            ty: Type::Vector,
        };
        let direction = crate::model::Expr {
            kind: ExprKind::Binary {
                op: ast::BinaryOp::Sub,
                lhs: Box::new(at(point)),
                rhs: Box::new(at(body.centre)),
            },
            span: d.span,
            ty: Type::Vector,
        };
        Some(Projection::AlongBody {
            body: body.name.name.clone(),
            direction,
        })
    }

    /// `reaction NAME: rolling ROLL normal n`: the rolling constraint's body and contact point.
    fn rolling_release(&mut self, ident: &Ident, spec: &ast::ReleaseSpec, span: Span) {
        let direction = spec
            .direction
            .as_ref()
            .and_then(|d| self.expr(d, Type::Vector, Place::configuration("a contact normal")));
        let Some(Target::Constraint(id)) = self.lookup(&spec.point, NameKind::Constraint) else {
            return;
        };
        let contact = match self.model.constraints[id.index()].kind {
            ConstraintKind::Rolling { contact, .. } => Some(contact),
            _ => None,
        };
        let Some(projection) = self.projection(spec, contact) else {
            return;
        };
        let ConstraintKind::Rolling { body, contact } = self.model.constraints[id.index()].kind
        else {
            self.diagnostics.push(
                Diagnostic::new(
                    DiagnosticKind::NotARollingConstraint {
                        name: spec.point.name.clone(),
                    },
                    spec.point.span,
                )
                .with_help("Name a constraint written `constraint ROLL: rolling BODY at P`."),
            );
            return;
        };
        if let Some(direction) = direction {
            self.model.releases.push(Release {
                name: name(ident),
                word: spec.word,
                point: contact,
                members: vec![ReleaseMember::Body(body)],
                direction: Some(direction),
                constraint: Some(id),
                projection,
                span,
            });
        }
    }

    fn gear_coordinate(&mut self, ident: &Ident) -> Option<CoordinateId> {
        self.used.insert(ident.name.clone());
        self.free_coordinate(ident)
    }
}
