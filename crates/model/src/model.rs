//! The checked model: every name resolved, every expression typed.
//!
//! [`Model`] is what [`crate::check`] produces and what the `lower` step turns into `cas`
//! expressions and a `mechanics::System`. Declarations of each kind are kept in file order in
//! their own list and referred to by typed ids ([`CoordinateId`], [`PointId`], …).
//!
//! Invariant: an expression or declaration refers only to declarations that come *before* it
//! in the file. [`Model::declarations`] lists them all in file order, so one pass over it,
//! building each declaration's symbolic value from those already built, never meets an
//! undefined id (lowering kind by kind would not do: a constant may use a fixed point, whose
//! position uses a frame). Expressions keep their source [`Span`]s, so later stages can
//! still point at the text.
//!
//! Expression semantics, for lowering: a point stands for its position vector from `origin`
//! (`origin` is [`PointId`] 0, at the zero vector); `N.x` is the frame's unit vector, the
//! first column of its rotation matrix in inertial axes; a rate `q'` is q̇; `t` is time; all
//! vector arithmetic is the usual one (`*` is only scalar × vector, `/` only by a scalar).

use crate::ast::BinaryOp;
use crate::diagnostic::Type;
use crate::span::Span;

macro_rules! id_type {
    ($(#[$doc:meta] $name:ident),* $(,)?) => {$(
        #[$doc]
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(pub(crate) u32);

        impl $name {
            /// The position of the declaration in its list of the [`Model`].
            #[must_use]
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }
    )*};
}

id_type! {
    /// A coordinate: an index into [`Model::coordinates`].
    CoordinateId,
    /// A parameter: an index into [`Model::parameters`].
    ParameterId,
    /// An input: an index into [`Model::inputs`].
    InputId,
    /// A named constant: an index into [`Model::constants`].
    ConstantId,
    /// A frame: an index into [`Model::frames`].
    FrameId,
    /// A point: an index into [`Model::points`]. Id 0 is the built-in `origin`.
    PointId,
    /// A rigid body: an index into [`Model::bodies`].
    BodyId,
    /// A constraint: an index into [`Model::constraints`].
    ConstraintId,
}

impl PointId {
    /// The built-in `origin`, the fixed origin of the inertial frame.
    pub const ORIGIN: PointId = PointId(0);
}

/// A name with where it is declared.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Name {
    /// The name.
    pub name: String,
    /// The span of its declaration.
    pub span: Span,
}

/// A resolved, typed expression.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    /// What it is.
    pub kind: ExprKind,
    /// Where it is written.
    pub span: Span,
    /// Scalar or vector.
    pub ty: Type,
}

/// The kinds of resolved expression. Points stand for their position vector from `origin`.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ExprKind {
    /// A number literal; `text` is kept for exact conversion (`0.1` → 1/10).
    Number {
        /// As written.
        text: String,
        /// Nearest `f64` (finite).
        value: f64,
    },
    /// Time, `t`.
    Time,
    /// π.
    Pi,
    /// A coordinate `q` (free or driven).
    Coordinate(CoordinateId),
    /// The rate `q'` (q̇) of a coordinate.
    Rate(CoordinateId),
    /// A parameter.
    Parameter(ParameterId),
    /// An input (a known function of time, or an unknown symbol).
    Input(InputId),
    /// A named constant.
    Constant(ConstantId),
    /// A point's position vector from `origin`.
    Point(PointId),
    /// A frame's unit vector.
    UnitVector {
        /// The frame.
        frame: FrameId,
        /// The axis.
        axis: Axis,
    },
    /// `-operand`.
    Neg(Box<Expr>),
    /// `lhs op rhs`. For vectors: `+`, `-`, scalar `*` vector, vector `*` or `/` scalar.
    Binary {
        /// The operator.
        op: BinaryOp,
        /// Left operand.
        lhs: Box<Expr>,
        /// Right operand.
        rhs: Box<Expr>,
    },
    /// A call of a built-in function.
    Call {
        /// The function.
        function: Function,
        /// Its arguments (the count matches [`Function::arity`]).
        args: Vec<Expr>,
    },
}

