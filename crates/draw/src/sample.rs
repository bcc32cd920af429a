//! The model's geometry in numbers: every point and frame at a state ([`Snapshot`]), and the
//! small vector algebra the drawing needs. Everything is read through
//! [`model::Model::evaluation`], the language's own numeric semantics: the model is evaluated
//! once per state (every frame and point in one pass) and each expression read off that.

use std::cell::OnceCell;

use model::{
    Axis, Declaration, Evaluation, EvaluationError, Expr, ExprKind, FrameId, Model, Span, State,
    Type, Value,
};

use crate::scene::P3;
use crate::DrawError;

/// Where the figure is drawn: time and the value of every coordinate of the model (indexed
/// like [`Model::coordinates`]; entries of driven coordinates are ignored).
#[derive(Clone, Debug, PartialEq)]
pub struct Configuration {
    /// Time (driven coordinates and inputs depend on it).
    pub time: f64,
    /// The coordinates' values.
    pub coordinates: Vec<f64>,
}

/// Every named point and every frame of the model at one configuration.
#[derive(Clone, Debug)]
pub struct Snapshot {
    /// Positions, indexed like [`Model::points`] (`origin` first).
    pub points: Vec<P3>,
    /// Unit vectors (columns x, y, z) of each frame, indexed like [`Model::frames`].
    pub frames: Vec<[P3; 3]>,
}

/// Evaluates a model's expressions at configurations near one given configuration.
pub struct Sampler<'m> {
    /// The model.
    pub model: &'m Model,
    /// The configuration drawn.
    pub at: Configuration,
    zeros: Vec<f64>,
    frame_ids: Vec<Option<FrameId>>,
    /// The model evaluated at `at`, once, when first needed.
    here: OnceCell<Result<Evaluation<'m>, EvaluationError>>,
}

impl<'m> Sampler<'m> {
    /// A sampler of `model` around `at`.
    ///
    /// # Errors
    /// [`DrawError::State`] when `at` does not give a value to every coordinate.
    pub fn new(model: &'m Model, at: Configuration) -> Result<Sampler<'m>, DrawError> {
        let needed = model.coordinates().len();
        if at.coordinates.len() != needed || at.coordinates.iter().any(|x| !x.is_finite()) {
            return Err(DrawError::State {
                given: at.coordinates.len(),
                needed,
            });
        }
        let frame_ids = model
            .frames()
            .iter()
            .map(|f| match model.find(&f.name.name) {
                Some(Declaration::Frame(id)) => Some(id),
                _ => None,
            })
            .collect();
        Ok(Sampler {
            model,
            zeros: vec![0.0; needed],
            at,
            frame_ids,
            here: OnceCell::new(),
        })
    }

    /// The model evaluated at `coordinates` and `time`.
    fn evaluation(
        &self,
        coordinates: &[f64],
        time: f64,
    ) -> Result<Evaluation<'m>, EvaluationError> {
        self.model.evaluation(&self.state(coordinates, time))
    }

    /// `expr`'s value in `evaluation`, or the error named by the expression.
    fn read(
        &self,
        evaluation: &Result<Evaluation<'m>, EvaluationError>,
        expr: &Expr,
    ) -> Result<Value, DrawError> {
        evaluation
            .as_ref()
            .map_err(Clone::clone)
            .and_then(|e| e.value(expr))
            .map_err(|source| DrawError::Evaluate {
                what: self.model.display(expr).to_string(),
                source,
            })
    }

    /// The value of `expr` at the configuration drawn.
    fn value_here(&self, expr: &Expr) -> Result<Value, DrawError> {
        let here = self
            .here
            .get_or_init(|| self.evaluation(&self.at.coordinates, self.at.time));
        self.read(here, expr)
    }

    fn state<'a>(&'a self, coordinates: &'a [f64], time: f64) -> State<'a> {
        State {
            time,
            coordinates,
            rates: &self.zeros,
        }
    }

    /// A scalar expression at the configuration drawn (`None` for a vector).
    ///
    /// # Errors
    /// As [`Sampler::value`].
    pub fn scalar(&self, expr: &Expr) -> Result<Option<f64>, DrawError> {
        Ok(self.value_here(expr)?.scalar().filter(|x| x.is_finite()))
    }

