//! The checker: [`Ast`] → [`Model`]. It resolves every name, types every expression, checks
//! each statement's rules (a body needs a mass, an inertia, a frame and a centre; `initial`
//! only for coordinates; …) and reports every problem it finds, not just the first.
//!
//! Declarations are processed in file order and a name is in scope only below its declaration,
//! which gives [`Model`] its ordering invariant and rules out cyclic definitions.

mod bodies;
mod constraints;
mod declarations;
mod expr;
mod finish;
mod loads;
mod scope;
mod simulation;

use crate::ast::{self, Ast, Ident, StatementKind};
use crate::diagnostic::{Diagnostic, NameKind, Type};
use crate::model::*;
use crate::span::Span;

use expr::{ExprChecker, Place};
use scope::{Level, Scope, Target};

/// Check a parsed model. Returns the model, or every diagnostic found.
///
/// # Errors
/// The diagnostics, when there is at least one error.
pub fn check(ast: &Ast) -> Result<Model, Vec<Diagnostic>> {
    let mut checker = Checker {
        scope: Scope::new(ast),
        diagnostics: Vec::new(),
        model: Model {
            coordinates: Vec::new(),
            parameters: Vec::new(),
            inputs: Vec::new(),
            constants: Vec::new(),
            frames: Vec::new(),
            points: vec![Point {
                name: Name {
                    name: "origin".to_string(),
                    span: Span::default(),
                },
                position: None,
            }],
            particles: Vec::new(),
            bodies: Vec::new(),
            loads: Vec::new(),
            constraints: Vec::new(),
            reactions: Vec::new(),
            releases: Vec::new(),
            initial: Vec::new(),
            simulation: None,
            outputs: Vec::new(),
            prose: crate::model::Prose::default(),
            warnings: Vec::new(),
            declarations: Vec::new(),
        },
        inertial: None,
        end: ast.statements.last().map_or(0, |s| s.span.end),
        point_levels: vec![Level::Constant],
        frame_levels: Vec::new(),
        used: std::collections::HashSet::new(),
    };
    for statement in &ast.statements {
        checker.statement(statement);
    }
    checker.finish();
    if checker.diagnostics.iter().any(Diagnostic::is_error) {
        Err(checker.diagnostics)
    } else {
        let mut model = checker.model;
        model.warnings = checker.diagnostics;
        Ok(model)
    }
}

struct Checker {
    scope: Scope,
    diagnostics: Vec<Diagnostic>,
    model: Model,
    inertial: Option<(String, Span)>,
    end: usize,
    /// The level of each point and frame, by id, computed once at its declaration: looking
    /// it up instead of recursing through the chain of definitions keeps the stack flat
    /// however long the chain is.
    point_levels: Vec<Level>,
    frame_levels: Vec<Level>,
    /// Every name used in an expression (or as a gear's coordinate).
    used: std::collections::HashSet<String>,
}

/// How many names a grouped warning lists (and points at) before "and N more".
const MAX_LISTED_NAMES: usize = 8;

fn id(len: usize) -> u32 {
    // A model file cannot have 2³² declarations of one kind (it would be > 4 GB).
    u32::try_from(len).unwrap_or(u32::MAX)
}

fn name(ident: &Ident) -> Name {
    Name {
        name: ident.name.clone(),
        span: ident.span,
    }
}

impl Checker {
    fn expr(&mut self, expr: &ast::Expr, ty: Type, place: Place) -> Option<Expr> {
        ExprChecker {
            scope: &self.scope,
            used: &mut self.used,
            diagnostics: &mut self.diagnostics,
            place,
        }
        .expect(expr, ty)
    }

    fn any_expr(&mut self, expr: &ast::Expr, place: Place) -> Option<Expr> {
        ExprChecker {
            scope: &self.scope,
            used: &mut self.used,
            diagnostics: &mut self.diagnostics,
            place,
        }
        .check(expr)
    }

    fn lookup(&mut self, ident: &Ident, kind: NameKind) -> Option<Target> {
        self.scope
            .expect_kind(ident, kind, &mut self.diagnostics)
            .map(|entry| entry.target)
    }

    fn declare(&mut self, ident: &Ident, kind: NameKind, target: Target, level: Level) -> bool {
        let declared = self
            .scope
            .declare(ident, kind, target, level, &mut self.diagnostics);
        if declared {
            // The caller pushes the declaration's data right after a successful `declare`, so
            // the id in `target` is the one it gets.
            let declaration = match target {
                Target::Coordinate(id) => Some(Declaration::Coordinate(id)),
                Target::Parameter(id) => Some(Declaration::Parameter(id)),
                Target::Input(id) => Some(Declaration::Input(id)),
                Target::Constant(id, _) => Some(Declaration::Constant(id)),
                Target::Frame(id) => Some(Declaration::Frame(id)),
                Target::Point(id) => Some(Declaration::Point(id)),
                Target::Body(id) => Some(Declaration::Body(id)),
                Target::Constraint(id) => Some(Declaration::Constraint(id)),
                Target::Poisoned => None,
            };
            self.model.declarations.extend(declaration);
        }
        declared
    }

