//! Lowering: a checked [`Model`] → the mechanics' [`mechanics::System`], every expression a
//! `cas` expression in inertial components.
//!
//! Parameters and inputs without a time-dependent value stay symbols (their values are
//! defaults for simulation); constants and time-dependent inputs are substituted; driven
//! coordinates are replaced by their motion `q = f(t)` (and `q̇` by `ḟ`).

use cas::{Expr as Cx, Number};
use mechanics::{
    rotation_about, Constraint as MConstraint, ConstraintForm, Load as MLoad, Particle, RigidBody,
    Rotation, System, Vector,
};

use crate::ast::BinaryOp;
use crate::model::{
    Axis, Connection, ConstraintKind, Declaration, Expr, ExprKind, Function, Load, Model,
};
use crate::span::Span;

/// Why a model could not be lowered.
#[derive(Debug, thiserror::Error, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum LowerError {
    /// An expression has the wrong shape (a vector where a scalar is needed or the reverse).
    #[error("a {expected} was expected here")]
    Shape {
        /// Where.
        span: Span,
        /// `"scalar"` or `"vector"`.
        expected: &'static str,
    },
    /// A reference to something not lowered yet (the model's declarations are out of order).
    #[error("a reference to a declaration that is not available here")]
    Unresolved {
        /// Where.
        span: Span,
    },
    /// A reaction's normal or rope direction that is the zero vector.
    #[error(
        "this direction is the zero vector: a contact normal or a rope's direction must not vanish"
    )]
    ZeroDirection {
        /// Where.
        span: Span,
    },
    /// A reaction's released bodies are moved by a coordinate that also moves bodies or
    /// particles not released, other than through the reaction's point (a rope over a pulley
    /// built into the coordinates): the force those exert on the released ones would be
    /// missing from the reaction, which is refused rather than given partial.
    #[error("reaction `{reaction}`: `{coordinate}` moves the released {} relative to the reaction's point and also moves {} (not released): the force {} on the released {} through `{coordinate}` (a rope, a gear or a link built into the coordinates) would be missing from the reaction, so it is not given; release {} together with {}, or keep that connection as a constraint", quoted(.members), quoted(.others), if .others.len() == 1 { "that one exerts" } else { "those exert" }, if .members.len() == 1 { "one" } else { "ones" }, quoted(.others), quoted(.members))]
    UnreleasedLoad {
        /// Where: the reaction's statement.
        span: Span,
        /// The reaction.
        reaction: String,
        /// The released bodies and particles.
        members: Vec<String>,
        /// The coordinate that moves both.
        coordinate: String,
        /// The bodies and particles not released that it moves.
        others: Vec<String>,
    },
    /// A divisor (or the base of a negative power) that is exactly zero.
    #[error(
        "division by zero: this divisor is zero, so the expression has no value; mend the divisor"
    )]
    DivisionByZero {
        /// Where: the divisor.
        span: Span,
    },
}

impl LowerError {
    /// Where in the model file.
    #[must_use]
    pub fn span(&self) -> Span {
        match self {
            LowerError::Shape { span, .. }
            | LowerError::Unresolved { span }
            | LowerError::ZeroDirection { span }
            | LowerError::UnreleasedLoad { span, .. }
            | LowerError::DivisionByZero { span } => *span,
        }
    }
}

/// `a`, `b` and `c`, each in backticks.
fn quoted(names: &[String]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    match quoted.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => quoted.concat(),
    }
}

/// A lowered value.
#[derive(Clone, Copy, Debug)]
enum Value {
    Scalar(Cx),
    Vector(Vector),
}

