//! The syntax tree of a model file, as written: every node carries the [`Span`] of its text.
//!
//! Names are still strings here; [`crate::check`] resolves them into a [`crate::Model`]. The
//! tree is a list of [`Statement`]s in file order, one per logical line.

use crate::span::Span;

/// A parsed model file: its statements in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Ast {
    /// The statements, in file order.
    pub statements: Vec<Statement>,
    /// Names that statements with syntax errors seem to declare (`x` and `y` in the broken
    /// `coordinates x, y,`). The checker does not know them, so [`crate::load`] drops its
    /// "unknown name" reports about them: they would only repeat the syntax error.
    pub names_in_broken_declarations: Vec<String>,
}

/// A name and where it is written.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Ident {
    /// The name as written.
    pub name: String,
    /// Its bytes in the source.
    pub span: Span,
}

/// A number literal: its text is kept so that `0.1` can become the exact rational `1/10`.
#[derive(Clone, Debug, PartialEq)]
pub struct Number {
    /// The literal as written (`0.5`, `1e-3`).
    pub text: String,
    /// Its value as the nearest `f64` (always finite).
    pub value: f64,
}

/// An expression with its span.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    /// What kind of expression.
    pub kind: ExprKind,
    /// Its bytes in the source (for a parenthesized expression, including the parentheses).
    pub span: Span,
}

/// The kinds of expression.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ExprKind {
    /// A number literal.
    Number(Number),
    /// A name: a coordinate, parameter, point, `t`, `pi`, `origin`…
    Name(Ident),
    /// The rate of a coordinate: `theta'`.
    Rate(Ident),
    /// A frame's unit vector: `N.x`.
    UnitVector {
        /// The frame.
        frame: Ident,
        /// The axis (`x`, `y` or `z` when valid).
        axis: Ident,
    },
    /// `-operand`.
    Neg(Box<Expr>),
    /// `lhs op rhs`.
    Binary {
        /// The operator.
        op: BinaryOp,
        /// Left operand.
        lhs: Box<Expr>,
        /// Right operand.
        rhs: Box<Expr>,
    },
    /// `function(args…)`.
    Call {
        /// The function's name.
        function: Ident,
        /// The arguments.
        args: Vec<Expr>,
    },
}

/// Binary operators, loosest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinaryOp {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `^` or `**`
    Pow,
}

impl BinaryOp {
    /// The operator as written.
    #[must_use]
    pub fn symbol(self) -> &'static str {
        match self {
            BinaryOp::Add => "+",
            BinaryOp::Sub => "-",
            BinaryOp::Mul => "*",
            BinaryOp::Div => "/",
            BinaryOp::Pow => "^",
        }
    }
}

/// One statement (a logical line) with its span.
#[derive(Clone, Debug, PartialEq)]
pub struct Statement {
    /// What it declares or states.
    pub kind: StatementKind,
    /// The whole statement.
    pub span: Span,
}

/// A name with an optional `= value`, as in `parameters m = 1, l`.
#[derive(Clone, Debug, PartialEq)]
pub struct Binding {
    /// The declared name.
    pub name: Ident,
    /// The value after `=`, if any.
    pub value: Option<Expr>,
}

/// One rotation in a frame definition: `theta about z`.
#[derive(Clone, Debug, PartialEq)]
pub struct Rotation {
    /// The angle.
    pub angle: Expr,
    /// The axis as written (`x`, `y` or `z` when valid).
    pub axis: Ident,
}

/// How an inertia tensor is written.
#[derive(Clone, Debug, PartialEq)]
pub enum InertiaSpec {
    /// `inertia I1, I2, I3`: principal moments along the body frame's axes.
    Principal(Vec<Expr>),
    /// `inertia xx = A, yy = B, zz = C, xy = D, …`: components in the body frame; products
    /// not given are zero. Keys are kept as written and checked later.
    Components(Vec<(Ident, Expr)>),
}

/// The `inertia` clause of a body.
#[derive(Clone, Debug, PartialEq)]
pub struct InertiaClause {
    /// The tensor.
    pub spec: InertiaSpec,
    /// `about P`: the point it is taken about, if not the centre of mass.
    pub about: Option<Ident>,
    /// The whole clause.
    pub span: Span,
}

/// The clauses of a `body` statement; each is optional in the syntax and checked later.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BodyClauses {
    /// `mass m`.
    pub mass: Option<Expr>,
    /// `at C`: the centre of mass.
    pub centre: Option<Ident>,
    /// `frame B`: the body frame.
    pub frame: Option<Ident>,
    /// `inertia …`.
    pub inertia: Option<InertiaClause>,
}

/// What a `reaction NAME: …` statement releases.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReleaseWord {
    /// `hinge P on B`: a force, every component.
    Hinge,
    /// `contact P on B normal n`: the normal force along `n` only, push only.
    Contact,
    /// `rope P on B along n`: the tension along `n` only, pull only.
    Rope,
    /// `clamp P on B`: a force and a couple, every component.
    Clamp,
    /// `rolling ROLL normal n`: a rolling constraint's force split into the normal force
    /// along `n` and friction.
    Rolling,
}