/// An axis of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The first axis.
    X,
    /// The second axis.
    Y,
    /// The third axis.
    Z,
}

impl Axis {
    /// Parse `x`, `y` or `z`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Axis> {
        match name {
            "x" => Some(Axis::X),
            "y" => Some(Axis::Y),
            "z" => Some(Axis::Z),
            _ => None,
        }
    }

    /// `"x"`, `"y"` or `"z"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Axis::X => "x",
            Axis::Y => "y",
            Axis::Z => "z",
        }
    }
}

/// The built-in functions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Function {
    /// sin x
    Sin,
    /// cos x
    Cos,
    /// tan x
    Tan,
    /// arcsin x
    Asin,
    /// arccos x
    Acos,
    /// arctan x
    Atan,
    /// `atan2(y, x)`: the angle of the point (x, y).
    Atan2,
    /// eˣ
    Exp,
    /// Natural logarithm (`ln` and `log` are the same function).
    Ln,
    /// √x
    Sqrt,
    /// |x|
    Abs,
    /// The sign of x: −1, 0 or 1.
    Sign,
    /// `dot(u, v)`: scalar product of two vectors.
    Dot,
    /// `cross(u, v)`: vector product.
    Cross,
    /// `norm(v)`: length of a vector.
    Norm,
    /// `vel(P)`: the velocity of a point (the time derivative of a vector, in the inertial
    /// frame), where rates may appear.
    Vel,
}

impl Function {
    /// The function called `name`, if there is one.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Function> {
        Some(match name {
            "sin" => Function::Sin,
            "cos" => Function::Cos,
            "tan" => Function::Tan,
            "asin" => Function::Asin,
            "acos" => Function::Acos,
            "atan" => Function::Atan,
            "atan2" => Function::Atan2,
            "exp" => Function::Exp,
            "ln" | "log" => Function::Ln,
            "sqrt" => Function::Sqrt,
            "abs" => Function::Abs,
            "sign" => Function::Sign,
            "dot" => Function::Dot,
            "cross" => Function::Cross,
            "norm" => Function::Norm,
            "vel" => Function::Vel,
            _ => return None,
        })
    }

    /// All function names, including aliases.
    pub const NAMES: &'static [&'static str] = &[
        "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "exp", "ln", "log", "sqrt", "abs",
        "sign", "dot", "cross", "norm", "vel",
    ];

    /// The canonical name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Function::Sin => "sin",
            Function::Cos => "cos",
            Function::Tan => "tan",
            Function::Asin => "asin",
            Function::Acos => "acos",
            Function::Atan => "atan",
            Function::Atan2 => "atan2",
            Function::Exp => "exp",
            Function::Ln => "ln",
            Function::Sqrt => "sqrt",
            Function::Abs => "abs",
            Function::Sign => "sign",
            Function::Dot => "dot",
            Function::Cross => "cross",
            Function::Norm => "norm",
            Function::Vel => "vel",
        }
    }

    /// Number of arguments.
    #[must_use]
    pub fn arity(self) -> usize {
        match self {
            Function::Atan2 | Function::Dot | Function::Cross => 2,
            _ => 1,
        }
    }

    /// Types of the arguments and of the result.
    #[must_use]
    pub fn signature(self) -> (&'static [Type], Type) {
        match self {
            Function::Atan2 => (&[Type::Scalar, Type::Scalar], Type::Scalar),
            Function::Dot => (&[Type::Vector, Type::Vector], Type::Scalar),
            Function::Cross => (&[Type::Vector, Type::Vector], Type::Vector),
            Function::Norm => (&[Type::Vector], Type::Scalar),
            Function::Vel => (&[Type::Vector], Type::Vector),
            _ => (&[Type::Scalar], Type::Scalar),
        }
    }
}

/// A generalized coordinate.
#[derive(Clone, Debug, PartialEq)]
pub struct Coordinate {
    /// Its name.
    pub name: Name,
    /// For a time-driven (rheonomic) coordinate, its prescribed motion `q = f(t)`; `None` for a
    /// free coordinate.
    pub driven: Option<Expr>,
}