/// A release for a reaction (see `crate::reactions`): the members' points are displaced by
/// `displacement` (a combination of the extra coordinates), and a constraint may be dropped.
#[derive(Clone, Debug, Default)]
pub(crate) struct Shift {
    /// Points moved with the members: particles' points and bodies' centres.
    pub points: Vec<crate::model::PointId>,
    /// Indices of released particles (for a particle at `origin`).
    pub particles: Vec<usize>,
    /// Released bodies (for a body centred at `origin`).
    pub bodies: Vec<crate::model::BodyId>,
    /// The displacement, in inertial components.
    pub displacement: Option<Vector>,
    /// The extra coordinates.
    pub coordinates: Vec<String>,
    /// A constraint left out.
    pub dropped: Option<crate::model::ConstraintId>,
    /// A driven coordinate lowered as a free one.
    pub freed: Option<crate::model::CoordinateId>,
    /// For a clamp: the small rotation `ψ` (components in the extra coordinates) and the pivot
    /// `P` it turns the members about. Every position attached to the members then becomes
    /// `r₀ + u + ψ × (r₀ − P)` and their bodies' rotations `(1 + ψ×) R`.
    pub rotation: Option<(Vector, Vector)>,
}

fn cross(a: &Vector, b: &Vector) -> Vector {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn shifted(v: Vector, by: Option<&Vector>) -> Vector {
    match by {
        Some(d) => [v[0] + d[0], v[1] + d[1], v[2] + d[2]],
        None => v,
    }
}

struct Lowerer<'m> {
    model: &'m Model,
    shift: Shift,
    coordinates: Vec<Option<(Cx, Cx)>>,
    constants: Vec<Option<Value>>,
    inputs: Vec<Option<Cx>>,
    frames: Vec<Option<Rotation>>,
    points: Vec<Option<Vector>>,
}

fn identity() -> Rotation {
    rotation_about(3, Cx::zero())
}

fn matmul(a: &Rotation, b: &Rotation) -> Rotation {
    let mut out = identity();
    for (i, row) in out.iter_mut().enumerate() {
        for (j, entry) in row.iter_mut().enumerate() {
            *entry = (0..3).map(|k| a[i][k] * b[k][j]).sum::<Cx>().normal();
        }
    }
    out
}

fn axis_index(axis: Axis) -> usize {
    match axis {
        Axis::X => 0,
        Axis::Y => 1,
        Axis::Z => 2,
    }
}