/// `reaction NAME: hinge|contact|rope|clamp P on B1, B2 [normal|along n]`.
#[derive(Clone, Debug, PartialEq)]
pub struct ReleaseSpec {
    /// Which kind.
    pub word: ReleaseWord,
    /// The point where the constraint acts; for `rolling`, the rolling constraint's name.
    pub point: Ident,
    /// The bodies or particles the reaction acts on (released together; none for `rolling`).
    pub members: Vec<Ident>,
    /// The direction for `contact` and `rope`.
    pub direction: Option<Expr>,
    /// `in frame R` or `along n`: the components the report projects the force on.
    pub projection: Option<ReleaseProjection>,
}

/// Where a reaction's force is projected for the report: `… in frame R`, `… along n`.
#[derive(Clone, Debug, PartialEq)]
pub enum ReleaseProjection {
    /// `in frame R`: the components along the frame's axes.
    Frame(Ident),
    /// `along n`: the component along `n` (normalised), e.g. `along A - B` for a rod from B to A.
    Along(Expr),
}

/// The kinds of constraint.
#[derive(Clone, Debug, PartialEq)]
pub enum ConstraintSpec {
    /// `lhs = rhs`: holonomic if there are no rates, a linear velocity constraint otherwise.
    Equation {
        /// Left side.
        lhs: Expr,
        /// Right side.
        rhs: Expr,
    },
    /// `rolling BODY at POINT`: the material point of the body at the contact point has zero
    /// velocity.
    Rolling {
        /// The body.
        body: Ident,
        /// The contact point.
        contact: Ident,
    },
    /// `gear DRIVER to DRIVEN ratio r`: `driven' = r * driver'`.
    Gear {
        /// The first coordinate.
        driver: Ident,
        /// The second coordinate.
        driven: Ident,
        /// The ratio.
        ratio: Expr,
    },
}

/// A spring or damper's geometry.
#[derive(Clone, Debug, PartialEq)]
pub enum Connection {
    /// `from P to Q`: along the line between two points.
    Points {
        /// First end.
        from: Expr,
        /// Second end.
        to: Expr,
    },
    /// `on q`: on a scalar (an angle, for a torsional spring).
    Scalar(Expr),
}

/// One item of an `initial` statement: `x = 0.1` or `x' = 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct InitialValue {
    /// The coordinate.
    pub name: Ident,
    /// Whether this is the rate (`x'`).
    pub rate: bool,
    /// The value.
    pub value: Expr,
}

/// One `key value` setting of `simulate`.
#[derive(Clone, Debug, PartialEq)]
pub struct Setting {
    /// The key (`from`, `to`, `step`, `rtol`, `atol`, `method`).
    pub key: Ident,
    /// The value: an expression, or a name for `method`.
    pub value: Expr,
}

/// One item of `output`: an expression, optionally named.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputItem {
    /// `name =`, if given.
    pub name: Option<Ident>,
    /// The quantity.
    pub value: Expr,
}

/// The kinds of statement.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum StatementKind {
    /// `coordinates x, theta`.
    Coordinates(Vec<Ident>),
    /// `parameters m = 1, l`.
    Parameters(Vec<Binding>),
    /// `inputs F = 0, C`.
    Inputs(Vec<Binding>),
    /// `constants r = R1/R2`.
    Constants(Vec<Binding>),
    /// `driven phi = Omega*t`.
    Driven(Vec<Binding>),
    /// `frame N` or `frame B = N rotated theta about z then …`.
    Frame {
        /// The new frame.
        name: Ident,
        /// `= PARENT rotated …`: the parent frame and the chain of rotations.
        rotation: Option<(Ident, Vec<Rotation>)>,
    },
    /// `point B = A + l*N.x`.
    Point {
        /// The new point.
        name: Ident,
        /// Its position.
        position: Expr,
    },
    /// `particle A mass m`.
    Particle {
        /// The point it sits at.
        point: Ident,
        /// Its mass.
        mass: Expr,
    },
    /// `body disc mass m at C frame B inertia I1, I2, I3 [about O]`.
    Body {
        /// The body's name.
        name: Ident,
        /// Its clauses.
        clauses: BodyClauses,
    },
    /// `gravity g*N.y`: the acceleration of gravity.
    Gravity(Expr),
    /// `spring k from A to B [length l0]` or `spring k on theta [rest theta0]`.
    Spring {
        /// Stiffness.
        stiffness: Expr,
        /// Where it acts.
        connection: Connection,
        /// Rest length or rest angle (default zero).
        rest: Option<Expr>,
    },
    /// `damper c from A to B` or `damper c on theta`.
    Damper {
        /// Damping coefficient.
        coefficient: Expr,
        /// Where it acts.
        connection: Connection,
    },
    /// `dissipation D`: a Rayleigh dissipation function.
    Dissipation(Expr),
    /// `potential V`: a potential energy added to the system.
    Potential(Expr),
    /// `force F*N.x at A`.
    Force {
        /// The force vector.
        force: Expr,
        /// Its point of application.
        point: Expr,
    },
    /// `couple C*N.z on disc`.
    Couple {
        /// The moment vector.
        moment: Expr,
        /// The body it acts on.
        body: Ident,
    },
    /// `generalized force Q on theta`.
    GeneralizedForce {
        /// The scalar force.
        force: Expr,
        /// The coordinate.
        coordinate: Ident,
    },
    /// `constraint [name:] …`.
    Constraint {
        /// Its name, if given.
        name: Option<Ident>,
        /// What it constrains.
        spec: ConstraintSpec,
    },
    /// `reactions c1, c2`.
    Reactions(Vec<Ident>),
    /// `reaction NAME: hinge P on B` (and `contact`, `rope`): a reaction at a point.
    Release {
        /// The reaction's name.
        name: Ident,
        /// What is released, where, on what.
        spec: ReleaseSpec,
    },
    /// `initial x = 0.1, x' = 0`.
    Initial(Vec<InitialValue>),
    /// `simulate from 0 to 10 step 0.01`.
    Simulate(Vec<Setting>),
    /// `output x, y_B = dot(B, N.y)`.
    Output(Vec<OutputItem>),
    /// `title "…"`: the report's title.
    Title(String),
    /// `problem "…" \ "…"`: one paragraph of the problem statement (the texts of one
    /// statement joined by spaces).
    Problem(String),
    /// `note "…"`: a note on the model (an assumption, a correction of the source).
    Note(String),
}