/// A parameter: a symbol that is constant in time.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// Its name.
    pub name: Name,
    /// Its numeric value (a constant expression of numbers and earlier parameters), if given.
    pub value: Option<Expr>,
}

/// An input: a given function of time (or a symbol when no value is given).
#[derive(Clone, Debug, PartialEq)]
pub struct Input {
    /// Its name.
    pub name: Name,
    /// Its value, a scalar expression of `t`, parameters and constants, if given.
    pub value: Option<Expr>,
}

/// A named constant: an abbreviation for an expression of parameters and numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct Constant {
    /// Its name.
    pub name: Name,
    /// Its value (scalar or vector).
    pub value: Expr,
}

/// One elementary rotation of a frame chain.
#[derive(Clone, Debug, PartialEq)]
pub struct Rotation {
    /// The angle (a scalar; a coordinate, a fixed parameter, a function of time…).
    pub angle: Expr,
    /// The axis, shared by the frame before and after the rotation.
    pub axis: Axis,
}

/// A reference frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Its name.
    pub name: Name,
    /// `None` for the inertial frame; otherwise the parent frame and the rotations that take
    /// the parent to this frame, applied in order (each about an axis of the frame produced
    /// by the previous rotation): `R = R_parent · R_1 · R_2 ⋯`, where the columns of `R` are
    /// the frame's unit vectors in inertial axes. Rotations are right-handed: by θ about `z`,
    /// `B.x = cos θ P.x + sin θ P.y`, `B.y = −sin θ P.x + cos θ P.y` (`P` the parent).
    pub rotation: Option<(FrameId, Vec<Rotation>)>,
}

/// A point.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// Its name.
    pub name: Name,
    /// Its position vector from `origin`; `None` only for `origin` itself (id 0).
    pub position: Option<Expr>,
}

/// A particle: a point mass.
#[derive(Clone, Debug, PartialEq)]
pub struct Particle {
    /// Where it is.
    pub point: PointId,
    /// Its mass (scalar).
    pub mass: Expr,
    /// The statement.
    pub span: Span,
}

/// An inertia tensor in body-frame components.
#[derive(Clone, Debug, PartialEq)]
pub struct Inertia {
    /// Components `[xx, yy, zz, xy, xz, yz]` in the body frame; `None` means zero (only
    /// products of inertia can be omitted).
    pub components: [Option<Expr>; 6],
    /// The point the tensor is taken about: the centre of mass, or a point of the body (fixed,
    /// for the usual use) given with `about`. When it is not the centre of mass `G`, the
    /// tensor about `G` follows from the parallel-axis theorem,
    /// `I_G = I_P − m ((r·r) 1 − r ⊗ r)` with `r = G − P` (in body axes).
    pub about: PointId,
    /// Whether it was written as principal moments.
    pub principal: bool,
}

/// A rigid body.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Its name.
    pub name: Name,
    /// Its mass.
    pub mass: Expr,
    /// Its centre of mass.
    pub centre: PointId,
    /// The frame attached to it.
    pub frame: FrameId,
    /// Its inertia tensor.
    pub inertia: Inertia,
}

/// Where a spring or damper acts.
#[derive(Clone, Debug, PartialEq)]
pub enum Connection {
    /// Between two points (vectors): along the line joining them.
    Points {
        /// First end.
        from: Expr,
        /// Second end.
        to: Expr,
    },
    /// On a scalar, such as an angle (torsional).
    Scalar(Expr),
}

/// A force element or a load.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Load {
    /// Uniform gravity: the acceleration vector acting on every particle and body.
    Gravity(Expr),
    /// A linear spring: potential `½ k (d − d₀)²`, with `d` the distance between the points
    /// or the value of the scalar.
    Spring {
        /// Stiffness.
        stiffness: Expr,
        /// Where.
        connection: Connection,
        /// Rest length or angle (zero when not given).
        rest: Option<Expr>,
    },
    /// A linear damper: Rayleigh dissipation `½ c ḋ²`.
    Damper {
        /// Coefficient.
        coefficient: Expr,
        /// Where.
        connection: Connection,
    },
    /// A Rayleigh dissipation function `D(q, q̇)`, at most quadratic in the rates.
    Dissipation(Expr),
    /// A potential energy `V(q, t)`.
    Potential(Expr),
    /// A force at a point.
    Force {
        /// The force vector.
        force: Expr,
        /// The point of application (a position vector).
        point: Expr,
    },
    /// A couple on a body.
    Couple {
        /// The moment vector.
        moment: Expr,
        /// The body.
        body: BodyId,
    },
    /// A generalized force on a coordinate.
    GeneralizedForce {
        /// The scalar.
        force: Expr,
        /// The coordinate.
        coordinate: CoordinateId,
    },
}