    /// A vector expression at the configuration drawn (`None` for a scalar).
    ///
    /// # Errors
    /// As [`Sampler::value`].
    pub fn vector(&self, expr: &Expr) -> Result<Option<P3>, DrawError> {
        Ok(self
            .value_here(expr)?
            .vector()
            .filter(|v| v.iter().all(|x| x.is_finite())))
    }

    /// Every point and frame at `coordinates` and `time`.
    ///
    /// # Errors
    /// As [`Sampler::value`].
    pub fn snapshot(&self, coordinates: &[f64], time: f64) -> Result<Snapshot, DrawError> {
        let evaluation = self.evaluation(coordinates, time);
        let mut points = Vec::with_capacity(self.model.points().len());
        for point in self.model.points() {
            let p = match &point.position {
                Some(e) => self.read(&evaluation, e)?.vector(),
                None => Some([0.0; 3]),
            };
            points.push(finite(p.unwrap_or([0.0; 3])));
        }
        let mut frames = Vec::with_capacity(self.frame_ids.len());
        for id in &self.frame_ids {
            let mut axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
            if let Some(frame) = id {
                for (k, axis) in [Axis::X, Axis::Y, Axis::Z].into_iter().enumerate() {
                    let e = unit_vector(*frame, axis);
                    if let Some(v) = self.read(&evaluation, &e)?.vector() {
                        axes[k] = finite(v);
                    }
                }
            }
            frames.push(axes);
        }
        Ok(Snapshot { points, frames })
    }

    /// The snapshot at the configuration drawn.
    ///
    /// # Errors
    /// As [`Sampler::value`].
    pub fn here(&self) -> Result<Snapshot, DrawError> {
        self.snapshot(&self.at.coordinates, self.at.time)
    }

    /// The snapshot with coordinate `k` moved by `delta`.
    ///
    /// # Errors
    /// As [`Sampler::value`].
    pub fn moved(&self, k: usize, delta: f64) -> Result<Snapshot, DrawError> {
        let mut q = self.at.coordinates.clone();
        if let Some(x) = q.get_mut(k) {
            *x += delta;
        }
        self.snapshot(&q, self.at.time)
    }

    /// The snapshot with every free coordinate and time moved by a fixed, irregular amount:
    /// what does not change between it and [`Sampler::here`] is fixed.
    ///
    /// # Errors
    /// As [`Sampler::value`].
    pub fn shaken(&self, scale: f64) -> Result<Snapshot, DrawError> {
        let q: Vec<f64> = self
            .at
            .coordinates
            .iter()
            .enumerate()
            .map(|(k, x)| x + scale * (0.37 + 0.11 * k as f64))
            .collect();
        self.snapshot(&q, self.at.time + 0.53 * scale)
    }
}

/// The expression `F.axis`.
pub fn unit_vector(frame: FrameId, axis: Axis) -> Expr {
    Expr {
        kind: ExprKind::UnitVector { frame, axis },
        span: Span::default(),
        ty: Type::Vector,
    }
}

fn finite(v: P3) -> P3 {
    v.map(|x| if x.is_finite() { x } else { 0.0 })
}

/// `a + b`.
pub fn add(a: P3, b: P3) -> P3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a − b`.
pub fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `s a`.
pub fn scale(s: f64, a: P3) -> P3 {
    [s * a[0], s * a[1], s * a[2]]
}

/// `a · b`.
pub fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b`.
pub fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `|a|`.
pub fn norm(a: P3) -> f64 {
    dot(a, a).sqrt()
}

/// `a / |a|`, or `None` for a vector too short to have a direction.
pub fn unit(a: P3) -> Option<P3> {
    let n = norm(a);
    (n > 1e-12).then(|| scale(1.0 / n, a))
}

/// `a` rotated by `angle` about the unit axis `n` (Rodrigues).
pub fn rotate(a: P3, n: P3, angle: f64) -> P3 {
    let (s, c) = angle.sin_cos();
    add(
        add(scale(c, a), scale(s, cross(n, a))),
        scale(dot(n, a) * (1.0 - c), n),
    )
}
