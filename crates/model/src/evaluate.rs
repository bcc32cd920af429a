//! Numeric evaluation of a model's expressions at a given state: [`Model::evaluate`].
//!
//! This is an independent, plain-`f64` reading of the language's semantics (frames as
//! rotation matrices, points as position vectors). It serves as the reference that the
//! symbolic lowering into `cas` is checked against (evaluate both at random states and
//! compare), and lets tests verify the kinematics of the example models.

use crate::ast::BinaryOp;
use crate::model::{Axis, Declaration, Expr, ExprKind, Function, Model};

/// Where to evaluate: time, and the value and rate of every coordinate, indexed by
/// [`crate::CoordinateId::index`] (entries of driven coordinates are ignored: their motion is
/// prescribed).
#[derive(Clone, Copy, Debug)]
pub struct State<'a> {
    /// Time `t`.
    pub time: f64,
    /// Coordinate values.
    pub coordinates: &'a [f64],
    /// Coordinate rates.
    pub rates: &'a [f64],
}

/// The value of an expression: a scalar or a vector in inertial-frame components.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// A number.
    Scalar(f64),
    /// A vector, components along the inertial frame's axes.
    Vector([f64; 3]),
}

impl Value {
    /// The number, if a scalar.
    #[must_use]
    pub fn scalar(self) -> Option<f64> {
        match self {
            Value::Scalar(x) => Some(x),
            Value::Vector(_) => None,
        }
    }

    /// The components, if a vector.
    #[must_use]
    pub fn vector(self) -> Option<[f64; 3]> {
        match self {
            Value::Vector(v) => Some(v),
            Value::Scalar(_) => None,
        }
    }
}

/// Why an expression could not be evaluated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EvaluationError {
    /// A parameter or input without a value.
    #[error("`{name}` has no value")]
    MissingValue {
        /// Its name.
        name: String,
    },
    /// The state has fewer coordinates or rates than the model.
    #[error("the state gives {given} values, but the model has {needed} coordinates")]
    StateTooShort {
        /// Entries given.
        given: usize,
        /// Coordinates in the model.
        needed: usize,
    },
}

/// Step of the central difference that gives the rate of a driven coordinate.
const TIME_STEP: f64 = 1e-6;

impl Model {
    /// Evaluate `expr` (an expression of this model) at `state`. Rates of driven coordinates
    /// are central differences of their motion (error ≈ 1e-10 relative).
    ///
    /// # Errors
    /// A parameter or input used without a value, or a state that is too short.
    pub fn evaluate(&self, expr: &Expr, state: &State<'_>) -> Result<Value, EvaluationError> {
        let needed = self.coordinates.len();
        let given = state.coordinates.len().min(state.rates.len());
        if given < needed {
            return Err(EvaluationError::StateTooShort { given, needed });
        }
        let environment = Environment::new(self, state, true)?;
        environment.value(expr)
    }

    /// Every declaration of this model evaluated once at `state`, to evaluate many expressions
    /// at that one state: [`Evaluation::value`] of an expression is what
    /// [`Model::evaluate`] gives, without computing every frame and point again for each.
    ///
    /// # Errors
    /// As [`Model::evaluate`].
    pub fn evaluation(&self, state: &State<'_>) -> Result<Evaluation<'_>, EvaluationError> {
        let needed = self.coordinates.len();
        let given = state.coordinates.len().min(state.rates.len());
        if given < needed {
            return Err(EvaluationError::StateTooShort { given, needed });
        }
        Ok(Evaluation {
            environment: Environment::new(self, state, true)?,
        })
    }
}

/// A model evaluated at one state ([`Model::evaluation`]): the values of its expressions there.
pub struct Evaluation<'m> {
    environment: Environment<'m>,
}

impl Evaluation<'_> {
    /// The value of `expr` (an expression of the model) at the state, as [`Model::evaluate`].
    ///
    /// # Errors
    /// A parameter or input used without a value.
    pub fn value(&self, expr: &Expr) -> Result<Value, EvaluationError> {
        self.environment.value(expr)
    }
}

