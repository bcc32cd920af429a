//! The checked, lowered input of the mechanics: coordinates, bodies and loads as `cas`
//! expressions in the inertial frame.

use cas::Expr;

/// A vector: components along the inertial axes.
pub type Vector = [Expr; 3];

/// A rotation matrix, rows of entries; its columns are a frame's unit vectors in inertial axes.
pub type Rotation = [[Expr; 3]; 3];

/// The elementary rotation by `angle` about axis `axis` (0 = x, 1 = y, 2 = z), right-handed.
/// Returns the identity for an axis index above 2.
#[must_use]
pub fn rotation_about(axis: usize, angle: Expr) -> Rotation {
    let (c, s) = (angle.cos(), angle.sin());
    let (o, z) = (Expr::one(), Expr::zero());
    match axis {
        0 => [[o, z, z], [z, c, -s], [z, s, c]],
        1 => [[c, z, s], [z, o, z], [-s, z, c]],
        2 => [[c, -s, z], [s, c, z], [z, z, o]],
        _ => [[o, z, z], [z, o, z], [z, z, o]],
    }
}

/// A point mass.
#[derive(Clone, Debug)]
pub struct Particle {
    /// Its name (for reports).
    pub name: String,
    /// Its mass.
    pub mass: Expr,
    /// Its position vector in the inertial frame.
    pub position: Vector,
}

/// A rigid body.
#[derive(Clone, Debug)]
pub struct RigidBody {
    /// Its name.
    pub name: String,
    /// Its mass.
    pub mass: Expr,
    /// Position of its centre of mass.
    pub centre: Vector,
    /// Rotation matrix of its frame (columns: body axes in inertial components).
    pub rotation: Rotation,
    /// Inertia tensor about the centre of mass, in body axes (symmetric).
    pub inertia: [[Expr; 3]; 3],
}

/// A load or force element.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub enum Load {
    /// Uniform gravity acceleration; potential `−m g·r` for every particle and body.
    Gravity(Vector),
    /// A potential energy `V(q, t)`.
    Potential(Expr),
    /// A Rayleigh dissipation function `D(q, q̇)`; contributes `−∂D/∂q̇_j`.
    Dissipation(Expr),
    /// A force at a point (the point's position vector).
    Force {
        /// The force.
        force: Vector,
        /// Where it acts.
        point: Vector,
    },
    /// A couple on body number `body` (index into [`System::bodies`]).
    Couple {
        /// The moment.
        moment: Vector,
        /// The body index.
        body: usize,
    },
    /// A generalized force on coordinate number `coordinate`.
    GeneralizedForce {
        /// The scalar.
        force: Expr,
        /// The coordinate index.
        coordinate: usize,
    },
}

/// The form of a constraint equation.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub enum ConstraintForm {
    /// `f(q, t) = 0`.
    Holonomic(Expr),
    /// `c(q, q̇, t) = 0`, linear in the rates.
    Velocity(Expr),
}

/// A named constraint.
#[derive(Clone, Debug)]
pub struct Constraint {
    /// Its name (for reports).
    pub name: String,
    /// The equations it imposes.
    pub equations: Vec<ConstraintForm>,
}

/// The checked input: coordinates (named; `Expr::coordinate(name)` in expressions), bodies and
/// loads. Invariant: every load's body or coordinate index is in range (enforced by
/// [`System::add_load`]).
#[derive(Clone, Debug, Default)]
pub struct System {
    coordinates: Vec<String>,
    driven: Vec<(String, Expr)>,
    parameters: Vec<(String, Option<Expr>)>,
    inputs: Vec<(String, Option<Expr>)>,
    particles: Vec<Particle>,
    bodies: Vec<RigidBody>,
    loads: Vec<Load>,
    constraints: Vec<Constraint>,
    points: Vec<(String, Vector)>,
    constants: Vec<(String, Expr)>,
}

impl System {
    /// An empty system.
    #[must_use]
    pub fn new() -> System {
        System::default()
    }

    /// Adds an independent coordinate; returns its index.
    pub fn add_coordinate(&mut self, name: &str) -> usize {
        self.coordinates.push(name.to_string());
        self.coordinates.len() - 1
    }

    /// Records a driven coordinate with its motion `q = f(t)` (already substituted in every
    /// expression by the caller).
    pub fn add_driven(&mut self, name: &str, motion: Expr) {
        self.driven.push((name.to_string(), motion));
    }

    /// Adds a parameter with its value, if known.
    pub fn add_parameter(&mut self, name: &str, value: Option<Expr>) {
        self.parameters.push((name.to_string(), value));
    }

    /// Records a named constant of the model with its value (already substituted in every
    /// expression by the caller); reports print products containing the value with the name.
    pub fn add_constant(&mut self, name: &str, value: Expr) {
        self.constants.push((name.to_string(), value));
    }

    /// The named constants, with their values in the parameters.
    #[must_use]
    pub fn constants(&self) -> &[(String, Expr)] {
        &self.constants
    }

    /// Records an input that stays a symbol in the expressions, with its constant value if
    /// the model gives one (equilibria hold inputs at these values).
    pub fn add_input(&mut self, name: &str, value: Option<Expr>) {
        self.inputs.push((name.to_string(), value));
    }

    /// Gives a parameter a new value; `false` when there is no parameter of that name. The
    /// equations stay valid: they hold parameters as symbols.
    pub fn set_parameter(&mut self, name: &str, value: Option<Expr>) -> bool {
        match self.parameters.iter_mut().find(|(n, _)| n == name) {
            Some(entry) => {
                entry.1 = value;
                true
            }
            None => false,
        }
    }