    /// Declare a name whose definition failed, so that its uses are not reported again.
    fn poison(&mut self, ident: &Ident, kind: NameKind) {
        self.declare(ident, kind, Target::Poisoned, Level::Configuration);
    }

    /// The highest level of any name in `expr` (for frames, points and constants).
    fn level_of(&self, expr: &Expr) -> Level {
        match &expr.kind {
            ExprKind::Time | ExprKind::Input(_) => Level::Time,
            ExprKind::Coordinate(id) | ExprKind::Rate(id) => {
                if self
                    .model
                    .coordinates
                    .get(id.index())
                    .is_some_and(|c| c.driven.is_some())
                {
                    Level::Time
                } else {
                    Level::Configuration
                }
            }
            ExprKind::Point(id) => self.point_level(*id),
            ExprKind::UnitVector { frame, .. } => self.frame_level(*frame),
            ExprKind::Constant(_)
            | ExprKind::Parameter(_)
            | ExprKind::Number { .. }
            | ExprKind::Pi => Level::Constant,
            ExprKind::Neg(e) => self.level_of(e),
            ExprKind::Binary { lhs, rhs, .. } => self.level_of(lhs).max(self.level_of(rhs)),
            ExprKind::Call { args, .. } => args
                .iter()
                .map(|a| self.level_of(a))
                .max()
                .unwrap_or(Level::Constant),
        }
    }

    fn point_level(&self, id: PointId) -> Level {
        self.point_levels
            .get(id.index())
            .copied()
            .unwrap_or(Level::Configuration)
    }

    fn frame_level(&self, id: FrameId) -> Level {
        self.frame_levels
            .get(id.index())
            .copied()
            .unwrap_or(Level::Configuration)
    }

    fn free_coordinate(&mut self, ident: &Ident) -> Option<CoordinateId> {
        match self.lookup(ident, NameKind::Coordinate)? {
            Target::Coordinate(id) => Some(id),
            _ => None,
        }
    }
    fn statement(&mut self, statement: &ast::Statement) {
        let span = statement.span;
        match &statement.kind {
            StatementKind::Coordinates(names) => self.coordinates(names),
            StatementKind::Parameters(bindings) => self.parameters(bindings),
            StatementKind::Inputs(bindings) => self.inputs(bindings),
            StatementKind::Constants(bindings) => self.constants(bindings),
            StatementKind::Driven(bindings) => self.driven(bindings),
            StatementKind::Frame {
                name: ident,
                rotation,
            } => self.frame(ident, rotation.as_ref()),
            StatementKind::Point {
                name: ident,
                position,
            } => self.point(ident, position),
            StatementKind::Particle { point, mass } => self.particle(point, mass, span),
            StatementKind::Body {
                name: ident,
                clauses,
            } => self.body(ident, clauses),
            StatementKind::Gravity(g) => self.gravity(g, span),
            StatementKind::Spring {
                stiffness,
                connection,
                rest,
            } => self.spring(stiffness, connection, rest.as_ref(), span),
            StatementKind::Damper {
                coefficient,
                connection,
            } => self.damper(coefficient, connection, span),
            StatementKind::Dissipation(d) => self.dissipation(d, span),
            StatementKind::Potential(v) => self.potential(v, span),
            StatementKind::Force { force, point } => self.force(force, point, span),
            StatementKind::Couple { moment, body } => self.couple(moment, body, span),
            StatementKind::GeneralizedForce { force, coordinate } => {
                self.generalized_force(force, coordinate, span)
            }
            StatementKind::Constraint { name: ident, spec } => {
                self.constraint(ident.as_ref(), spec, span)
            }
            StatementKind::Reactions(names) => {
                for ident in names {
                    self.reaction(ident);
                }
            }
            StatementKind::Release { name, spec } => self.release(name, spec, span),
            StatementKind::Initial(values) => {
                for value in values {
                    self.initial(value);
                }
            }
            StatementKind::Simulate(settings) => self.simulate(settings, span),
            StatementKind::Output(items) => {
                for item in items {
                    self.output(item);
                }
            }
            StatementKind::Title(text) => self.title(text, span),
            StatementKind::Problem(text) => self.model.prose.problem.push(text.clone()),
            StatementKind::Note(text) => self.model.prose.notes.push(text.clone()),
        }
    }
}