type Matrix = [[f64; 3]; 3];

/// The values of every declaration at one state, computed once in file order.
struct Environment<'m> {
    model: &'m Model,
    time: f64,
    coordinates: Vec<f64>,
    rates: Vec<f64>,
    parameters: Vec<Option<f64>>,
    inputs: Vec<Option<f64>>,
    constants: Vec<Option<Value>>,
    /// Columns are the frame's unit vectors in inertial components.
    frames: Vec<Matrix>,
    points: Vec<[f64; 3]>,
}

impl<'m> Environment<'m> {
    /// The environment at `state`. With `rates`, the rates of driven coordinates are central
    /// differences of their values in two environments at `t ± h` (built without rates, so
    /// this recurses once).
    fn new(
        model: &'m Model,
        state: &State<'_>,
        rates: bool,
    ) -> Result<Environment<'m>, EvaluationError> {
        let h = TIME_STEP * (1.0 + state.time.abs());
        let neighbours = if rates && model.coordinates.iter().any(|c| c.driven.is_some()) {
            Some(Environment::neighbours(model, state, h)?)
        } else {
            None
        };
        let mut environment = Environment {
            model,
            time: state.time,
            coordinates: state.coordinates.to_vec(),
            rates: state.rates.to_vec(),
            parameters: Vec::new(),
            inputs: Vec::new(),
            constants: Vec::new(),
            frames: Vec::new(),
            points: vec![[0.0; 3]],
        };
        for declaration in &model.declarations {
            environment.declare(*declaration, neighbours.as_ref(), h)?;
        }
        Ok(environment)
    }

    /// The environments (without rates) at `t − h` and `t + h`.
    fn neighbours(
        model: &'m Model,
        state: &State<'_>,
        h: f64,
    ) -> Result<(Environment<'m>, Environment<'m>), EvaluationError> {
        let before = State {
            time: state.time - h,
            ..*state
        };
        let after = State {
            time: state.time + h,
            ..*state
        };
        Ok((
            Environment::new(model, &before, false)?,
            Environment::new(model, &after, false)?,
        ))
    }

    /// Evaluates one declaration and keeps its value for later references.
    fn declare(
        &mut self,
        declaration: Declaration,
        neighbours: Option<&(Environment<'m>, Environment<'m>)>,
        h: f64,
    ) -> Result<(), EvaluationError> {
        let model = self.model;
        match declaration {
            Declaration::Coordinate(id) => {
                if let Some(motion) = &model.coordinate(id).driven {
                    self.drive(id, motion, neighbours, h)?;
                }
            }
            Declaration::Parameter(id) => {
                let value = match &model.parameter(id).value {
                    Some(value) => Some(self.scalar(value)?),
                    None => None,
                };
                self.parameters.push(value);
            }
            Declaration::Input(id) => {
                let value = match &model.input(id).value {
                    Some(value) => Some(self.scalar(value)?),
                    None => None,
                };
                self.inputs.push(value);
            }
            Declaration::Constant(id) => {
                let value = self.value(&model.constant(id).value)?;
                self.constants.push(Some(value));
            }
            Declaration::Frame(id) => {
                let matrix = self.frame(id)?;
                self.frames.push(matrix);
            }
            Declaration::Point(id) => {
                let position = match &model.point(id).position {
                    Some(position) => self.vector(position)?,
                    None => [0.0; 3],
                };
                self.points.push(position);
            }
            Declaration::Body(_) | Declaration::Constraint(_) => {}
        }
        Ok(())
    }

    /// Sets a driven coordinate's value from its motion, and its rate from the neighbours'
    /// values (zero without them).
    fn drive(
        &mut self,
        id: crate::model::CoordinateId,
        motion: &Expr,
        neighbours: Option<&(Environment<'m>, Environment<'m>)>,
        h: f64,
    ) -> Result<(), EvaluationError> {
        let value = self.scalar(motion)?;
        let rate = match neighbours {
            Some((before, after)) => {
                let at = |e: &Environment<'_>| {
                    e.coordinates.get(id.index()).copied().unwrap_or(f64::NAN)
                };
                (at(after) - at(before)) / (2.0 * h)
            }
            None => 0.0,
        };
        if let Some(slot) = self.coordinates.get_mut(id.index()) {
            *slot = value;
        }
        if let Some(slot) = self.rates.get_mut(id.index()) {
            *slot = rate;
        }
        Ok(())
    }

    /// `vel(arg)`: the central difference of `arg` along the motion, in two environments at
    /// `t ± h` with the coordinates moved by `± h q̇` (the lowered model differentiates
    /// exactly; this is for plots and outputs).
    fn velocity(&self, arg: &Expr) -> Result<Value, EvaluationError> {
        let h = TIME_STEP * (1.0 + self.time.abs());
        let moved = |sign: f64| -> Vec<f64> {
            self.coordinates
                .iter()
                .zip(&self.rates)
                .map(|(q, r)| q + sign * h * r)
                .collect()
        };
        let (back, ahead) = (moved(-1.0), moved(1.0));
        let at = |time: f64, coordinates: &[f64]| -> Result<[f64; 3], EvaluationError> {
            let state = State {
                time,
                coordinates,
                rates: &self.rates,
            };
            Environment::new(self.model, &state, false)?.vector(arg)
        };
        let before = at(self.time - h, &back)?;
        let after = at(self.time + h, &ahead)?;
        Ok(Value::Vector(
            [0, 1, 2].map(|i| (after[i] - before[i]) / (2.0 * h)),
        ))
    }

    /// A frame's matrix: its parent's, turned by each of its rotations in order.
    fn frame(&self, id: crate::model::FrameId) -> Result<Matrix, EvaluationError> {
        let Some((parent, rotations)) = &self.model.frame(id).rotation else {
            return Ok(IDENTITY);
        };
        let mut matrix = self.frames.get(parent.index()).copied().unwrap_or(IDENTITY);
        for rotation in rotations {
            let angle = self.scalar(&rotation.angle)?;
            matrix = multiply(&matrix, &elementary(rotation.axis, angle));
        }
        Ok(matrix)
    }

    fn scalar(&self, expr: &Expr) -> Result<f64, EvaluationError> {
        // The checker typed every expression, so a scalar place holds a scalar; NaN marks the
        // impossible case instead of a panic.
        Ok(self.value(expr)?.scalar().unwrap_or(f64::NAN))
    }

    fn vector(&self, expr: &Expr) -> Result<[f64; 3], EvaluationError> {
        Ok(self.value(expr)?.vector().unwrap_or([f64::NAN; 3]))
    }

    fn value(&self, expr: &Expr) -> Result<Value, EvaluationError> {
        use Value::{Scalar, Vector};
        let missing = |name: &str| EvaluationError::MissingValue {
            name: name.to_string(),
        };
        let model = self.model;
        Ok(match &expr.kind {
            ExprKind::Number { value, .. } => Scalar(*value),
            ExprKind::Time => Scalar(self.time),
            ExprKind::Pi => Scalar(std::f64::consts::PI),
            ExprKind::Coordinate(id) => Scalar(
                self.coordinates
                    .get(id.index())
                    .copied()
                    .unwrap_or(f64::NAN),
            ),
            ExprKind::Rate(id) => Scalar(self.rates.get(id.index()).copied().unwrap_or(f64::NAN)),
            ExprKind::Parameter(id) => Scalar(
                self.parameters
                    .get(id.index())
                    .copied()
                    .flatten()
                    .ok_or_else(|| missing(&model.parameter(*id).name.name))?,
            ),
            ExprKind::Input(id) => Scalar(
                self.inputs
                    .get(id.index())
                    .copied()
                    .flatten()
                    .ok_or_else(|| missing(&model.input(*id).name.name))?,
            ),
            ExprKind::Constant(id) => self
                .constants
                .get(id.index())
                .copied()
                .flatten()
                .unwrap_or(Scalar(f64::NAN)),
            ExprKind::Point(id) => Vector(
                self.points
                    .get(id.index())
                    .copied()
                    .unwrap_or([f64::NAN; 3]),
            ),
            ExprKind::UnitVector { frame, axis } => {
                let matrix = self.frames.get(frame.index()).copied().unwrap_or(IDENTITY);
                let column = axis_index(*axis);
                Vector([matrix[0][column], matrix[1][column], matrix[2][column]])
            }
            ExprKind::Neg(operand) => match self.value(operand)? {
                Scalar(x) => Scalar(-x),
                Vector(v) => Vector(v.map(|c| -c)),
            },
            ExprKind::Binary { op, lhs, rhs } => {
                let (a, b) = (self.value(lhs)?, self.value(rhs)?);
                match (op, a, b) {
                    (BinaryOp::Add, Scalar(a), Scalar(b)) => Scalar(a + b),
                    (BinaryOp::Sub, Scalar(a), Scalar(b)) => Scalar(a - b),
                    (BinaryOp::Mul, Scalar(a), Scalar(b)) => Scalar(a * b),
                    (BinaryOp::Div, Scalar(a), Scalar(b)) => Scalar(a / b),
                    (BinaryOp::Pow, Scalar(a), Scalar(b)) => Scalar(a.powf(b)),
                    (BinaryOp::Add, Vector(u), Vector(v)) => {
                        Vector([u[0] + v[0], u[1] + v[1], u[2] + v[2]])
                    }
                    (BinaryOp::Sub, Vector(u), Vector(v)) => {
                        Vector([u[0] - v[0], u[1] - v[1], u[2] - v[2]])
                    }
                    (BinaryOp::Mul, Scalar(a), Vector(v))
                    | (BinaryOp::Mul, Vector(v), Scalar(a)) => Vector(v.map(|c| a * c)),
                    (BinaryOp::Div, Vector(v), Scalar(a)) => Vector(v.map(|c| c / a)),
                    // Ruled out by the checker.
                    _ => Scalar(f64::NAN),
                }
            }
            ExprKind::Call {
                function: Function::Vel,
                args,
            } => match args.first() {
                Some(arg) => self.velocity(arg)?,
                None => Vector([f64::NAN; 3]),
            },
            ExprKind::Call { function, args } => {
                let values = args
                    .iter()
                    .map(|a| self.value(a))
                    .collect::<Result<Vec<_>, _>>()?;
                call(*function, &values)
            }
        })
    }
}