impl Lowerer<'_> {
    /// `v` moved rigidly with the members when it is attached to them (depends on the
    /// displacement) and the release has a rotation; `v` otherwise.
    fn rigid(&self, v: Vector) -> Vector {
        let Some((psi, pivot)) = self.shift.rotation.as_ref() else {
            return v;
        };
        if !self.moves(&v) {
            return v;
        }
        let zero = self.at_rest();
        let r0 = v.map(|x| x.subs(&zero).normal());
        let d: Vector = [r0[0] - pivot[0], r0[1] - pivot[1], r0[2] - pivot[2]];
        let turn = cross(psi, &d);
        let by = self
            .shift
            .displacement
            .unwrap_or([Cx::zero(), Cx::zero(), Cx::zero()]);
        [0, 1, 2].map(|k| (r0[k] + by[k] + turn[k]).normal())
    }

    /// Every extra coordinate set to zero.
    fn at_rest(&self) -> Vec<(Cx, Cx)> {
        self.shift
            .coordinates
            .iter()
            .map(|u| (Cx::coordinate(u), Cx::zero()))
            .collect()
    }

    /// Whether `v` depends on a released displacement.
    fn moves(&self, v: &Vector) -> bool {
        let symbols: Vec<cas::Symbol> = self
            .shift
            .coordinates
            .iter()
            .filter_map(|u| Cx::coordinate(u).as_symbol())
            .collect();
        v.iter()
            .any(|x| symbols.iter().any(|s| !x.diff(*s).is_zero()))
    }

    fn scalar(&self, e: &Expr) -> Result<Cx, LowerError> {
        match self.expr(e)? {
            Value::Scalar(x) => Ok(x),
            Value::Vector(_) => Err(LowerError::Shape {
                span: e.span,
                expected: "scalar",
            }),
        }
    }

    fn vector(&self, e: &Expr) -> Result<Vector, LowerError> {
        match self.expr(e)? {
            Value::Vector(v) => Ok(v),
            Value::Scalar(_) => Err(LowerError::Shape {
                span: e.span,
                expected: "vector",
            }),
        }
    }

    /// A model expression as a `cas` scalar or vector.
    fn expr(&self, e: &Expr) -> Result<Value, LowerError> {
        let shape = |expected| LowerError::Shape {
            span: e.span,
            expected,
        };
        Ok(match &e.kind {
            ExprKind::Number { text, value } => Value::Scalar(
                Number::parse_literal(text).map_or_else(|_| Cx::float(*value), Cx::number),
            ),
            ExprKind::Time => Value::Scalar(Cx::time()),
            ExprKind::Pi => Value::Scalar(Cx::pi()),
            ExprKind::Neg(x) => match self.expr(x)? {
                Value::Scalar(s) => Value::Scalar(-s),
                Value::Vector(v) => Value::Vector(v.map(|c| -c)),
            },
            ExprKind::Binary { op, lhs, rhs } => {
                let (l, r) = (self.expr(lhs)?, self.expr(rhs)?);
                if divides_by_zero(*op, l, r) {
                    let span = if *op == BinaryOp::Pow {
                        lhs.span
                    } else {
                        rhs.span
                    };
                    return Err(LowerError::DivisionByZero { span });
                }
                binary(*op, l, r).map_err(shape)?
            }
            ExprKind::Call { function, args } => {
                let vals = args
                    .iter()
                    .map(|a| self.expr(a))
                    .collect::<Result<Vec<_>, _>>()?;
                call(*function, &vals).map_err(shape)?
            }
            ExprKind::Coordinate(_)
            | ExprKind::Rate(_)
            | ExprKind::Parameter(_)
            | ExprKind::Input(_)
            | ExprKind::Constant(_)
            | ExprKind::Point(_)
            | ExprKind::UnitVector { .. } => self.reference(e)?,
        })
    }

    /// The value of a reference to a declaration, lowered earlier.
    fn reference(&self, e: &Expr) -> Result<Value, LowerError> {
        let unresolved = LowerError::Unresolved { span: e.span };
        let coordinate = |id: &crate::model::CoordinateId| {
            self.coordinates
                .get(id.index())
                .copied()
                .flatten()
                .ok_or(unresolved.clone())
        };
        Ok(match &e.kind {
            ExprKind::Coordinate(id) => Value::Scalar(coordinate(id)?.0),
            ExprKind::Rate(id) => Value::Scalar(coordinate(id)?.1),
            ExprKind::Parameter(id) => {
                Value::Scalar(Cx::symbol(&self.model.parameter(*id).name.name))
            }
            ExprKind::Input(id) => Value::Scalar(
                self.inputs
                    .get(id.index())
                    .copied()
                    .flatten()
                    .ok_or(unresolved)?,
            ),
            ExprKind::Constant(id) => self
                .constants
                .get(id.index())
                .copied()
                .flatten()
                .ok_or(unresolved)?,
            ExprKind::Point(id) => Value::Vector(
                self.points
                    .get(id.index())
                    .copied()
                    .flatten()
                    .ok_or(unresolved)?,
            ),
            ExprKind::UnitVector { frame, axis } => {
                let r = self
                    .frames
                    .get(frame.index())
                    .copied()
                    .flatten()
                    .ok_or(unresolved)?;
                let k = axis_index(*axis);
                Value::Vector([r[0][k], r[1][k], r[2][k]])
            }
            // Not a reference: `expr` lowers everything else.
            _ => return Err(unresolved),
        })
    }
}

/// `a / 0`, or `0^k` with `k < 0`: a divisor that the constructors fold to zero (`0`, `2 - 2`,
/// `x - x`) has no value to give, whatever the rest of the model does with it.
fn divides_by_zero(op: BinaryOp, lhs: Value, rhs: Value) -> bool {
    match (op, lhs, rhs) {
        (BinaryOp::Div, _, Value::Scalar(b)) => b.is_literal_zero(),
        (BinaryOp::Pow, Value::Scalar(a), Value::Scalar(k)) => {
            a.is_literal_zero() && k.as_number().is_some_and(Number::is_negative)
        }
        _ => false,
    }
}

