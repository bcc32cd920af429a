//! Constraint reactions, two independent ways, and whether they agree.
//!
//! **Lagrange I.** The constraint is *released*: the bodies on one side of it get redundant
//! coordinates `u_i` (a displacement along direction `d_i`), the constraint is dropped, and the
//! released system's Lagrange equations read `E_u − Q_u = R·∂r/∂u_i = R·d_i`. Evaluated at
//! `u = u̇ = ü = 0` on the motion of the constrained system (accelerations eliminated with its
//! pure equations of motion, other multipliers from its DAE form), that generalized force is
//! the multiplier, i.e. the reaction. A constraint with no point (a rope written as an
//! equation, a gear) gives the generalized reaction `Q^R_j` on each coordinate instead.
//!
//! **Newton–Euler.** The momentum equation of the released bodies, `Σ m a_G = Σ F + R`, with
//! `a_G` the second time derivative of the centres' positions on the same motion: `R·d_i =
//! (Σ m a_G − Σ m g − Σ F)·d_i + ∂V/∂u_i + ∂D/∂u̇_i` (springs and dampers attached to the
//! released bodies act through the gradient of their potential with respect to the
//! displacement).
//!
//! **Sign convention.** Every reaction is the force that the constraint exerts *on the released
//! bodies*, in inertial components.

use cas::{Expr, Matrix, Symbol};

use crate::equations::{angular_velocity, derive, derive_with, Equations, MechanicsError};
use crate::system::{ConstraintForm, Load, System, Vector};

/// What can go wrong computing reactions.
#[derive(Debug, thiserror::Error, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum ReactionError {
    /// The constrained or the released system has no equations of motion.
    #[error("reaction `{reaction}`: {source}")]
    Mechanics {
        /// The reaction.
        reaction: String,
        /// Why.
        source: MechanicsError,
    },
    /// The accelerations (and multipliers) cannot be solved for.
    #[error("the equations of motion cannot be solved for the accelerations")]
    Unsolvable,
    /// Another constraint moves with the released bodies; its multiplier would mix in.
    #[error("reaction `{reaction}`: constraint `{other}` involves the released bodies too; release it as well or ask for a combined reaction")]
    Entangled {
        /// The reaction.
        reaction: String,
        /// The other constraint.
        other: String,
    },
    /// A constraint named in a reaction is unknown.
    #[error("no constraint `{0}`")]
    UnknownConstraint(String),
}

/// What a reaction transmits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ReleaseKind {
    /// A pin: a force, all components.
    Hinge,
    /// A contact: the normal force only, unilateral (push only, `N ≥ 0`).
    Contact,
    /// A rope: the tension along the rope only, unilateral (pull only, `T ≥ 0`).
    Rope,
    /// A rolling contact: normal force and friction.
    Rolling,
    /// A clamp (a weld): a force and a couple.
    Clamp,
}

impl ReleaseKind {
    /// The word of the model language.
    #[must_use]
    pub fn word(self) -> &'static str {
        match self {
            ReleaseKind::Hinge => "hinge",
            ReleaseKind::Contact => "contact",
            ReleaseKind::Rope => "rope",
            ReleaseKind::Rolling => "rolling",
            ReleaseKind::Clamp => "clamp",
        }
    }

    /// Whether the constraint can only push (or only pull).
    #[must_use]
    pub fn is_unilateral(self) -> bool {
        matches!(self, ReleaseKind::Contact | ReleaseKind::Rope)
    }
}