fn call(function: Function, args: &[Value]) -> Value {
    use Value::{Scalar, Vector};
    match (function, args) {
        (Function::Dot, [Vector(u), Vector(v)]) => Scalar(u[0] * v[0] + u[1] * v[1] + u[2] * v[2]),
        (Function::Cross, [Vector(u), Vector(v)]) => Vector([
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]),
        (Function::Norm, [Vector(v)]) => Scalar((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()),
        (Function::Atan2, [Scalar(y), Scalar(x)]) => Scalar(y.atan2(*x)),
        (_, [Scalar(x)]) => Scalar(match function {
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
            Function::Sign if *x == 0.0 => 0.0,
            Function::Sign => x.signum(),
            _ => f64::NAN,
        }),
        // Ruled out by the checker.
        _ => Scalar(f64::NAN),
    }
}

const IDENTITY: Matrix = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn axis_index(axis: Axis) -> usize {
    match axis {
        Axis::X => 0,
        Axis::Y => 1,
        Axis::Z => 2,
    }
}

/// The right-handed rotation by `angle` about `axis`; its columns are the rotated unit vectors.
fn elementary(axis: Axis, angle: f64) -> Matrix {
    let (s, c) = angle.sin_cos();
    match axis {
        Axis::X => [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]],
        Axis::Y => [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]],
        Axis::Z => [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
    }
}

fn multiply(a: &Matrix, b: &Matrix) -> Matrix {
    let mut product = [[0.0; 3]; 3];
    for (i, row) in product.iter_mut().enumerate() {
        for (j, entry) in row.iter_mut().enumerate() {
            *entry = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    product
}