/// A load with the span of its statement.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadItem {
    /// The load.
    pub load: Load,
    /// The statement.
    pub span: Span,
}

/// A kind of constraint.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ConstraintKind {
    /// `f(q, t) = 0` with `f = lhs − rhs`: no rates.
    Holonomic {
        /// Left side.
        lhs: Expr,
        /// Right side.
        rhs: Expr,
    },
    /// `lhs = rhs`, linear in the rates.
    Velocity {
        /// Left side.
        lhs: Expr,
        /// Right side.
        rhs: Expr,
    },
    /// The material point of `body` at `contact` has zero velocity: `v_C + ω × (contact − C) = 0`.
    Rolling {
        /// The body.
        body: BodyId,
        /// The contact point.
        contact: PointId,
    },
    /// `driven' = ratio · driver'` (integrable when the ratio is constant).
    Gear {
        /// First coordinate.
        driver: CoordinateId,
        /// Second coordinate.
        driven: CoordinateId,
        /// The ratio.
        ratio: Expr,
    },
}

/// A constraint.
#[derive(Clone, Debug, PartialEq)]
pub struct Constraint {
    /// Its name, if given.
    pub name: Option<Name>,
    /// What it says.
    pub kind: ConstraintKind,
    /// The statement.
    pub span: Span,
}

impl Constraint {
    /// Whether the constraint is known to integrate to a relation among coordinates (and so
    /// can eliminate one): holonomic equations, and gears with a constant ratio.
    #[must_use]
    pub fn is_holonomic(&self) -> bool {
        match &self.kind {
            ConstraintKind::Holonomic { .. } => true,
            ConstraintKind::Gear { ratio, .. } => is_constant(ratio),
            _ => false,
        }
    }
}

/// Whether `expr` involves no coordinate, rate, input or time.
pub(crate) fn is_constant(expr: &Expr) -> bool {
    match &expr.kind {
        ExprKind::Time
        | ExprKind::Coordinate(_)
        | ExprKind::Rate(_)
        | ExprKind::Input(_)
        | ExprKind::Point(_) => false,
        ExprKind::Number { .. }
        | ExprKind::Pi
        | ExprKind::Parameter(_)
        | ExprKind::Constant(_)
        | ExprKind::UnitVector { .. } => true,
        ExprKind::Neg(e) => is_constant(e),
        ExprKind::Binary { lhs, rhs, .. } => is_constant(lhs) && is_constant(rhs),
        ExprKind::Call { args, .. } => args.iter().all(is_constant),
    }
}

/// A reaction to report.
#[derive(Clone, Debug, PartialEq)]
pub enum ReactionTarget {
    /// The reaction of a constraint.
    Constraint(ConstraintId),
    /// The generalized force that drives a time-driven coordinate.
    Driven(CoordinateId),
}

/// What a reaction at a point acts on: a body, or the particle at a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReleaseMember {
    /// A rigid body.
    Body(BodyId),
    /// A particle, by its index in [`Model::particles`].
    Particle(usize),
}

/// A reaction at a point, `reaction NAME: hinge|contact|rope P on B1, B2 [normal|along n]`:
/// the force that the constraint at `point` exerts on `members`, found by releasing them.
#[derive(Clone, Debug, PartialEq)]
pub struct Release {
    /// Its name.
    pub name: Name,
    /// Which kind of constraint.
    pub word: crate::ast::ReleaseWord,
    /// Where the constraint acts.
    pub point: PointId,
    /// The bodies and particles released together.
    pub members: Vec<ReleaseMember>,
    /// The contact normal or the rope's direction (pointing into the members for a contact or
    /// a rolling contact, away from them along the rope for a rope).
    pub direction: Option<Expr>,
    /// For `rolling ROLL normal n`: the rolling constraint (dropped when released).
    pub constraint: Option<ConstraintId>,
    /// `in frame R` or `along n`: where the report projects the force.
    pub projection: Option<Projection>,
    /// The statement.
    pub span: Span,
}