/// A constraint released at a point: the system lowered again with redundant displacements.
#[derive(Clone, Debug)]
pub struct Release {
    /// The reaction's name.
    pub name: String,
    /// What it transmits.
    pub kind: ReleaseKind,
    /// The point's name and position (constrained system).
    pub point: (String, Vector),
    /// The released bodies' and particles' names (for reports).
    pub members: Vec<String>,
    /// The released system: the displacements are extra coordinates, the constraint (if it
    /// was written as one) is dropped.
    pub system: System,
    /// The displacement coordinates with the (unit) direction each moves the members along.
    pub displacements: Vec<(String, Vector)>,
    /// For a clamp (and, to check that no couple is needed, a hinge or a rolling contact):
    /// the small-rotation coordinates, with the axis each turns the members about (through the
    /// point). Empty otherwise.
    pub rotations: Vec<(String, Vector)>,
    /// For a rolling contact: the unit normal (into the body) that splits the force into the
    /// normal force, which can only push, and friction.
    pub normal: Option<Vector>,
    /// Indices of the released particles in the system (same in both systems).
    pub particles: Vec<usize>,
    /// Indices of the released rigid bodies.
    pub bodies: Vec<usize>,
}

/// A reaction asked for.
#[derive(Clone, Debug)]
pub enum ReactionRequest {
    /// A force at a point, by release.
    Release(Release),
    /// The generalized reaction of a constraint written as an equation (or a gear): its
    /// multipliers. `without` is the system with that constraint dropped.
    Constraint {
        /// The constraint's name.
        name: String,
        /// The system with the constraint dropped.
        without: System,
    },
    /// The generalized force that drives a driven coordinate `q = f(t)`: `E_q − Q_q` of the
    /// system in which `q` is free, on the motion.
    Driven {
        /// The coordinate.
        name: String,
        /// The system with the coordinate free.
        without: System,
        /// Its prescribed motion `f(t)`.
        motion: Expr,
    },
}

/// A method that gave a reaction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Lagrange's equations of the first kind.
    LagrangeI,
    /// Newton–Euler: momentum equation of the released bodies.
    NewtonEuler,
}

impl Method {
    /// Its name in reports and JSON.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Method::LagrangeI => "lagrange_1",
            Method::NewtonEuler => "newton_euler",
        }
    }
}

/// How the two methods were compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Agreement {
    /// Equal normal forms.
    Exact,
    /// The normal forms differ but the values agree at random states (relative 1e-9).
    Numeric,
    /// They disagree: a bug, reported as such.
    Disagree,
    /// Only one method applies.
    Single,
}

impl Agreement {
    /// What it means, for people.
    #[must_use]
    pub fn verdict(self) -> &'static str {
        match self {
            Agreement::Exact => "agree exactly (equal normal forms)",
            Agreement::Numeric => "agree numerically at random states",
            Agreement::Disagree => "DISAGREE: this is a bug, please report it",
            Agreement::Single => "one method",
        }
    }

    /// Its name in reports and JSON.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Agreement::Exact => "exact",
            Agreement::Numeric => "numeric",
            Agreement::Disagree => "disagree",
            Agreement::Single => "single",
        }
    }
}

/// A computed reaction, as a function of `(q, q̇, t)` of the constrained system.
#[derive(Clone, Debug)]
pub struct Reaction {
    /// Its name.
    pub name: String,
    /// What it transmits (`None` for a generalized reaction).
    pub kind: Option<ReleaseKind>,
    /// The point's name and position, for a force at a point.
    pub point: Option<(String, Vector)>,
    /// The bodies the force acts on.
    pub members: Vec<String>,
    /// The force on the released bodies, inertial components (Lagrange I).
    pub force: Option<Vector>,
    /// For a clamp: the reaction couple on the released bodies, inertial components.
    pub couple: Option<Vector>,
    /// For a hinge or a rolling contact, which transmit no couple: the couple about the point
    /// that the motion nevertheless needs, when it is not zero. Then other supports built into
    /// the coordinates act on the released bodies (the force is their total with this one), or
    /// the joint transmits a couple (ask for a `clamp`).
    pub unbalanced_couple: Option<Vector>,
    /// For a rolling contact with a normal: the friction force, `R − N n`.
    pub friction: Option<Vector>,
    /// For a contact or rope: the scalar along the given direction (`N`, `T`), and the unit
    /// direction.
    pub along: Option<(Expr, Vector)>,
    /// For a constraint written as an equation: the generalized reaction on each coordinate,
    /// `Q^R_j` (Lagrange I), and the multipliers of its rows.
    pub generalized: Vec<(String, Expr)>,
    /// The multipliers `λ` (`M q̈ + Aᵀλ = f`), for a generalized reaction.
    pub multipliers: Vec<Expr>,
    /// Whether this is the generalized force driving a driven coordinate (in `generalized`).
    pub driving: bool,
    /// The methods that agree.
    pub methods: Vec<Method>,
    /// How they were compared.
    pub agreement: Agreement,
}

