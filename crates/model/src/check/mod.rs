//! The checker: [`Ast`] → [`Model`]. It resolves every name, types every expression, checks
//! each statement's rules (a body needs a mass, an inertia, a frame and a centre; `initial`
//! only for coordinates; …) and reports every problem it finds, not just the first.
//!
//! Declarations are processed in file order and a name is in scope only below its declaration,
//! which gives [`Model`] its ordering invariant and rules out cyclic definitions.

mod expr;
mod scope;

use crate::ast::{self, Ast, Binding, Ident, StatementKind};
use crate::diagnostic::{Diagnostic, DiagnosticKind, NameKind, Type};
use crate::model::*;
use crate::span::Span;

use expr::{rate_degree, ExprChecker, Place};
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

    fn statement(&mut self, statement: &ast::Statement) {
        match &statement.kind {
            StatementKind::Coordinates(names) => {
                for ident in names {
                    let target = Target::Coordinate(CoordinateId(id(self.model.coordinates.len())));
                    if self.declare(ident, NameKind::Coordinate, target, Level::Configuration) {
                        self.model.coordinates.push(Coordinate {
                            name: name(ident),
                            driven: None,
                        });
                    }
                }
            }
            StatementKind::Parameters(bindings) => {
                for Binding { name: ident, value } in bindings {
                    let value = value
                        .as_ref()
                        .map(|v| self.expr(v, Type::Scalar, Place::constant("a parameter value")));
                    if matches!(value, Some(None)) {
                        self.poison(ident, NameKind::Parameter);
                        continue;
                    }
                    let target = Target::Parameter(ParameterId(id(self.model.parameters.len())));
                    if self.declare(ident, NameKind::Parameter, target, Level::Constant) {
                        self.model.parameters.push(Parameter {
                            name: name(ident),
                            value: value.flatten(),
                        });
                    }
                }
            }
            StatementKind::Inputs(bindings) => {
                for Binding { name: ident, value } in bindings {
                    let value = value
                        .as_ref()
                        .map(|v| self.expr(v, Type::Scalar, Place::time("an input value")));
                    if matches!(value, Some(None)) {
                        self.poison(ident, NameKind::Input);
                        continue;
                    }
                    let target = Target::Input(InputId(id(self.model.inputs.len())));
                    if self.declare(ident, NameKind::Input, target, Level::Time) {
                        self.model.inputs.push(Input {
                            name: name(ident),
                            value: value.flatten(),
                        });
                    }
                }
            }
            StatementKind::Constants(bindings) => {
                for Binding { name: ident, value } in bindings {
                    let Some(value) = value
                        .as_ref()
                        .and_then(|v| self.any_expr(v, Place::constant("a constant")))
                    else {
                        self.poison(ident, NameKind::Constant);
                        continue;
                    };
                    let target =
                        Target::Constant(ConstantId(id(self.model.constants.len())), value.ty);
                    if self.declare(ident, NameKind::Constant, target, Level::Constant) {
                        self.model.constants.push(Constant {
                            name: name(ident),
                            value,
                        });
                    }
                }
            }
            StatementKind::Driven(bindings) => {
                for Binding { name: ident, value } in bindings {
                    let Some(value) = value.as_ref().and_then(|v| {
                        self.expr(v, Type::Scalar, Place::time("a driven coordinate's motion"))
                    }) else {
                        self.poison(ident, NameKind::DrivenCoordinate);
                        continue;
                    };
                    let target = Target::Coordinate(CoordinateId(id(self.model.coordinates.len())));
                    if self.declare(ident, NameKind::DrivenCoordinate, target, Level::Time) {
                        self.model.coordinates.push(Coordinate {
                            name: name(ident),
                            driven: Some(value),
                        });
                    }
                }
            }
            StatementKind::Frame {
                name: ident,
                rotation,
            } => self.frame(ident, rotation.as_ref()),
            StatementKind::Point {
                name: ident,
                position,
            } => {
                let Some(position) = self.expr(
                    position,
                    Type::Vector,
                    Place::configuration("a point's position"),
                ) else {
                    self.poison(ident, NameKind::Point);
                    return;
                };
                let target = Target::Point(PointId(id(self.model.points.len())));
                let level = self.level_of(&position);
                if self.declare(ident, NameKind::Point, target, level) {
                    self.point_levels.push(level);
                    self.model.points.push(Point {
                        name: name(ident),
                        position: Some(position),
                    });
                }
            }
            StatementKind::Particle { point, mass } => {
                let target = self.lookup(point, NameKind::Point);
                let mass = self.mass(mass);
                if let (Some(Target::Point(point)), Some(mass)) = (target, mass) {
                    self.model.particles.push(Particle {
                        point,
                        mass,
                        span: statement.span,
                    });
                }
            }
            StatementKind::Body {
                name: ident,
                clauses,
            } => self.body(ident, clauses),
            StatementKind::Gravity(g) => {
                if let Some(g) = self.expr(g, Type::Vector, Place::constant("gravity")) {
                    self.load(Load::Gravity(g), statement.span);
                }
            }
            StatementKind::Spring {
                stiffness,
                connection,
                rest,
            } => {
                let stiffness =
                    self.expr(stiffness, Type::Scalar, Place::time("a spring's stiffness"));
                let connection = self.connection(connection, "a spring's ends");
                let rest = rest
                    .as_ref()
                    .map(|r| self.expr(r, Type::Scalar, Place::time("a spring's rest length")));
                if let (Some(stiffness), Some(connection), None | Some(Some(_))) =
                    (stiffness, connection, &rest)
                {
                    self.load(
                        Load::Spring {
                            stiffness,
                            connection,
                            rest: rest.flatten(),
                        },
                        statement.span,
                    );
                }
            }
            StatementKind::Damper {
                coefficient,
                connection,
            } => {
                let coefficient = self.expr(
                    coefficient,
                    Type::Scalar,
                    Place::time("a damping coefficient"),
                );
                let connection = self.connection(connection, "a damper's ends");
                if let (Some(coefficient), Some(connection)) = (coefficient, connection) {
                    self.load(
                        Load::Damper {
                            coefficient,
                            connection,
                        },
                        statement.span,
                    );
                }
            }
            StatementKind::Dissipation(d) => {
                if let Some(d) = self.expr(d, Type::Scalar, Place::motion("a dissipation function"))
                {
                    if rate_degree(&d).is_none_or(|degree| degree > 2) {
                        self.diagnostics.push(
                            Diagnostic::new(
                                DiagnosticKind::WrongDegreeInRates {
                                    place: "a Rayleigh dissipation function",
                                    requirement: "at most quadratic",
                                },
                                d.span,
                            )
                            .with_help(
                                "Write D = ½ c q'² (a polynomial of degree 2 in the rates).",
                            ),
                        );
                    } else {
                        self.load(Load::Dissipation(d), statement.span);
                    }
                }
            }
            StatementKind::Potential(v) => {
                if let Some(v) = self.expr(v, Type::Scalar, Place::configuration("a potential")) {
                    self.load(Load::Potential(v), statement.span);
                }
            }
            StatementKind::Force { force, point } => {
                let force = self.expr(force, Type::Vector, Place::motion("a force"));
                let point = self.expr(
                    point,
                    Type::Vector,
                    Place::configuration("a point of application"),
                );
                if let (Some(force), Some(point)) = (force, point) {
                    self.load(Load::Force { force, point }, statement.span);
                }
            }
            StatementKind::Couple { moment, body } => {
                let moment = self.expr(moment, Type::Vector, Place::motion("a couple"));
                let body = self.lookup(body, NameKind::Body);
                if let (Some(moment), Some(Target::Body(body))) = (moment, body) {
                    self.load(Load::Couple { moment, body }, statement.span);
                }
            }
            StatementKind::GeneralizedForce { force, coordinate } => {
                let force = self.expr(force, Type::Scalar, Place::motion("a generalized force"));
                let coordinate = self.free_coordinate(coordinate);
                if let (Some(force), Some(coordinate)) = (force, coordinate) {
                    self.load(Load::GeneralizedForce { force, coordinate }, statement.span);
                }
            }
            StatementKind::Constraint { name: ident, spec } => {
                self.constraint(ident.as_ref(), spec, statement.span)
            }
            StatementKind::Reactions(names) => {
                for ident in names {
                    self.reaction(ident);
                }
            }
            StatementKind::Release { name, spec } => self.release(name, spec, statement.span),
            StatementKind::Initial(values) => {
                for value in values {
                    self.initial(value);
                }
            }
            StatementKind::Simulate(settings) => self.simulate(settings, statement.span),
            StatementKind::Output(items) => {
                for item in items {
                    self.output(item);
                }
            }
        }
    }

    /// Warn about coordinates and parameters nothing uses. Only on an otherwise valid model:
    /// after an error, a name may look unused because the line that used it was skipped.
    fn unused(&mut self) {
        for coordinate in &self.model.coordinates {
            if coordinate.driven.is_none() && !self.used.contains(&coordinate.name.name) {
                let name = coordinate.name.name.clone();
                self.diagnostics.push(
                    Diagnostic::warning(DiagnosticKind::UnusedCoordinate { name: name.clone() }, coordinate.name.span)
                        .with_help(format!(
                            "Use `{name}` in a point, a frame or a constraint, or remove it: a coordinate \
                             that nothing depends on has no equation of motion."
                        )),
                );
            }
        }
        let unused: Vec<&Name> = self
            .model
            .parameters
            .iter()
            .map(|p| &p.name)
            .filter(|n| !self.used.contains(&n.name))
            .collect();
        match unused.as_slice() {
            [] => {}
            [one] => self.diagnostics.push(
                Diagnostic::warning(
                    DiagnosticKind::UnusedParameter {
                        name: one.name.clone(),
                    },
                    one.span,
                )
                .with_help(format!(
                    "Remove `{}`, or use it where it was meant to be.",
                    one.name
                )),
            ),
            // One warning for all of them: 5,000 unused parameters were 5,000 warnings, each
            // re-printing the source line (issue 14).
            [first, rest @ ..] => {
                let shown: Vec<String> = unused
                    .iter()
                    .take(MAX_LISTED_NAMES)
                    .map(|n| n.name.clone())
                    .collect();
                let mut diagnostic = Diagnostic::warning(
                    DiagnosticKind::UnusedParameters {
                        more: unused.len() - shown.len(),
                        names: shown,
                    },
                    first.span,
                )
                .with_help("Remove them, or use them where they were meant to be.");
                for other in rest.iter().take(MAX_LISTED_NAMES - 1) {
                    diagnostic = diagnostic.with_related(other.span, "never used");
                }
                self.diagnostics.push(diagnostic);
            }
        }
    }

    fn output(&mut self, item: &ast::OutputItem) {
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

    /// Check a mass: a constant scalar, positive when it can be evaluated.
    fn mass(&mut self, mass: &ast::Expr) -> Option<Expr> {
        let mass = self.expr(mass, Type::Scalar, Place::constant("a mass"))?;
        match self.model.evaluate_constant(&mass) {
            Some(value) if value.is_nan() || value <= 0.0 || !value.is_normal() => {
                self.diagnostics.push(
                    Diagnostic::new(DiagnosticKind::NonPositiveMass { value }, mass.span)
                        .with_help("Give a positive mass (at least 2.2e-308; use other units for smaller ones); a massless point needs no `particle`."),
                );
                None
            }
            _ => Some(mass),
        }
    }

    /// Check that a moment of inertia that can be evaluated is not negative.
    fn moment(&mut self, moment: Option<Expr>) -> Option<Expr> {
        let moment = moment?;
        match self.model.evaluate_constant(&moment) {
            Some(value) if value.is_nan() || value < 0.0 => {
                self.diagnostics.push(
                    Diagnostic::new(DiagnosticKind::NegativeMoment { value }, moment.span)
                        .with_help("Moments of inertia are sums of m·r², never negative."),
                );
                None
            }
            _ => Some(moment),
        }
    }

    fn load(&mut self, load: Load, span: Span) {
        self.model.loads.push(LoadItem { load, span });
    }

    fn gear_coordinate(&mut self, ident: &Ident) -> Option<CoordinateId> {
        self.used.insert(ident.name.clone());
        self.free_coordinate(ident)
    }

    fn free_coordinate(&mut self, ident: &Ident) -> Option<CoordinateId> {
        match self.lookup(ident, NameKind::Coordinate)? {
            Target::Coordinate(id) => Some(id),
            _ => None,
        }
    }

    fn connection(
        &mut self,
        connection: &ast::Connection,
        what: &'static str,
    ) -> Option<Connection> {
        match connection {
            ast::Connection::Points { from, to } => {
                let from = self.expr(from, Type::Vector, Place::configuration(what));
                let to = self.expr(to, Type::Vector, Place::configuration(what));
                Some(Connection::Points {
                    from: from?,
                    to: to?,
                })
            }
            ast::Connection::Scalar(value) => self
                .expr(
                    value,
                    Type::Scalar,
                    Place::configuration("the angle of a torsional element"),
                )
                .map(Connection::Scalar),
        }
    }

    fn frame(&mut self, ident: &Ident, rotation: Option<&(Ident, Vec<ast::Rotation>)>) {
        let target = Target::Frame(FrameId(id(self.model.frames.len())));
        let Some((parent, rotations)) = rotation else {
            if let Some((first_name, first)) = &self.inertial {
                self.diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::SecondInertialFrame { first_name: first_name.clone(), first: *first },
                        ident.span,
                    )
                    .with_related(*first, "the inertial frame")
                    .with_help(format!(
                        "Define `{}` relative to `{first_name}`: `frame {} = {first_name} rotated … about z`.",
                        ident.name, ident.name
                    )),
                );
                self.poison(ident, NameKind::Frame);
                return;
            }
            if self.declare(ident, NameKind::Frame, target, Level::Constant) {
                self.inertial = Some((ident.name.clone(), ident.span));
                self.frame_levels.push(Level::Constant);
                self.model.frames.push(Frame {
                    name: name(ident),
                    rotation: None,
                });
            }
            return;
        };
        let parent = self.lookup(parent, NameKind::Frame);
        let mut checked = Vec::new();
        let mut ok = true;
        for rotation in rotations {
            let angle = self.expr(
                &rotation.angle,
                Type::Scalar,
                Place::configuration("a rotation angle"),
            );
            let axis = Axis::from_name(&rotation.axis.name);
            if axis.is_none() {
                let written = &rotation.axis.name;
                let mut diagnostic = Diagnostic::new(
                    DiagnosticKind::UnknownRotationAxis {
                        axis: written.clone(),
                    },
                    rotation.axis.span,
                );
                diagnostic = match crate::diagnostic::suggest(written, ["x", "y", "z"]) {
                    Some(best) => diagnostic.with_help(format!("Did you mean `{best}`? Rotations are about `x`, `y` or `z`.")),
                    None if written.len() > 1 && written.ends_with(['x', 'y', 'z']) => diagnostic.with_help(format!(
                        "Write only the axis letter, `about {}`: the axis is shared by the frame and its parent.",
                        written.chars().last().unwrap_or('z')
                    )),
                    None => diagnostic.with_help("Rotations are about `x`, `y` or `z`."),
                };
                self.diagnostics.push(diagnostic);
            }
            match (angle, axis) {
                (Some(angle), Some(axis)) => checked.push(Rotation { angle, axis }),
                _ => ok = false,
            }
        }
        match parent {
            Some(Target::Frame(parent)) if ok => {
                let level = checked
                    .iter()
                    .map(|r| self.level_of(&r.angle))
                    .fold(self.frame_level(parent), Level::max);
                if self.declare(ident, NameKind::Frame, target, level) {
                    self.frame_levels.push(level);
                    self.model.frames.push(Frame {
                        name: name(ident),
                        rotation: Some((parent, checked)),
                    });
                }
            }
            _ => self.poison(ident, NameKind::Frame),
        }
    }

    fn body(&mut self, ident: &Ident, clauses: &ast::BodyClauses) {
        let missing = |clause: &'static str, help: String| {
            Diagnostic::new(
                DiagnosticKind::BodyMissing {
                    body: ident.name.clone(),
                    clause,
                },
                ident.span,
            )
            .with_help(help)
        };
        let mut ok = true;
        let mass = match &clauses.mass {
            Some(mass) => self.mass(mass),
            None => {
                self.diagnostics.push(missing(
                    "mass",
                    format!("Add `mass m` to `body {}`.", ident.name),
                ));
                None
            }
        };
        let centre = match &clauses.centre {
            Some(point) => self.lookup(point, NameKind::Point),
            None => {
                self.diagnostics.push(missing(
                    "centre of mass",
                    "Add `at G`, where `G` is the point at its centre of mass.".to_string(),
                ));
                None
            }
        };
        let frame = match &clauses.frame {
            Some(frame) => self.lookup(frame, NameKind::Frame),
            None => {
                self.diagnostics.push(missing(
                    "frame",
                    "Add `frame B`, the frame attached to the body in whose axes the inertia is given.".to_string(),
                ));
                None
            }
        };
        let inertia = match &clauses.inertia {
            Some(inertia) => self.inertia(ident, inertia, centre),
            None => {
                self.diagnostics.push(missing(
                    "inertia",
                    "Add `inertia I1, I2, I3` (principal moments about the centre of mass, in the body frame's axes)."
                        .to_string(),
                ));
                None
            }
        };
        ok &= mass.is_some() && inertia.is_some();
        match (mass, centre, frame, inertia) {
            (
                Some(mass),
                Some(Target::Point(centre)),
                Some(Target::Frame(frame)),
                Some(inertia),
            ) if ok => {
                let target = Target::Body(BodyId(id(self.model.bodies.len())));
                if self.declare(ident, NameKind::Body, target, Level::Configuration) {
                    self.model.bodies.push(Body {
                        name: name(ident),
                        mass,
                        centre,
                        frame,
                        inertia,
                    });
                }
            }
            _ => self.poison(ident, NameKind::Body),
        }
    }

    fn inertia(
        &mut self,
        body: &Ident,
        clause: &ast::InertiaClause,
        centre: Option<Target>,
    ) -> Option<Inertia> {
        let place = Place::constant("a moment of inertia");
        let mut components: [Option<Expr>; 6] = Default::default();
        let mut ok = true;
        let principal = matches!(clause.spec, ast::InertiaSpec::Principal(_));
        match &clause.spec {
            ast::InertiaSpec::Principal(moments) => {
                for (slot, moment) in components.iter_mut().zip(moments) {
                    let checked = self.expr(moment, Type::Scalar, place);
                    *slot = self.moment(checked);
                    ok &= slot.is_some();
                }
            }
            ast::InertiaSpec::Components(pairs) => {
                let mut given = [false; 6];
                for (key, value) in pairs {
                    let index = match key.name.as_str() {
                        "xx" => Some(0),
                        "yy" => Some(1),
                        "zz" => Some(2),
                        "xy" | "yx" => Some(3),
                        "xz" | "zx" => Some(4),
                        "yz" | "zy" => Some(5),
                        _ => None,
                    };
                    let value = self.expr(value, Type::Scalar, place);
                    let Some(index) = index else {
                        let mut diagnostic = Diagnostic::new(
                            DiagnosticKind::UnknownOption {
                                option: key.name.clone(),
                                statement: "inertia",
                            },
                            key.span,
                        );
                        diagnostic = match crate::diagnostic::suggest(
                            &key.name,
                            ["xx", "yy", "zz", "xy", "xz", "yz"],
                        ) {
                            Some(best) => diagnostic.with_help(format!("Did you mean `{best}`?")),
                            None => diagnostic.with_help(
                                "The components are `xx`, `yy`, `zz`, `xy`, `xz` and `yz`.",
                            ),
                        };
                        self.diagnostics.push(diagnostic);
                        ok = false;
                        continue;
                    };
                    if std::mem::replace(&mut given[index], true) {
                        self.diagnostics.push(
                            Diagnostic::new(
                                DiagnosticKind::DuplicateClause {
                                    clause: key.name.clone(),
                                },
                                key.span,
                            )
                            .with_help(
                                "Give each component once (the tensor is symmetric: `xy` is `yx`).",
                            ),
                        );
                        ok = false;
                    }
                    let value = if index < 3 { self.moment(value) } else { value };
                    ok &= value.is_some();
                    if let Some(slot) = components.get_mut(index) {
                        *slot = value;
                    }
                }
                for (index, clause_name) in ["moment `xx`", "moment `yy`", "moment `zz`"]
                    .into_iter()
                    .enumerate()
                {
                    if !given[index] {
                        self.diagnostics.push(
                            Diagnostic::new(
                                DiagnosticKind::BodyMissing { body: body.name.clone(), clause: clause_name },
                                clause.span,
                            )
                            .with_help("Give the three moments `xx`, `yy` and `zz`; products of inertia default to zero."),
                        );
                        ok = false;
                    }
                }
            }
        }
        let about = match &clause.about {
            Some(point) => match self.lookup(point, NameKind::Point) {
                Some(Target::Point(id)) => Some(id),
                _ => None,
            },
            None => match centre {
                Some(Target::Point(id)) => Some(id),
                _ => None,
            },
        };
        if ok {
            Some(Inertia {
                components,
                about: about?,
                principal,
            })
        } else {
            None
        }
    }

    fn constraint(&mut self, ident: Option<&Ident>, spec: &ast::ConstraintSpec, span: Span) {
        let kind = match spec {
            ast::ConstraintSpec::Equation { lhs, rhs } => {
                let place = Place::motion("a constraint");
                let lhs = self.expr(lhs, Type::Scalar, place);
                let rhs = self.expr(rhs, Type::Scalar, place);
                match (lhs, rhs) {
                    (Some(lhs), Some(rhs))
                        if self.level_of(&lhs).max(self.level_of(&rhs)) < Level::Configuration =>
                    {
                        self.diagnostics.push(
                            Diagnostic::new(DiagnosticKind::ConstraintWithoutCoordinates, lhs.span.to(rhs.span))
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

    fn reaction(&mut self, ident: &Ident) {
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

    fn release(&mut self, ident: &Ident, spec: &ast::ReleaseSpec, span: Span) {
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
        if let Some(point) = point {
            if complete {
                self.model.releases.push(Release {
                    name: name(ident),
                    word: spec.word,
                    point,
                    members,
                    direction,
                    constraint: None,
                    span,
                });
            }
        }
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
                span,
            });
        }
    }

    fn initial(&mut self, value: &ast::InitialValue) {
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

    fn simulate(&mut self, settings: &[ast::Setting], span: Span) {
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

    fn finish(&mut self) {
        if !self.diagnostics.iter().any(Diagnostic::is_error) {
            self.unused();
            // Values the file gives that numeric work could not use (`1/0`, an overflowing
            // product) are errors at their place now, not NaNs far downstream. Masses were
            // checked where they were declared.
            let values = self.model.value_diagnostics();
            self.diagnostics.extend(
                values
                    .into_iter()
                    .filter(|d| matches!(d.kind, DiagnosticKind::UnusableValue { .. })),
            );
        }
        let free = self.model.free_coordinates().count();
        if free == 0 && !self.diagnostics.iter().any(Diagnostic::is_error) {
            let span = Span::new(0, 0);
            self.diagnostics.push(
                Diagnostic::new(DiagnosticKind::NoCoordinates, span)
                    .with_help("Declare the generalized coordinates, e.g. `coordinates x, theta`."),
            );
        }
        let constraints = self.model.constraints.len();
        if free > 0 && constraints > free {
            let span = self
                .model
                .constraints
                .get(free)
                .map_or(Span::new(self.end, self.end), |c| c.span);
            self.diagnostics.push(
                Diagnostic::new(DiagnosticKind::TooManyConstraints { constraints, coordinates: free }, span)
                    .with_label("one constraint too many from here on")
                    .with_help("Each constraint removes a degree of freedom: remove redundant constraints or add coordinates."),
            );
        }
    }
}