/// Where a reaction's force is projected for the report (`reaction NAME: … in frame R`,
/// `… along n`).
#[derive(Clone, Debug, PartialEq)]
pub enum Projection {
    /// The components along a frame's axes.
    Frame(FrameId),
    /// The component along a direction (a vector, normalised when projected).
    Along(Expr),
    /// `along BODY`: the component along the line from the body's centre to the reaction's
    /// point (a rod's axis; positive when it pulls the body towards the point).
    AlongBody {
        /// The body's name, as the report says it.
        body: String,
        /// The direction: the reaction's point less the body's centre.
        direction: Expr,
    },
}

/// An initial value of a coordinate or of its rate.
#[derive(Clone, Debug, PartialEq)]
pub struct InitialValue {
    /// The coordinate.
    pub coordinate: CoordinateId,
    /// Whether this is the rate.
    pub rate: bool,
    /// The value (a constant scalar).
    pub value: Expr,
}

/// Simulation settings; everything is optional and defaults belong to the simulator.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Simulation {
    /// Start time (default: 0).
    pub from: Option<Expr>,
    /// End time (required to simulate).
    pub to: Option<Expr>,
    /// Output step (default: the simulator's choice).
    pub step: Option<Expr>,
    /// Relative tolerance.
    pub rtol: Option<Expr>,
    /// Absolute tolerance.
    pub atol: Option<Expr>,
    /// Integration method, by name (`rk45`, `symplectic`, `implicit`, …): checked later.
    pub method: Option<Name>,
    /// The `simulate` statement.
    pub span: Span,
}

/// A quantity to record.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    /// Its label: the given name, or the expression's text.
    pub label: String,
    /// The quantity.
    pub quantity: Quantity,
    /// Where it is written.
    pub span: Span,
}

/// What an output records.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Quantity {
    /// A scalar or vector expression of the state and time.
    Expr(Expr),
    /// The total mechanical energy `K + V` (the Jacobi integral `h` when the system is
    /// rheonomic); written `energy`.
    Energy,
    /// The kinetic energy `K`; written `kinetic_energy`.
    KineticEnergy,
    /// The potential energy `V`; written `potential_energy`.
    PotentialEnergy,
    /// A constraint reaction (a multiplier), or the force driving a driven coordinate;
    /// written as the constraint's (or driven coordinate's) name.
    Reaction(ReactionTarget),
}

/// What the model says in words (`title`, `problem`, `note`), for the reports.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Prose {
    /// The title and where it is written.
    pub title: Option<(String, Span)>,
    /// The problem statement, one paragraph per `problem` statement.
    pub problem: Vec<String>,
    /// The notes (assumptions, corrections of the source), one per `note` statement.
    pub notes: Vec<String>,
}

/// A checked model. See the module doc for the ordering invariant.
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    pub(crate) coordinates: Vec<Coordinate>,
    pub(crate) parameters: Vec<Parameter>,
    pub(crate) inputs: Vec<Input>,
    pub(crate) constants: Vec<Constant>,
    pub(crate) frames: Vec<Frame>,
    pub(crate) points: Vec<Point>,
    pub(crate) particles: Vec<Particle>,
    pub(crate) bodies: Vec<Body>,
    pub(crate) loads: Vec<LoadItem>,
    pub(crate) constraints: Vec<Constraint>,
    pub(crate) reactions: Vec<ReactionTarget>,
    pub(crate) releases: Vec<Release>,
    pub(crate) initial: Vec<InitialValue>,
    pub(crate) simulation: Option<Simulation>,
    pub(crate) outputs: Vec<Output>,
    pub(crate) prose: Prose,
    pub(crate) warnings: Vec<crate::diagnostic::Diagnostic>,
    pub(crate) declarations: Vec<Declaration>,
}