/// The motion of the constrained system: how to replace every coordinate (eliminated ones by
/// their value), and accelerations and multipliers as functions of the state.
struct Motion {
    substitutions: Vec<Vec<(Expr, Expr)>>,
    accelerations: Vec<(Expr, Expr)>,
    multipliers: Vec<Expr>,
    constraint_names: Vec<String>,
}

impl Motion {
    fn of(equations: &Equations) -> Result<Motion, ReactionError> {
        let n = equations.coordinates().len();
        let m = equations.constraint_names().len();
        let (accelerations, multipliers) = match equations.accelerations() {
            Some(a) if m == 0 => (a.to_vec(), Vec::new()),
            _ => {
                // Rows that depend on the others (a rolling contact's normal row, say) would make
                // the DAE singular; their multipliers are set to zero, which leaves `Aᵀλ`, the
                // generalized reaction, unchanged.
                let independent = independent_rows(equations.constraint_matrix());
                let kept: Vec<usize> = (0..m).filter(|k| independent[*k]).collect();
                let size = n + kept.len();
                let mut rows = vec![vec![Expr::zero(); size]; size];
                let mut rhs = Vec::with_capacity(size);
                for (i, row) in equations.mass_matrix().iter().enumerate() {
                    rows[i][..n].copy_from_slice(row);
                    rhs.push(equations.forcing()[i]);
                }
                for (slot, &k) in kept.iter().enumerate() {
                    for (j, a) in equations.constraint_matrix()[k].iter().enumerate() {
                        rows[n + slot][j] = *a;
                        rows[j][n + slot] = *a;
                    }
                    rhs.push(equations.constraint_rhs()[k]);
                }
                let matrix = Matrix::from_rows(rows).ok_or(ReactionError::Unsolvable)?;
                let x = matrix
                    .solve(&Matrix::column(rhs))
                    .map_err(|_| ReactionError::Unsolvable)?;
                let value = |i| {
                    x.get(i, 0)
                        .map(Expr::normal)
                        .ok_or(ReactionError::Unsolvable)
                };
                let a = (0..n).map(value).collect::<Result<Vec<_>, _>>()?;
                let mut l = vec![Expr::zero(); m];
                for (slot, &k) in kept.iter().enumerate() {
                    l[k] = value(n + slot)?;
                }
                (a, l)
            }
        };
        // Eliminations are applied in order: a value may name a coordinate eliminated later.
        let substitutions = equations
            .eliminated()
            .iter()
            .map(|e| {
                let v1 = e.value.dt();
                vec![
                    (Expr::coordinate(&e.coordinate), e.value),
                    (Expr::rate(&e.coordinate, 1), v1),
                    (Expr::rate(&e.coordinate, 2), v1.dt()),
                ]
            })
            .collect();
        let accelerations = equations
            .coordinates()
            .iter()
            .zip(accelerations)
            .map(|(q, a)| (Expr::rate(q, 2), a))
            .collect();
        Ok(Motion {
            substitutions,
            accelerations,
            multipliers,
            constraint_names: equations.constraint_names().to_vec(),
        })
    }

    /// `e` on the motion: eliminated coordinates replaced, then accelerations.
    fn on_motion(&self, e: Expr) -> Expr {
        let mut e = e;
        for pairs in &self.substitutions {
            e = e.subs(pairs);
        }
        e.subs(&self.accelerations).normal()
    }
}