/// A binary operation on lowered operands; `Err` names the shape an operand should have had.
fn binary(op: BinaryOp, lhs: Value, rhs: Value) -> Result<Value, &'static str> {
    Ok(match (op, lhs, rhs) {
        (BinaryOp::Add, Value::Scalar(a), Value::Scalar(b)) => Value::Scalar(a + b),
        (BinaryOp::Sub, Value::Scalar(a), Value::Scalar(b)) => Value::Scalar(a - b),
        (BinaryOp::Mul, Value::Scalar(a), Value::Scalar(b)) => Value::Scalar(a * b),
        (BinaryOp::Div, Value::Scalar(a), Value::Scalar(b)) => Value::Scalar(a / b),
        (BinaryOp::Pow, Value::Scalar(a), Value::Scalar(b)) => {
            match b.as_number().and_then(Number::to_i64) {
                Some(k) => Value::Scalar(a.powi(k)),
                None => Value::Scalar(a.pow(b)),
            }
        }
        (BinaryOp::Add, Value::Vector(a), Value::Vector(b)) => {
            Value::Vector([a[0] + b[0], a[1] + b[1], a[2] + b[2]])
        }
        (BinaryOp::Sub, Value::Vector(a), Value::Vector(b)) => {
            Value::Vector([a[0] - b[0], a[1] - b[1], a[2] - b[2]])
        }
        (BinaryOp::Mul, Value::Scalar(s), Value::Vector(v))
        | (BinaryOp::Mul, Value::Vector(v), Value::Scalar(s)) => Value::Vector(v.map(|c| s * c)),
        (BinaryOp::Div, Value::Vector(v), Value::Scalar(s)) => Value::Vector(v.map(|c| c / s)),
        (_, Value::Vector(_), _) | (_, _, Value::Vector(_)) => return Err("scalar"),
    })
}