/// A named declaration (or a constraint), for walking a model in file order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Declaration {
    /// A coordinate, free or driven.
    Coordinate(CoordinateId),
    /// A parameter.
    Parameter(ParameterId),
    /// An input.
    Input(InputId),
    /// A named constant.
    Constant(ConstantId),
    /// A frame.
    Frame(FrameId),
    /// A point (other than `origin`).
    Point(PointId),
    /// A rigid body.
    Body(BodyId),
    /// A constraint, named or not.
    Constraint(ConstraintId),
}

impl Model {
    /// Coordinates, free and driven, in declaration order.
    #[must_use]
    pub fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }

    /// Parameters.
    #[must_use]
    pub fn parameters(&self) -> &[Parameter] {
        &self.parameters
    }

    /// Inputs.
    #[must_use]
    pub fn inputs(&self) -> &[Input] {
        &self.inputs
    }

    /// Named constants.
    #[must_use]
    pub fn constants(&self) -> &[Constant] {
        &self.constants
    }

    /// Frames; exactly one has no rotation (the inertial frame) when any frame exists.
    #[must_use]
    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// Points; the first is `origin`.
    #[must_use]
    pub fn points(&self) -> &[Point] {
        &self.points
    }

    /// Particles.
    #[must_use]
    pub fn particles(&self) -> &[Particle] {
        &self.particles
    }

    /// Rigid bodies.
    #[must_use]
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// Forces, force elements and potentials, in file order.
    #[must_use]
    pub fn loads(&self) -> &[LoadItem] {
        &self.loads
    }

    /// Constraints.
    #[must_use]
    pub fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }

    /// The reactions asked for.
    #[must_use]
    pub fn reactions(&self) -> &[ReactionTarget] {
        &self.reactions
    }

    /// The reactions at points asked for (`reaction NAME: hinge P on B`, …).
    #[must_use]
    pub fn releases(&self) -> &[Release] {
        &self.releases
    }

    /// Initial values given (the others are zero).
    #[must_use]
    pub fn initial(&self) -> &[InitialValue] {
        &self.initial
    }

    /// Simulation settings, if a `simulate` statement is present.
    #[must_use]
    pub fn simulation(&self) -> Option<&Simulation> {
        self.simulation.as_ref()
    }

    /// Quantities to record.
    #[must_use]
    pub fn outputs(&self) -> &[Output] {
        &self.outputs
    }

    /// The title, problem statement and notes the model gives.
    #[must_use]
    pub fn prose(&self) -> &Prose {
        &self.prose
    }

    /// Every coordinate, parameter, input, constant, frame, point, body and constraint, in
    /// file order. Each refers only to declarations before it, so a single pass over this list
    /// (building each one's symbolic value from the ones already built) lowers the model.
    /// Particles and loads refer to declarations but are not referred to, so they can be
    /// lowered after it, from their own lists.
    #[must_use]
    pub fn declarations(&self) -> &[Declaration] {
        &self.declarations
    }

    /// The declaration called `name`, if any (`origin` and other built-ins are not
    /// declarations). For the command line, e.g. to override a parameter's value by name.
    #[must_use]
    pub fn find(&self, name: &str) -> Option<Declaration> {
        self.declarations.iter().copied().find(|declaration| {
            let declared = match *declaration {
                Declaration::Coordinate(id) => Some(&self.coordinate(id).name),
                Declaration::Parameter(id) => Some(&self.parameter(id).name),
                Declaration::Input(id) => Some(&self.input(id).name),
                Declaration::Constant(id) => Some(&self.constant(id).name),
                Declaration::Frame(id) => Some(&self.frame(id).name),
                Declaration::Point(id) => Some(&self.point(id).name),
                Declaration::Body(id) => Some(&self.body(id).name),
                Declaration::Constraint(id) => self.constraint(id).name.as_ref(),
            };
            declared.is_some_and(|declared| declared.name == name)
        })
    }

    /// Warnings found while checking (an unused coordinate or parameter, …): the model is
    /// valid, but something is probably not what was meant.
    #[must_use]
    pub fn warnings(&self) -> &[crate::diagnostic::Diagnostic] {
        &self.warnings
    }

    /// The inertial frame, if any frame is declared.
    #[must_use]
    pub fn inertial_frame(&self) -> Option<FrameId> {
        self.frames
            .iter()
            .position(|f| f.rotation.is_none())
            .map(|i| FrameId(i as u32))
    }

    /// The coordinate with id `id`.
    #[must_use]
    pub fn coordinate(&self, id: CoordinateId) -> &Coordinate {
        // Ids are only made by the checker for this model, so the index is valid.
        &self.coordinates[id.index()]
    }

    /// The free (not driven) coordinates: the unknowns of the equations of motion.
    pub fn free_coordinates(&self) -> impl Iterator<Item = (CoordinateId, &Coordinate)> {
        self.coordinates
            .iter()
            .enumerate()
            .filter(|(_, c)| c.driven.is_none())
            .map(|(i, c)| (CoordinateId(i as u32), c))
    }

    /// The parameter with id `id`.
    #[must_use]
    pub fn parameter(&self, id: ParameterId) -> &Parameter {
        &self.parameters[id.index()]
    }

    /// The input with id `id`.
    #[must_use]
    pub fn input(&self, id: InputId) -> &Input {
        &self.inputs[id.index()]
    }

    /// The constant with id `id`.
    #[must_use]
    pub fn constant(&self, id: ConstantId) -> &Constant {
        &self.constants[id.index()]
    }

    /// The frame with id `id`.
    #[must_use]
    pub fn frame(&self, id: FrameId) -> &Frame {
        &self.frames[id.index()]
    }

    /// The point with id `id`.
    #[must_use]
    pub fn point(&self, id: PointId) -> &Point {
        &self.points[id.index()]
    }

    /// The body with id `id`.
    #[must_use]
    pub fn body(&self, id: BodyId) -> &Body {
        &self.bodies[id.index()]
    }

    /// The constraint with id `id`.
    #[must_use]
    pub fn constraint(&self, id: ConstraintId) -> &Constraint {
        &self.constraints[id.index()]
    }
}