/// Which rows of `a` are independent of the rows before them, judged by their values at a
/// pseudo-random state (Gram–Schmidt; a row whose remainder is below 1e-9 of its size is
/// dependent: at a random state that happens only for rows dependent everywhere). When a row
/// cannot be evaluated every row is kept.
fn independent_rows(a: &[Vec<Expr>]) -> Vec<bool> {
    let env = |s: Symbol| Some(sample(s, 11));
    let mut keep = vec![true; a.len()];
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for (k, row) in a.iter().enumerate() {
        let values: Result<Vec<f64>, _> = row.iter().map(|e| e.eval(&env)).collect();
        let Ok(mut v) = values else {
            return vec![true; a.len()];
        };
        let size = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        for b in &basis {
            let p: f64 = v.iter().zip(b).map(|(x, y)| x * y).sum();
            for (x, y) in v.iter_mut().zip(b) {
                *x -= p * y;
            }
        }
        let rest = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if rest > 1e-9 * size.max(f64::MIN_POSITIVE) {
            basis.push(v.iter().map(|x| x / rest).collect());
        } else {
            keep[k] = false;
        }
    }
    keep
}

fn dot(a: &Vector, b: &Vector) -> Expr {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `u = u̇ = ü = 0` for every displacement.
fn at_rest(displacements: &[(String, Vector)]) -> Vec<(Expr, Expr)> {
    displacements
        .iter()
        .flat_map(|(u, _)| {
            [
                (Expr::coordinate(u), Expr::zero()),
                (Expr::rate(u, 1), Expr::zero()),
                (Expr::rate(u, 2), Expr::zero()),
            ]
        })
        .collect()
}

/// Residuals `E_j − Q_j + Σ_k A_kj λ_k` of the system `without` (a constraint dropped, maybe
/// displacements added) on the motion of the constrained system, for every coordinate of
/// `without`. Other constraints' rows are matched to the constrained system's by name, in order.
fn residuals(
    name: &str,
    without: &System,
    motion: &Motion,
    zero: &[(Expr, Expr)],
) -> Result<Vec<(String, Expr)>, ReactionError> {
    let released = derive_with(without, false).map_err(|source| ReactionError::Mechanics {
        reaction: name.to_string(),
        source,
    })?;
    let mut used = vec![false; motion.constraint_names.len()];
    let mut terms: Vec<Expr> = released
        .lagrange_lhs()
        .iter()
        .zip(released.generalized_forces())
        .map(|(e, q)| *e - *q)
        .collect();
    for (row, other) in released
        .constraint_matrix()
        .iter()
        .zip(released.constraint_names())
    {
        let position = motion
            .constraint_names
            .iter()
            .zip(&used)
            .position(|(n, u)| n == other && !u);
        let Some(k) = position else {
            return Err(ReactionError::Entangled {
                reaction: name.to_string(),
                other: other.clone(),
            });
        };
        used[k] = true;
        for (term, a) in terms.iter_mut().zip(row) {
            *term += *a * motion.multipliers[k];
        }
    }
    Ok(released
        .coordinates()
        .iter()
        .zip(terms)
        .map(|(q, r)| (q.clone(), motion.on_motion(r.subs(zero))))
        .collect())
}

/// Checks that no constraint of the released system moves with the displacements.
fn check_disentangled(release: &Release) -> Result<(), ReactionError> {
    let symbols: Vec<Symbol> = release
        .displacements
        .iter()
        .chain(&release.rotations)
        .flat_map(|(u, _)| [Expr::coordinate(u), Expr::rate(u, 1)])
        .filter_map(Expr::as_symbol)
        .collect();
    for c in release.system.constraints() {
        for form in &c.equations {
            let e = match form {
                ConstraintForm::Holonomic(e) | ConstraintForm::Velocity(e) => *e,
            };
            if symbols.iter().any(|s| !e.diff(*s).is_zero()) {
                return Err(ReactionError::Entangled {
                    reaction: release.name.clone(),
                    other: c.name.clone(),
                });
            }
        }
    }
    Ok(())
}

/// Whether a point moves with the release's redundant displacements (loads at such points act
/// on the released bodies).
fn moved_by(release: &Release) -> impl Fn(&Vector) -> bool {
    let symbols: Vec<Symbol> = release
        .displacements
        .iter()
        .filter_map(|(u, _)| Expr::coordinate(u).as_symbol())
        .collect();
    move |e: &Vector| {
        e.iter()
            .any(|x| symbols.iter().any(|s| !x.diff(*s).is_zero()))
    }
}

/// Newton–Euler: `R·d_i` from the momentum equation of the released bodies.
fn newton_euler(
    original: &System,
    release: &Release,
    motion: &Motion,
    zero: &[(Expr, Expr)],
) -> Vec<Expr> {
    let mut momentum_rate: Vector = [Expr::zero(), Expr::zero(), Expr::zero()];
    let mut weight: Vector = momentum_rate;
    let mut mass = Expr::zero();
    let mut add = |m: Expr, r: &Vector| {
        for (k, x) in r.iter().enumerate() {
            momentum_rate[k] += m * x.dt().dt();
        }
        mass += m;
    };
    for &i in &release.particles {
        if let Some(p) = original.particles().get(i) {
            add(p.mass, &p.position);
        }
    }
    for &i in &release.bodies {
        if let Some(b) = original.bodies().get(i) {
            add(b.mass, &b.centre);
        }
    }
    let moves = moved_by(release);
    let mut applied: Vector = [Expr::zero(), Expr::zero(), Expr::zero()];
    let mut potential = Expr::zero();
    let mut dissipation = Expr::zero();
    for load in release.system.loads() {
        match load {
            Load::Gravity(g) => {
                for (k, x) in g.iter().enumerate() {
                    weight[k] += mass * *x;
                }
            }
            Load::Force { force, point } if moves(point) => {
                for (k, x) in force.iter().enumerate() {
                    applied[k] += *x;
                }
            }
            Load::Potential(v) => potential += *v,
            Load::Dissipation(d) => dissipation += *d,
            _ => {}
        }
    }
    release
        .displacements
        .iter()
        .map(|(u, d)| {
            let newton: Vector = [0, 1, 2].map(|k| momentum_rate[k] - weight[k] - applied[k]);
            let r = released_balance(&newton, d, u, potential, dissipation).subs(zero);
            motion.on_motion(r)
        })
        .collect()
}

fn cross(a: &Vector, b: &Vector) -> Vector {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn minus(a: &Vector, b: &Vector) -> Vector {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Newton–Euler for a clamp: the couple `C·e_i` from the angular momentum equation of the
/// released bodies about the point `P`, `Σ (r − P) × m a + Σ Ḣ_G = Σ (r − P) × F + Σ C_applied +
/// C` (the reaction force at `P` has no moment about it), springs and dampers through
/// `∂V/∂ψ_i`, `∂D/∂ψ̇_i`.
fn moment_equation(
    original: &System,
    release: &Release,
    motion: &Motion,
    zero: &[(Expr, Expr)],
) -> Vec<Expr> {
    if release.rotations.is_empty() {
        return Vec::new();
    }
    let pivot = release.point.1;
    let mut inertial: Vector = [Expr::zero(), Expr::zero(), Expr::zero()];
    let mut gravity_moment: Vector = inertial;
    let mut spin: Vector = inertial;
    let gravity: Vector = release
        .system
        .loads()
        .iter()
        .find_map(|l| match l {
            Load::Gravity(g) => Some(*g),
            _ => None,
        })
        .unwrap_or([Expr::zero(), Expr::zero(), Expr::zero()]);
    let mut add = |m: Expr, r: &Vector| {
        let arm = minus(r, &pivot);
        let a: Vector = r.map(|x| x.dt().dt());
        let ma: Vector = a.map(|x| m * x);
        let mg: Vector = gravity.map(|x| m * x);
        let (t, w) = (cross(&arm, &ma), cross(&arm, &mg));
        for k in 0..3 {
            inertial[k] += t[k];
            gravity_moment[k] += w[k];
        }
    };
    for &i in &release.particles {
        if let Some(p) = original.particles().get(i) {
            add(p.mass, &p.position);
        }
    }
    for &i in &release.bodies {
        if let Some(b) = original.bodies().get(i) {
            add(b.mass, &b.centre);
            // H_G = R I Rᵀ ω, differentiated in time.
            let r = &b.rotation;
            let w = angular_velocity(r);
            let wb: Vec<Expr> = (0..3)
                .map(|i| (0..3).map(|k| r[k][i] * w[k]).sum())
                .collect();
            let hb: Vec<Expr> = (0..3)
                .map(|i| (0..3).map(|j| b.inertia[i][j] * wb[j]).sum())
                .collect();
            for (k, total) in spin.iter_mut().enumerate() {
                let h: Expr = (0..3).map(|i| r[k][i] * hb[i]).sum();
                *total += h.normal().dt();
            }
        }
    }
    for (total, s) in inertial.iter_mut().zip(spin) {
        *total += s;
    }
    let moves = moved_by(release);
    let mut applied: Vector = [Expr::zero(), Expr::zero(), Expr::zero()];
    let mut potential = Expr::zero();
    let mut dissipation = Expr::zero();
    for load in release.system.loads() {
        match load {
            Load::Force { force, point } if moves(point) => {
                let at: Vector = point.map(|x| x.subs(zero));
                let m = cross(&minus(&at, &pivot), force);
                for k in 0..3 {
                    applied[k] += m[k];
                }
            }
            Load::Couple { moment, body } if release.bodies.contains(body) => {
                for k in 0..3 {
                    applied[k] += moment[k];
                }
            }
            Load::Potential(v) => potential += *v,
            Load::Dissipation(d) => dissipation += *d,
            _ => {}
        }
    }
    release
        .rotations
        .iter()
        .map(|(psi, axis)| {
            let euler: Vector = [0, 1, 2].map(|k| inertial[k] - gravity_moment[k] - applied[k]);
            motion.on_motion(released_balance(&euler, axis, psi, potential, dissipation).subs(zero))
        })
        .collect()
}

/// Above this many terms the exact comparison is skipped for the numeric one: the normal form
/// of a difference of two large rational functions costs far more than five evaluations.
const EXACT_TERMS: usize = 4000;

/// Whether `a` and `b` agree: exactly, or at a few pseudo-random points.
fn compare(a: Expr, b: Expr) -> Agreement {
    if a.term_count() + b.term_count() <= EXACT_TERMS && (a - b).normal().is_zero() {
        return Agreement::Exact;
    }
    let agree = (0..5u64).all(|round| {
        let env = |s: Symbol| Some(sample(s, round));
        match (a.eval(&env), b.eval(&env)) {
            (Ok(x), Ok(y)) => (x - y).abs() <= 1e-9 * (1.0 + x.abs().max(y.abs())),
            _ => false,
        }
    });
    if agree {
        Agreement::Numeric
    } else {
        Agreement::Disagree
    }
}

/// A value in `[0.35, 1.65]` drawn from a symbol's name, order and a round number.
fn sample(s: Symbol, round: u64) -> f64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325 ^ round.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    for b in s.name().bytes().chain([s.order()]) {
        h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
    }
    0.35 + 1.3 * ((h >> 11) as f64 / (1u64 << 53) as f64)
}

fn worst(a: Agreement, b: Agreement) -> Agreement {
    let rank = |x: Agreement| match x {
        Agreement::Exact => 0,
        Agreement::Numeric => 1,
        Agreement::Single => 2,
        Agreement::Disagree => 3,
    };
    if rank(a) >= rank(b) {
        a
    } else {
        b
    }
}

fn release_reaction(
    original: &System,
    release: &Release,
    motion: &Motion,
) -> Result<Reaction, ReactionError> {
    check_disentangled(release)?;
    let extra: Vec<(String, Vector)> = release
        .displacements
        .iter()
        .chain(&release.rotations)
        .cloned()
        .collect();
    let zero = at_rest(&extra);
    let residuals = residuals(&release.name, &release.system, motion, &zero)?;
    let lagrange: Vec<Expr> = release
        .displacements
        .iter()
        .map(|(u, _)| {
            residuals
                .iter()
                .find(|(q, _)| q == u)
                .map_or_else(Expr::zero, |(_, r)| *r)
        })
        .collect();
    let turning: Vec<Expr> = release
        .rotations
        .iter()
        .map(|(psi, _)| {
            residuals
                .iter()
                .find(|(q, _)| q == psi)
                .map_or_else(Expr::zero, |(_, r)| *r)
        })
        .collect();
    let mut newton = newton_euler(original, release, motion, &zero);
    newton.extend(moment_equation(original, release, motion, &zero));
    let agreement = lagrange
        .iter()
        .chain(&turning)
        .zip(&newton)
        .map(|(a, b)| compare(*a, *b))
        .fold(Agreement::Exact, worst);
    let turned = (!release.rotations.is_empty()).then(|| {
        let mut couple: Vector = [Expr::zero(), Expr::zero(), Expr::zero()];
        for (c, (_, axis)) in turning.iter().zip(&release.rotations) {
            for (k, x) in axis.iter().enumerate() {
                couple[k] += *c * *x;
            }
        }
        couple.map(Expr::normal)
    });
    let (couple, unbalanced_couple) = if release.kind == ReleaseKind::Clamp {
        (turned, None)
    } else {
        let needed = turned.filter(|c| {
            c.iter()
                .any(|x| compare(*x, Expr::zero()) == Agreement::Disagree)
        });
        (None, needed)
    };
    let mut force: Vector = [Expr::zero(), Expr::zero(), Expr::zero()];
    for (r, (_, d)) in lagrange.iter().zip(&release.displacements) {
        for (k, x) in d.iter().enumerate() {
            force[k] += *r * *x;
        }
    }
    let force = force.map(Expr::normal);
    let along = match (release.kind.is_unilateral(), release.displacements.first()) {
        (true, Some((_, d))) => lagrange.first().map(|n| (*n, *d)),
        _ => release.normal.map(|n| (dot(&force, &n).normal(), n)),
    };
    let friction = release.normal.and_then(|n| {
        let (value, _) = along?;
        Some([0, 1, 2].map(|k| (force[k] - value * n[k]).normal()))
    });
    let methods = if agreement == Agreement::Disagree {
        vec![Method::LagrangeI]
    } else {
        vec![Method::LagrangeI, Method::NewtonEuler]
    };
    Ok(Reaction {
        name: release.name.clone(),
        kind: Some(release.kind),
        point: Some(release.point.clone()),
        members: release.members.clone(),
        force: Some(force),
        couple,
        unbalanced_couple,
        friction,
        along,
        generalized: Vec::new(),
        multipliers: Vec::new(),
        driving: false,
        methods,
        agreement,
    })
}

fn constraint_reaction(
    name: &str,
    without: &System,
    equations: &Equations,
    motion: &Motion,
) -> Result<Reaction, ReactionError> {
    let rows: Vec<usize> = equations
        .constraint_names()
        .iter()
        .enumerate()
        .filter(|(_, n)| *n == name)
        .map(|(k, _)| k)
        .collect();
    let (generalized, multipliers) = if rows.is_empty() {
        // Eliminated by integration: the residuals of the system without it are its
        // generalized reaction on every coordinate, the eliminated one included.
        let generalized = residuals(name, without, motion, &[])?;
        (generalized, Vec::new())
    } else {
        let multipliers: Vec<Expr> = rows.iter().map(|&k| motion.multipliers[k]).collect();
        let generalized = equations
            .coordinates()
            .iter()
            .enumerate()
            .map(|(j, q)| {
                let r: Expr = rows
                    .iter()
                    .map(|&k| -(equations.constraint_matrix()[k][j] * motion.multipliers[k]))
                    .sum();
                (q.clone(), r.normal())
            })
            .collect();
        (generalized, multipliers)
    };
    Ok(Reaction {
        name: name.to_string(),
        kind: None,
        point: None,
        members: Vec::new(),
        force: None,
        couple: None,
        unbalanced_couple: None,
        friction: None,
        along: None,
        generalized,
        multipliers,
        driving: false,
        methods: vec![Method::LagrangeI],
        agreement: Agreement::Single,
    })
}

fn driving_force(
    name: &str,
    without: &System,
    prescribed: Expr,
    motion: &Motion,
) -> Result<Reaction, ReactionError> {
    let rate = prescribed.dt();
    let driven = [
        (Expr::coordinate(name), prescribed),
        (Expr::rate(name, 1), rate),
        (Expr::rate(name, 2), rate.dt()),
    ];
    let generalized: Vec<(String, Expr)> = residuals(name, without, motion, &driven)?
        .into_iter()
        .filter(|(q, _)| q == name)
        .collect();
    Ok(Reaction {
        name: name.to_string(),
        kind: None,
        point: None,
        members: Vec::new(),
        force: None,
        couple: None,
        unbalanced_couple: None,
        friction: None,
        along: None,
        generalized,
        multipliers: Vec::new(),
        driving: true,
        methods: vec![Method::LagrangeI],
        agreement: Agreement::Single,
    })
}

/// A momentum (or angular-momentum) balance of the released bodies along the direction of a
/// released coordinate, with the forces that enter through the potential and the Rayleigh
/// function of that coordinate: what the reaction must supply.
fn released_balance(
    balance: &Vector,
    direction: &Vector,
    coordinate: &str,
    potential: Expr,
    dissipation: Expr,
) -> Expr {
    let gradient = Expr::coordinate(coordinate)
        .as_symbol()
        .map_or_else(Expr::zero, |s| potential.diff(s));
    let drag = Expr::rate(coordinate, 1)
        .as_symbol()
        .map_or_else(Expr::zero, |s| dissipation.diff(s));
    dot(balance, direction) + gradient + drag
}

/// The reactions asked for, on the motion of `system`.
///
/// # Errors
/// The system has no equations of motion, they cannot be solved for the accelerations, or a
/// released constraint is entangled with another one.
pub fn reactions(
    system: &System,
    requests: &[ReactionRequest],
) -> Result<Vec<Reaction>, ReactionError> {
    let equations = derive(system).map_err(|source| ReactionError::Mechanics {
        reaction: "(the constrained system)".to_string(),
        source,
    })?;
    reactions_of(system, &equations, requests)
}

/// [`reactions`] when the equations of `system` are already derived.
///
/// # Errors
/// As [`reactions`].
pub fn reactions_of(
    system: &System,
    equations: &Equations,
    requests: &[ReactionRequest],
) -> Result<Vec<Reaction>, ReactionError> {
    let motion = Motion::of(equations)?;
    requests
        .iter()
        .map(|request| match request {
            ReactionRequest::Release(release) => release_reaction(system, release, &motion),
            ReactionRequest::Constraint { name, without } => {
                if !system.constraints().iter().any(|c| &c.name == name) {
                    return Err(ReactionError::UnknownConstraint(name.clone()));
                }
                constraint_reaction(name, without, equations, &motion)
            }
            ReactionRequest::Driven {
                name,
                without,
                motion: prescribed,
            } => driving_force(name, without, *prescribed, &motion),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comparison_is_exact_then_numeric_then_a_disagreement() {
        let x = Expr::coordinate("x");
        let one = x.sin().powi(2) + x.cos().powi(2);
        assert_eq!(compare(one, Expr::one()), Agreement::Exact);
        // √(x²) is not reduced to x by the normal form, but the two agree for x > 0, where
        // the random states are drawn.
        let root = x.powi(2).sqrt();
        if !(root - x).normal().is_zero() {
            assert_eq!(compare(root, x), Agreement::Numeric);
        }
        assert_eq!(compare(x, x + Expr::one()), Agreement::Disagree);
    }

    #[test]
    fn dependent_constraint_rows_are_found() {
        let (x, y) = (Expr::coordinate("x"), Expr::coordinate("y"));
        let rows = vec![
            vec![x.cos(), x.sin()],
            vec![2 * x.cos(), 2 * x.sin()],
            vec![y, Expr::one()],
        ];
        assert_eq!(independent_rows(&rows), vec![true, false, true]);
    }
}