    /// Gives an input (kept as a symbol) a new constant value; `false` when there is no such
    /// input.
    pub fn set_input(&mut self, name: &str, value: Option<Expr>) -> bool {
        match self.inputs.iter_mut().find(|(n, _)| n == name) {
            Some(entry) => {
                entry.1 = value;
                true
            }
            None => false,
        }
    }

    /// Inputs kept as symbols, with their constant values.
    #[must_use]
    pub fn inputs(&self) -> &[(String, Option<Expr>)] {
        &self.inputs
    }

    /// Adds a particle.
    pub fn add_particle(&mut self, particle: Particle) {
        self.particles.push(particle);
    }

    /// Adds a rigid body; returns its index.
    pub fn add_body(&mut self, body: RigidBody) -> usize {
        self.bodies.push(body);
        self.bodies.len() - 1
    }

    /// Adds a load. Returns `false` (and drops it) when its body or coordinate index is out
    /// of range.
    pub fn add_load(&mut self, load: Load) -> bool {
        let ok = match &load {
            Load::Couple { body, .. } => *body < self.bodies.len(),
            Load::GeneralizedForce { coordinate, .. } => *coordinate < self.coordinates.len(),
            _ => true,
        };
        if ok {
            self.loads.push(load);
        }
        ok
    }

    /// Adds a constraint.
    pub fn add_constraint(&mut self, constraint: Constraint) {
        self.constraints.push(constraint);
    }

    /// Records a named point's position, for reports (kinematics of every point the model
    /// names, not only those that carry mass).
    pub fn add_point(&mut self, name: &str, position: Vector) {
        self.points.push((name.to_string(), position));
    }

    /// The named points and their positions, in the order they were declared.
    #[must_use]
    pub fn points(&self) -> &[(String, Vector)] {
        &self.points
    }

    /// The independent coordinates' names.
    #[must_use]
    pub fn coordinates(&self) -> &[String] {
        &self.coordinates
    }

    /// Driven coordinates with their motion.
    #[must_use]
    pub fn driven(&self) -> &[(String, Expr)] {
        &self.driven
    }

    /// Parameters with their values.
    #[must_use]
    pub fn parameters(&self) -> &[(String, Option<Expr>)] {
        &self.parameters
    }

    /// The particles.
    #[must_use]
    pub fn particles(&self) -> &[Particle] {
        &self.particles
    }

    /// The rigid bodies.
    #[must_use]
    pub fn bodies(&self) -> &[RigidBody] {
        &self.bodies
    }

    /// The loads.
    #[must_use]
    pub fn loads(&self) -> &[Load] {
        &self.loads
    }

    /// The acceleration of gravity: the sum of every [`Load::Gravity`] (zero without one).
    /// Every method reads gravity from here, so two `gravity` loads act as their sum in all of
    /// them (Newton–Euler's moment equation once took only the first, and its reaction then
    /// disagreed with Lagrange I's).
    #[must_use]
    pub fn gravity(&self) -> Vector {
        let mut g = [Expr::zero(), Expr::zero(), Expr::zero()];
        for load in &self.loads {
            if let Load::Gravity(a) = load {
                for k in 0..3 {
                    g[k] += a[k];
                }
            }
        }
        g
    }

    /// The constraints.
    #[must_use]
    pub fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }

    /// Removes coordinate `index` and maps every expression through `f` (used when a
    /// constraint eliminates a coordinate).
    pub(crate) fn eliminate(&mut self, index: usize, f: &dyn Fn(Expr) -> Expr) {
        self.coordinates.remove(index);
        let v = |x: &mut Vector| {
            for e in x.iter_mut() {
                *e = f(*e);
            }
        };
        for p in &mut self.particles {
            p.mass = f(p.mass);
            v(&mut p.position);
        }
        for b in &mut self.bodies {
            b.mass = f(b.mass);
            v(&mut b.centre);
            for row in &mut b.rotation {
                v(row);
            }
            for row in &mut b.inertia {
                v(row);
            }
        }
        let mut loads = Vec::new();
        for load in self.loads.drain(..) {
            let load = match load {
                Load::Gravity(mut g) => {
                    v(&mut g);
                    Load::Gravity(g)
                }
                Load::Potential(e) => Load::Potential(f(e)),
                Load::Dissipation(e) => Load::Dissipation(f(e)),
                Load::Force {
                    mut force,
                    mut point,
                } => {
                    v(&mut force);
                    v(&mut point);
                    Load::Force { force, point }
                }
                Load::Couple { mut moment, body } => {
                    v(&mut moment);
                    Load::Couple { moment, body }
                }
                Load::GeneralizedForce { force, coordinate } => {
                    // A generalized force on the eliminated coordinate would need the virtual
                    // work through the elimination; it is dropped here and reported by the
                    // caller, which refuses to eliminate such a coordinate.
                    if coordinate == index {
                        continue;
                    }
                    let coordinate = if coordinate > index {
                        coordinate - 1
                    } else {
                        coordinate
                    };
                    Load::GeneralizedForce {
                        force: f(force),
                        coordinate,
                    }
                }
            };
            loads.push(load);
        }
        self.loads = loads;
        for c in &mut self.constraints {
            for e in &mut c.equations {
                *e = match e {
                    ConstraintForm::Holonomic(x) => ConstraintForm::Holonomic(f(*x)),
                    ConstraintForm::Velocity(x) => ConstraintForm::Velocity(f(*x)),
                };
            }
        }
    }
}