/// A number literal as an exact decimal: `mantissa × 10^exponent`. `0.25` is `25 × 10⁻²`,
/// `1.5e3` is `15 × 10²`. Made by [`decimal`]; the symbolic core turns it into a rational.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Decimal {
    /// The digits, without the decimal point.
    pub mantissa: u128,
    /// The power of ten.
    pub exponent: i32,
}

/// The exact value of a number literal of the language (the `text` of
/// [`ExprKind::Number`]), or `None` if it is not one or does not fit (more than 38 digits, or
/// an exponent beyond ±2³⁰); fall back to the `f64` value then.
#[must_use]
pub fn decimal(text: &str) -> Option<Decimal> {
    let (digits, exponent) = match text.find(['e', 'E']) {
        Some(at) => (text.get(..at)?, text.get(at + 1..)?.parse::<i32>().ok()?),
        None => (text, 0),
    };
    if exponent.unsigned_abs() > 1 << 30 {
        return None;
    }
    let (integer, fraction) = digits.split_once('.').unwrap_or((digits, ""));
    if integer.is_empty() && fraction.is_empty() {
        return None;
    }
    let mut mantissa: u128 = 0;
    for c in integer.chars().chain(fraction.chars()) {
        let digit = c.to_digit(10)?;
        mantissa = mantissa.checked_mul(10)?.checked_add(u128::from(digit))?;
    }
    let fraction_digits = i32::try_from(fraction.len()).ok()?;
    Some(Decimal {
        mantissa,
        exponent: exponent - fraction_digits,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimals_are_exact() {
        let d = |mantissa, exponent| Some(Decimal { mantissa, exponent });
        assert_eq!(decimal("0.25"), d(25, -2));
        assert_eq!(decimal("1.5e3"), d(15, 2));
        assert_eq!(decimal(".5"), d(5, -1));
        assert_eq!(decimal("2."), d(2, 0));
        assert_eq!(decimal("7"), d(7, 0));
        assert_eq!(decimal("1E-8"), d(1, -8));
        assert_eq!(decimal("."), None);
        assert_eq!(decimal("x"), None);
        assert_eq!(decimal(&"9".repeat(50)), None);
    }
}