/// A built-in function applied to lowered arguments; `Err` names the shape an argument should
/// have had.
fn call(function: Function, args: &[Value]) -> Result<Value, &'static str> {
    Ok(match (function, args) {
        (Function::Dot, [Value::Vector(u), Value::Vector(v)]) => {
            Value::Scalar(u[0] * v[0] + u[1] * v[1] + u[2] * v[2])
        }
        (Function::Cross, [Value::Vector(u), Value::Vector(v)]) => Value::Vector(cross(u, v)),
        (Function::Norm, [Value::Vector(v)]) => {
            Value::Scalar((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        }
        // The total time derivative of each inertial component: a point's velocity.
        (Function::Vel, [Value::Vector(v)]) => Value::Vector(v.map(Cx::dt)),
        (f, [Value::Scalar(x)]) => Value::Scalar(match f {
            Function::Sin => x.sin(),
            Function::Cos => x.cos(),
            Function::Tan => x.tan(),
            Function::Asin => x.asin(),
            Function::Acos => x.acos(),
            Function::Atan => x.atan(),
            Function::Exp => x.exp(),
            Function::Ln => x.ln(),
            Function::Sqrt => x.sqrt(),
            Function::Abs => x.abs(),
            Function::Sign => x.sign(),
            _ => return Err("vector"),
        }),
        (Function::Atan2, [Value::Scalar(y), Value::Scalar(x)]) => Value::Scalar(Cx::atan2(*y, *x)),
        _ => return Err("scalar"),
    })
}

/// Lowers a checked model to the mechanics' input, one pass over the declarations in file
/// order. Inertia given `about` a point other than the centre of mass is moved to the centre
/// of mass with the parallel-axis theorem `I_G = I_P − m ((r·r) 1 − r ⊗ r)`, `r = G − P` in
/// body axes.
///
/// # Errors
/// A [`LowerError`] with the span of the offending expression.
pub fn lower(model: &Model) -> Result<System, LowerError> {
    lower_with(model, Shift::default())
}

/// [`lower`], with the members of a release displaced (see [`Shift`]).
pub(crate) fn lower_with(model: &Model, shift: Shift) -> Result<System, LowerError> {
    lower_parts(model, shift).map(|parts| parts.0)
}

/// The points' positions and the frames' rotations of a lowering, by id (`None`: not lowered).
pub(crate) type Geometry = (Vec<Option<Vector>>, Vec<Option<Rotation>>);

/// [`lower_with`], also returning the points and frames.
pub(crate) fn lower_parts(model: &Model, shift: Shift) -> Result<(System, Geometry), LowerError> {
    let mut l = Lowerer::new(model, shift);
    let mut system = System::new();
    let mut indices = Indices {
        coordinates: vec![None; model.coordinates().len()],
        bodies: vec![None; model.bodies().len()],
    };
    for declaration in model.declarations() {
        l.declaration(&mut system, &mut indices, *declaration)?;
    }
    for u in &l.shift.coordinates {
        system.add_coordinate(u);
    }
    lower_particles(&l, &mut system)?;
    for item in model.loads() {
        if let Some(load) = lower_load(&l, &indices, item)? {
            system.add_load(load);
        }
    }
    for (index, c) in model.constraints().iter().enumerate() {
        if l.shift.dropped.is_some_and(|d| d.index() == index) {
            continue;
        }
        let name = c
            .name
            .as_ref()
            .map_or_else(|| "constraint".to_string(), |n| n.name.clone());
        let equations = constraint_equations(&l, c)?;
        system.add_constraint(MConstraint { name, equations });
    }
    Ok((system, (l.points, l.frames)))
}

/// The system's indices of the free coordinates and of the bodies, by model id (`None`:
/// driven, or not lowered yet).
struct Indices {
    coordinates: Vec<Option<usize>>,
    bodies: Vec<Option<usize>>,
}

impl<'m> Lowerer<'m> {
    /// Nothing lowered yet but `origin`, the first point.
    fn new(model: &'m Model, shift: Shift) -> Self {
        let mut l = Lowerer {
            model,
            shift,
            coordinates: vec![None; model.coordinates().len()],
            constants: vec![None; model.constants().len()],
            inputs: vec![None; model.inputs().len()],
            frames: vec![None; model.frames().len()],
            points: vec![None; model.points().len()],
        };
        if let Some(origin) = l.points.get_mut(0) {
            *origin = Some([Cx::zero(), Cx::zero(), Cx::zero()]);
        }
        l
    }

    /// Lowers one declaration into `system`, keeping its value for later references.
    fn declaration(
        &mut self,
        system: &mut System,
        indices: &mut Indices,
        declaration: Declaration,
    ) -> Result<(), LowerError> {
        let model = self.model;
        match declaration {
            Declaration::Coordinate(id) => {
                let (value, index) = self.coordinate(system, id)?;
                indices.coordinates[id.index()] = index;
                self.coordinates[id.index()] = Some(value);
            }
            Declaration::Parameter(id) => {
                let p = model.parameter(id);
                let value = p.value.as_ref().map(|v| self.scalar(v)).transpose()?;
                system.add_parameter(&p.name.name, value);
            }
            Declaration::Input(id) => {
                self.inputs[id.index()] = Some(self.input(system, id)?);
            }
            Declaration::Constant(id) => {
                let value = self.expr(&model.constant(id).value)?;
                if let Value::Scalar(x) = &value {
                    system.add_constant(&model.constant(id).name.name, *x);
                }
                self.constants[id.index()] = Some(value);
            }
            Declaration::Frame(id) => {
                self.frames[id.index()] = Some(self.frame(id)?);
            }
            Declaration::Point(id) => {
                if let Some(position) = &model.point(id).position {
                    let v = self.point(id, position)?;
                    system.add_point(&model.point(id).name.name, v);
                    self.points[id.index()] = Some(v);
                }
            }
            Declaration::Body(id) => {
                indices.bodies[id.index()] = Some(lower_body(self, system, model.body(id))?);
            }
            Declaration::Constraint(_) => {}
        }
        Ok(())
    }

    /// A coordinate's value and rate, and its index in `system` when it is free (not driven,
    /// or freed by the release).
    fn coordinate(
        &self,
        system: &mut System,
        id: crate::model::CoordinateId,
    ) -> Result<((Cx, Cx), Option<usize>), LowerError> {
        let c = self.model.coordinate(id);
        let name = &c.name.name;
        let driven = c.driven.as_ref().filter(|_| self.shift.freed != Some(id));
        Ok(match driven {
            Some(motion) => {
                let f = self.scalar(motion)?;
                system.add_driven(name, f);
                ((f, f.dt()), None)
            }
            None => {
                let index = system.add_coordinate(name);
                ((Cx::coordinate(name), Cx::rate(name, 1)), Some(index))
            }
        })
    }

    /// An input's value: a time-dependent value substituted, otherwise its symbol (with the
    /// value, if any, as the simulation's default).
    fn input(&self, system: &mut System, id: crate::model::InputId) -> Result<Cx, LowerError> {
        let input = self.model.input(id);
        let symbol = Cx::symbol(&input.name.name);
        Ok(match &input.value {
            Some(v) => {
                let x = self.scalar(v)?;
                let timed = Cx::time().as_symbol().is_some_and(|t| !x.diff(t).is_zero());
                if timed {
                    x
                } else {
                    system.add_input(&input.name.name, Some(x));
                    symbol
                }
            }
            None => {
                system.add_input(&input.name.name, None);
                symbol
            }
        })
    }

    /// A frame's rotation: its parent's, turned by each of its rotations in order.
    fn frame(&self, id: crate::model::FrameId) -> Result<Rotation, LowerError> {
        let frame = self.model.frame(id);
        let Some((parent, rotations)) = &frame.rotation else {
            return Ok(identity());
        };
        let mut r =
            self.frames
                .get(parent.index())
                .copied()
                .flatten()
                .ok_or(LowerError::Unresolved {
                    span: frame.name.span,
                })?;
        for rotation in rotations {
            let angle = self.scalar(&rotation.angle)?;
            r = matmul(&r, &rotation_about(axis_index(rotation.axis), angle));
        }
        Ok(r)
    }

    /// A point's position, moved with the release's members when it is one of them.
    fn point(&self, id: crate::model::PointId, position: &Expr) -> Result<Vector, LowerError> {
        let mut v = self.vector(position)?;
        // A point defined from a released point already moves with it.
        if self.shift.points.contains(&id) && !self.moves(&v) {
            v = shifted(v, self.shift.displacement.as_ref());
        }
        Ok(self.rigid(v.map(Cx::normal)))
    }
}

/// Adds the model's particles, displacing the released ones at `origin`.
fn lower_particles(l: &Lowerer<'_>, system: &mut System) -> Result<(), LowerError> {
    for (index, p) in l.model.particles().iter().enumerate() {
        let mut position = l
            .points
            .get(p.point.index())
            .copied()
            .flatten()
            .ok_or(LowerError::Unresolved { span: p.span })?;
        // `origin` is shared by everything, so a particle there is displaced here.
        if p.point.index() == 0 && l.shift.particles.contains(&index) {
            position = l.rigid(shifted(position, l.shift.displacement.as_ref()));
        }
        system.add_particle(Particle {
            name: l.model.point(p.point).name.name.clone(),
            mass: l.scalar(&p.mass)?,
            position,
        });
    }
    Ok(())
}

/// One load in the mechanics' terms; `None` for a load that does no virtual work.
fn lower_load(
    l: &Lowerer<'_>,
    indices: &Indices,
    item: &crate::model::LoadItem,
) -> Result<Option<MLoad>, LowerError> {
    Ok(Some(match &item.load {
        Load::Gravity(g) => MLoad::Gravity(l.vector(g)?),
        Load::Spring {
            stiffness,
            connection,
            rest,
        } => MLoad::Potential(spring_potential(l, stiffness, connection, rest.as_ref())?),
        Load::Damper {
            coefficient,
            connection,
        } => MLoad::Dissipation(damper_dissipation(l, coefficient, connection)?),
        Load::Dissipation(d) => MLoad::Dissipation(l.scalar(d)?),
        Load::Potential(v) => MLoad::Potential(l.scalar(v)?),
        Load::Force { force, point } => MLoad::Force {
            force: l.vector(force)?,
            point: l.rigid(l.vector(point)?),
        },
        Load::Couple { moment, body } => MLoad::Couple {
            moment: l.vector(moment)?,
            body: indices
                .bodies
                .get(body.index())
                .copied()
                .flatten()
                .ok_or(LowerError::Unresolved { span: item.span })?,
        },
        Load::GeneralizedForce { force, coordinate } => {
            let f = l.scalar(force)?;
            match indices
                .coordinates
                .get(coordinate.index())
                .copied()
                .flatten()
            {
                Some(j) => MLoad::GeneralizedForce {
                    force: f,
                    coordinate: j,
                },
                // A generalized force on a driven coordinate does no virtual work.
                None => return Ok(None),
            }
        }
    }))
}

/// A spring's potential `k (ℓ − r)² / 2`.
fn spring_potential(
    l: &Lowerer<'_>,
    stiffness: &Expr,
    connection: &Connection,
    rest: Option<&Expr>,
) -> Result<Cx, LowerError> {
    let k = l.scalar(stiffness)?;
    let rest = rest.map(|r| l.scalar(r)).transpose()?;
    let rest = rest.filter(|r| !r.is_zero());
    Ok(match connection {
        Connection::Points { from, to } => {
            let (a, b) = (l.rigid(l.vector(from)?), l.rigid(l.vector(to)?));
            let d: Vector = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            match rest {
                // With no rest length the potential stays polynomial.
                None => k * d2 / 2,
                Some(r) => k * (d2.sqrt() - r).powi(2) / 2,
            }
        }
        Connection::Scalar(s) => {
            let s = l.scalar(s)?;
            k * (s - rest.unwrap_or_else(Cx::zero)).powi(2) / 2
        }
    })
}

/// A damper's dissipation function `c ℓ̇² / 2`.
fn damper_dissipation(
    l: &Lowerer<'_>,
    coefficient: &Expr,
    connection: &Connection,
) -> Result<Cx, LowerError> {
    let c = l.scalar(coefficient)?;
    let rate2 = match connection {
        Connection::Points { from, to } => {
            let (a, b) = (l.rigid(l.vector(from)?), l.rigid(l.vector(to)?));
            let d: Vector = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let dd: Vector = d.map(Cx::dt);
            let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            let along = d[0] * dd[0] + d[1] * dd[1] + d[2] * dd[2];
            along.powi(2) / d2
        }
        Connection::Scalar(s) => l.scalar(s)?.dt().powi(2),
    };
    Ok(c * rate2 / 2)
}

/// A constraint's equations.
fn constraint_equations(
    l: &Lowerer<'_>,
    c: &crate::model::Constraint,
) -> Result<Vec<ConstraintForm>, LowerError> {
    Ok(match &c.kind {
        ConstraintKind::Holonomic { lhs, rhs } => {
            vec![ConstraintForm::Holonomic(l.scalar(lhs)? - l.scalar(rhs)?)]
        }
        ConstraintKind::Velocity { lhs, rhs } => {
            vec![ConstraintForm::Velocity(l.scalar(lhs)? - l.scalar(rhs)?)]
        }
        ConstraintKind::Gear {
            driver,
            driven,
            ratio,
        } => {
            let rate = |id: crate::model::CoordinateId| {
                l.coordinates
                    .get(id.index())
                    .copied()
                    .flatten()
                    .map(|x| x.1)
                    .ok_or(LowerError::Unresolved { span: c.span })
            };
            vec![ConstraintForm::Velocity(
                rate(*driven)? - l.scalar(ratio)? * rate(*driver)?,
            )]
        }
        ConstraintKind::Rolling { body, contact } => rolling_equations(l, c.span, *body, *contact)?,
    })
}

/// Rolling without slipping: the contact point's velocity vanishes, in body-frame components.
fn rolling_equations(
    l: &Lowerer<'_>,
    span: Span,
    body: crate::model::BodyId,
    contact: crate::model::PointId,
) -> Result<Vec<ConstraintForm>, LowerError> {
    let b = l.model.body(body);
    let point = |id: crate::model::PointId| {
        l.points
            .get(id.index())
            .copied()
            .flatten()
            .ok_or(LowerError::Unresolved { span })
    };
    let g = point(b.centre)?;
    let p = point(contact)?;
    let r = l
        .frames
        .get(b.frame.index())
        .copied()
        .flatten()
        .ok_or(LowerError::Unresolved { span })?;
    let w = angular_velocity(&r);
    let d: Vector = [p[0] - g[0], p[1] - g[1], p[2] - g[2]];
    let v: Vector = g.map(Cx::dt);
    let vp = [
        v[0] + w[1] * d[2] - w[2] * d[1],
        v[1] + w[2] * d[0] - w[0] * d[2],
        v[2] + w[0] * d[1] - w[1] * d[0],
    ];
    // Expressed in the body frame the components' coefficients are often constant,
    // which lets an integrable rolling constraint eliminate a coordinate (the derivation
    // reads them in normal form). They are left as graphs here: the normal form of a 3-D
    // contact with `norm()` (the Whipple bicycle's front wheel) took 1.9 s of a 2 s
    // `linearize`, and Kane's method evaluates the graph as it is (issue 18).
    Ok((0..3)
        .map(|i| ConstraintForm::Velocity((0..3).map(|k| r[k][i] * vp[k]).sum::<Cx>()))
        .collect())
}

fn angular_velocity(r: &Rotation) -> Vector {
    let w = |i: usize, j: usize| -> Cx { (0..3).map(|k| r[i][k].dt() * r[j][k]).sum::<Cx>() };
    [
        ((w(2, 1) - w(1, 2)) / 2).normal(),
        ((w(0, 2) - w(2, 0)) / 2).normal(),
        ((w(1, 0) - w(0, 1)) / 2).normal(),
    ]
}

fn lower_body(
    l: &Lowerer<'_>,
    system: &mut System,
    b: &crate::model::Body,
) -> Result<usize, LowerError> {
    let unresolved = LowerError::Unresolved { span: b.name.span };
    let mass = l.scalar(&b.mass)?;
    let mut centre = l
        .points
        .get(b.centre.index())
        .copied()
        .flatten()
        .ok_or(unresolved.clone())?;
    let released = l
        .shift
        .bodies
        .iter()
        .any(|id| l.model.body(*id).name == b.name);
    if b.centre.index() == 0 && released {
        centre = l.rigid(shifted(centre, l.shift.displacement.as_ref()));
    }
    let mut rotation = l
        .frames
        .get(b.frame.index())
        .copied()
        .flatten()
        .ok_or(unresolved.clone())?;
    let unturned = rotation;
    if let (true, Some((psi, _))) = (released, l.shift.rotation.as_ref()) {
        // (1 + ψ×) R: exact to first order in ψ, all that a reaction (a derivative at ψ = 0)
        // sees.
        for (i, row) in rotation.iter_mut().enumerate() {
            for (j, entry) in row.iter_mut().enumerate() {
                let column: Vector = [unturned[0][j], unturned[1][j], unturned[2][j]];
                *entry = (unturned[i][j] + cross(psi, &column)[i]).normal();
            }
        }
    }
    let c = &b.inertia.components;
    let get = |i: usize| -> Result<Cx, LowerError> {
        c[i].as_ref().map_or(Ok(Cx::zero()), |e| l.scalar(e))
    };
    let (xx, yy, zz, xy, xz, yz) = (get(0)?, get(1)?, get(2)?, get(3)?, get(4)?, get(5)?);
    let mut inertia = [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]];
    if b.inertia.about != b.centre {
        let p = l
            .points
            .get(b.inertia.about.index())
            .copied()
            .flatten()
            .ok_or(unresolved)?;
        // The transfer uses the constrained centre: a released displacement moves the body,
        // not its inertia.
        let zero = l.at_rest();
        let d: Vector = [0, 1, 2].map(|k| (centre[k] - p[k]).subs(&zero).normal());
        let r: Vec<Cx> = (0..3)
            .map(|i| (0..3).map(|k| unturned[k][i] * d[k]).sum::<Cx>().normal())
            .collect();
        let r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        for (i, row) in inertia.iter_mut().enumerate() {
            for (j, entry) in row.iter_mut().enumerate() {
                let delta = if i == j { r2 } else { Cx::zero() };
                *entry = (*entry - mass * (delta - r[i] * r[j])).normal();
            }
        }
    }
    Ok(system.add_body(RigidBody {
        name: b.name.name.clone(),
        mass,
        centre,
        rotation,
        inertia,
    }))
}