impl StatementKind {
    /// The statement keyword, for messages and summaries.
    #[must_use]
    pub fn keyword(&self) -> &'static str {
        match self {
            StatementKind::Coordinates(_) => "coordinates",
            StatementKind::Parameters(_) => "parameters",
            StatementKind::Inputs(_) => "inputs",
            StatementKind::Constants(_) => "constants",
            StatementKind::Driven(_) => "driven",
            StatementKind::Frame { .. } => "frame",
            StatementKind::Point { .. } => "point",
            StatementKind::Particle { .. } => "particle",
            StatementKind::Body { .. } => "body",
            StatementKind::Gravity(_) => "gravity",
            StatementKind::Spring { .. } => "spring",
            StatementKind::Damper { .. } => "damper",
            StatementKind::Dissipation(_) => "dissipation",
            StatementKind::Potential(_) => "potential",
            StatementKind::Force { .. } => "force",
            StatementKind::Couple { .. } => "couple",
            StatementKind::GeneralizedForce { .. } => "generalized force",
            StatementKind::Constraint { .. } => "constraint",
            StatementKind::Reactions(_) | StatementKind::Release { .. } => "reactions",
            StatementKind::Initial(_) => "initial",
            StatementKind::Simulate(_) => "simulate",
            StatementKind::Output(_) => "output",
            StatementKind::Title(_) => "title",
            StatementKind::Problem(_) => "problem",
            StatementKind::Note(_) => "note",
        }
    }
}

impl BinaryOp {
    /// Binding strength: higher binds tighter.
    fn precedence(self) -> u8 {
        match self {
            BinaryOp::Add | BinaryOp::Sub => 1,
            BinaryOp::Mul | BinaryOp::Div => 2,
            BinaryOp::Pow => 4,
        }
    }
}

/// Prints the expression in the language's syntax with only the parentheses it needs.
impl std::fmt::Display for Expr {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        fn child(f: &mut std::fmt::Formatter<'_>, expr: &Expr, needs: bool) -> std::fmt::Result {
            if needs {
                write!(f, "({expr})")
            } else {
                write!(f, "{expr}")
            }
        }
        // Unary minus binds between `*` and `^`.
        let precedence = |e: &Expr| match &e.kind {
            ExprKind::Binary { op, .. } => op.precedence(),
            ExprKind::Neg(_) => 3,
            _ => 5,
        };
        match &self.kind {
            ExprKind::Number(number) => f.write_str(&number.text),
            ExprKind::Name(ident) => f.write_str(&ident.name),
            ExprKind::Rate(ident) => write!(f, "{}'", ident.name),
            ExprKind::UnitVector { frame, axis } => write!(f, "{}.{}", frame.name, axis.name),
            ExprKind::Neg(operand) => {
                f.write_str("-")?;
                child(f, operand, precedence(operand) < 3)
            }
            ExprKind::Binary { op, lhs, rhs } => {
                let own = op.precedence();
                // Left-associative operators need parentheses on an equal-precedence right
                // child; `^` is right-associative, so the other way round.
                let (left_needs, right_needs) = if *op == BinaryOp::Pow {
                    (precedence(lhs) <= own, precedence(rhs) < own)
                } else {
                    (precedence(lhs) < own, precedence(rhs) <= own)
                };
                child(f, lhs, left_needs)?;
                match op {
                    BinaryOp::Mul | BinaryOp::Div | BinaryOp::Pow => f.write_str(op.symbol())?,
                    _ => write!(f, " {} ", op.symbol())?,
                }
                child(f, rhs, right_needs)
            }
            ExprKind::Call { function, args } => {
                write!(f, "{}(", function.name)?;
                for (i, arg) in args.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    write!(f, "{arg}")?;
                }
                f.write_str(")")
            }
        }
    }
}
