//! Kinematics, energies, generalized forces and Lagrange's equations of the second kind:
//! `E_j = d/dt(∂L/∂q̇_j) − ∂L/∂q_j − Q_j = 0`, gathered as `M(q,t) q̈ = f(q,q̇,t)`.

use std::cell::Cell;
use std::sync::OnceLock;

use cas::{Expr, Matrix, NormalForm, SolveError, Symbol, WorkLimitError};

use crate::system::{ConstraintForm, Load, Rotation, System, Vector};

/// What can go wrong deriving the equations.
#[derive(Debug, thiserror::Error, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum MechanicsError {
    /// The mass matrix is singular: the model does not determine these coordinates'
    /// accelerations.
    #[error("the mass matrix is singular: the accelerations of {} are not determined", coordinates.join(", "))]
    SingularMassMatrix {
        /// The coordinates involved.
        coordinates: Vec<String>,
    },
    /// An equation is not linear in the accelerations.
    #[error("the equation of `{coordinate}` is not linear in the accelerations")]
    NotLinearInAccelerations {
        /// The coordinate.
        coordinate: String,
    },
    /// A velocity constraint is not linear in the rates.
    #[error("constraint `{constraint}` is not linear in the rates")]
    NonlinearConstraint {
        /// The constraint.
        constraint: String,
    },
    /// The model has no independent coordinate left.
    #[error("no independent coordinate is left")]
    NoCoordinates,
    /// The symbolic work went past a limit of the symbolic core ([`cas::WorkLimits`]).
    #[error("{}: {error}", part.as_ref().map_or_else(|| "deriving the equations of motion".to_string(), |p| format!("deriving the {p}")))]
    WorkLimit {
        /// The part of the system being derived when the limit was hit (`None`: the equations
        /// as a whole, past the parts).
        part: Option<Part>,
        /// The limit hit.
        error: WorkLimitError,
    },
}

/// A part of a [`System`] whose derivation can be told apart (for [`MechanicsError::WorkLimit`]).
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Part {
    /// The kinetic energy of the particle at this point.
    Particle(String),
    /// The kinetic energy of this body.
    Body(String),
    /// The potential of the load with this index in [`System::loads`].
    Load(usize),
    /// The constraint of this name: its rates, its eliminated coordinate, or its
    /// acceleration-level row.
    Constraint(String),
}

impl std::fmt::Display for Part {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Part::Particle(p) => write!(f, "kinetic energy of particle `{p}`"),
            Part::Body(b) => write!(f, "kinetic energy of body `{b}`"),
            Part::Load(i) => write!(f, "potential of load {}", i + 1),
            Part::Constraint(c) => write!(f, "constraint `{c}`"),
        }
    }
}

/// Which part of the system is being derived, for the error of a work limit: the first part
/// during which the limit was hit.
type Progress = Cell<Option<Part>>;

fn working_on(progress: &Progress, part: Option<Part>) {
    if cas::limit_hit().is_none() {
        progress.set(part);
    }
}

/// A coordinate eliminated by an integrable velocity constraint.
#[derive(Clone, Debug)]
pub struct Elimination {
    /// The eliminated coordinate.
    pub coordinate: String,
    /// The constraint that eliminated it.
    pub constraint: String,
    /// Its value in terms of the remaining coordinates (integration constant zero).
    pub value: Expr,
}

/// A conserved quantity, verified to have a zero time derivative on the equations.
#[derive(Clone, Debug)]
pub struct FirstIntegral {
    /// `"energy"`, `"jacobi"`, or `"momentum"`.
    pub kind: &'static str,
    /// The coordinate, for a conjugate momentum.
    pub coordinate: Option<String>,
    /// The expression.
    pub value: Expr,
    /// Conserved only while each of these generalized forces is zero: they depend on inputs
    /// and parameters alone (a motor couple `C`, a pull `F`), so holding the inputs at values
    /// that make them vanish keeps the quantity constant. Empty when conserved outright.
    pub conditions: Vec<Expr>,
}

/// Lagrange's equations of a system. Invariant: `mass_matrix` is n×n and non-singular (or, with
/// constraints kept by multipliers, `[M Aᵀ; A 0]` is: a coordinate without inertia that they fix),
/// `forcing`, `lhs`, `generalized_forces` have n entries, n = `coordinates.len()`.
#[derive(Clone, Debug)]
pub struct Equations {
    coordinates: Vec<String>,
    /// `L`, in working form; `K = L + V` is rebuilt from it when asked for (keeping both
    /// held another O(n³) terms for an n-link chain).
    lagrangian: LazyTree,
    kinetic_energy: OnceLock<Expr>,
    potential_energy: Expr,
    generalized_forces: Vec<Expr>,
    lhs: OnceLock<Vec<Expr>>,
    mass_matrix: Vec<Vec<Expr>>,
    forcing: Vec<Expr>,
    constraint_matrix: Vec<Vec<Expr>>,
    constraint_rhs: Vec<Expr>,
    constraint_names: Vec<String>,
    constraint_rank: usize,
    eliminated: Vec<Elimination>,
    accelerations: Option<Vec<Expr>>,
    first_integrals: Vec<FirstIntegral>,
}

impl Equations {
    /// The degrees of freedom: the independent virtual displacements, `n − rank A` — the
    /// coordinates left after the integrable constraints eliminated theirs, less the
    /// independent constraints kept with multipliers, holonomic or not (a knife edge's three
    /// coordinates and one rolling condition: 2).
    #[must_use]
    pub fn degrees_of_freedom(&self) -> usize {
        self.coordinates.len().saturating_sub(self.constraint_rank)
    }

    /// The independent coordinates.
    #[must_use]
    pub fn coordinates(&self) -> &[String] {
        &self.coordinates
    }
    /// `K`.
    #[must_use]
    pub fn kinetic_energy(&self) -> Expr {
        *self.kinetic_energy.get_or_init(|| {
            let potential = self.potential_energy.normal_form();
            self.lagrangian.form.add(&potential).to_expr()
        })
    }
    /// `V` (the seed's `U = −V`).
    #[must_use]
    pub fn potential_energy(&self) -> Expr {
        self.potential_energy
    }
    /// `L = K − V`.
    #[must_use]
    pub fn lagrangian(&self) -> Expr {
        self.lagrangian.tree()
    }
    /// `Q_j`, damping included.
    #[must_use]
    pub fn generalized_forces(&self) -> &[Expr] {
        &self.generalized_forces
    }
    /// `d/dt(∂L/∂q̇_j) − ∂L/∂q_j` (normal form), which equals `Q_j` on motions.
    #[must_use]
    pub fn lagrange_lhs(&self) -> &[Expr] {
        self.lhs.get_or_init(|| {
            lagrange_lhs(
                &self.coordinates,
                &self.mass_matrix,
                &self.forcing,
                &self.generalized_forces,
            )
        })
    }
    /// `M(q, t)`, rows.
    #[must_use]
    pub fn mass_matrix(&self) -> &[Vec<Expr>] {
        &self.mass_matrix
    }
    /// `f(q, q̇, t)` with `M q̈ = f` (plus `−Aᵀλ` when there are constraint multipliers).
    #[must_use]
    pub fn forcing(&self) -> &[Expr] {
        &self.forcing
    }
    /// `A` of the constraints kept with multipliers (`A q̈ = b`), rows.
    #[must_use]
    pub fn constraint_matrix(&self) -> &[Vec<Expr>] {
        &self.constraint_matrix
    }
    /// `b` of `A q̈ = b`.
    #[must_use]
    pub fn constraint_rhs(&self) -> &[Expr] {
        &self.constraint_rhs
    }
    /// The names of the constraint rows of `A`.
    #[must_use]
    pub fn constraint_names(&self) -> &[String] {
        &self.constraint_names
    }
    /// The coordinates eliminated by integrable constraints.
    #[must_use]
    pub fn eliminated(&self) -> &[Elimination] {
        &self.eliminated
    }
    /// The explicit `q̈ = M⁻¹ f` for one or two degrees of freedom without multipliers.
    #[must_use]
    pub fn accelerations(&self) -> Option<&[Expr]> {
        self.accelerations.as_deref()
    }
    /// The verified first integrals.
    #[must_use]
    pub fn first_integrals(&self) -> &[FirstIntegral] {
        &self.first_integrals
    }
}

/// `E_j = Σ_k M_jk q̈_k − f_j + Q_j`, rebuilt from the mass matrix and the forcing, which
/// split `E − Q` exactly (the coefficients of the accelerations and the rest); keeping the
/// left-hand sides' working forms held as many terms as `M` and `f` together.
fn lagrange_lhs(
    coordinates: &[String],
    mass_matrix: &[Vec<Expr>],
    forcing: &[Expr],
    forces: &[Expr],
) -> Vec<Expr> {
    let accelerations: Vec<NormalForm> = coordinates
        .iter()
        .map(|c| Expr::rate(c, 2).normal_form())
        .collect();
    let row = |((masses, f), q): ((&Vec<Expr>, &Expr), &Expr)| {
        let mut parts: Vec<NormalForm> = masses
            .iter()
            .zip(&accelerations)
            .map(|(m, a)| m.normal_form().mul(a))
            .collect();
        parts.push(f.normal_form().neg());
        parts.push(q.normal_form());
        NormalForm::sum(&parts).to_expr()
    };
    mass_matrix
        .iter()
        .zip(forcing)
        .zip(forces)
        .map(row)
        .collect()
}

/// A result kept in working form whose canonical tree is built when first asked for. The trees
/// of `L` and the left-hand sides `E_j` have as many terms as the mass matrix and the
/// forcing together (O(n³) for an n-link chain), and building a tree costs more than the
/// derivative it comes from; a simulation or a sweep never reads them.
#[derive(Clone, Debug)]
struct LazyTree {
    form: NormalForm,
    tree: OnceLock<Expr>,
}

impl LazyTree {
    fn new(form: NormalForm) -> LazyTree {
        LazyTree {
            form,
            tree: OnceLock::new(),
        }
    }

    /// The canonical tree, the same `Expr` as `form.to_expr()`.
    fn tree(&self) -> Expr {
        *self.tree.get_or_init(|| self.form.to_expr())
    }
}

fn dot(a: &Vector, b: &Vector) -> Expr {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sym(e: Expr) -> Option<Symbol> {
    e.as_symbol()
}

fn depends_on(e: Expr, symbols: &[Symbol]) -> bool {
    symbols.iter().any(|s| !e.diff(*s).is_zero())
}

/// The angular velocity `ω` (inertial components) from `ω× = Ṙ Rᵀ`.
#[must_use]
pub fn angular_velocity(r: &Rotation) -> Vector {
    let rd: Vec<Vec<Expr>> = r
        .iter()
        .map(|row| row.iter().map(|e| e.dt()).collect())
        .collect();
    let w = |i: usize, j: usize| -> Expr { (0..3).map(|k| rd[i][k] * r[j][k]).sum::<Expr>() };
    [
        ((w(2, 1) - w(1, 2)) / 2).normal(),
        ((w(0, 2) - w(2, 0)) / 2).normal(),
        ((w(1, 0) - w(0, 1)) / 2).normal(),
    ]
}

/// Eliminates coordinates with integrable velocity constraints (constant-ratio linear
/// relations among rates) and returns the rest as multiplier rows `(name, c)` with `c = 0`
/// at the velocity level.
fn eliminate(
    system: &mut System,
    eliminated: &mut Vec<Elimination>,
    progress: &Progress,
) -> Result<Vec<(String, Expr)>, MechanicsError> {
    let mut kept = Vec::new();
    let constraints = system.constraints().to_vec();
    let mut pending: Vec<(String, ConstraintForm)> = constraints
        .into_iter()
        .flat_map(|c| {
            let name = c.name.clone();
            c.equations.into_iter().map(move |e| (name.clone(), e))
        })
        .collect();
    while let Some((name, form)) = pending.first().cloned() {
        pending.remove(0);
        working_on(progress, Some(Part::Constraint(name.clone())));
        let coordinates = system.coordinates().to_vec();
        // Holonomic constraints stay implicit, with multipliers (the DAE form); only
        // velocity constraints that integrate eliminate a coordinate.
        let c = match form {
            ConstraintForm::Holonomic(f) => {
                let c = f.dt();
                if !c.is_zero() {
                    kept.push((name, c));
                }
                continue;
            }
            ConstraintForm::Velocity(c) => c,
        };
        if c.is_zero() {
            continue;
        }
        let rates: Vec<Expr> = coordinates.iter().map(|q| Expr::rate(q, 1)).collect();
        let Some((a, b)) = c.affine_coefficients(&rates) else {
            return Err(MechanicsError::NonlinearConstraint { constraint: name });
        };
        let mut state: Vec<Symbol> = coordinates
            .iter()
            .filter_map(|q| sym(Expr::coordinate(q)))
            .collect();
        state.extend(rates.iter().filter_map(|r| sym(*r)));
        state.extend(sym(Expr::time()));
        let pivot = (0..a.len()).rev().find(|&k| !a[k].is_zero());
        let Some(k) = pivot else {
            kept.push((name, c));
            continue;
        };
        let ratios: Vec<Expr> = a.iter().map(|x| (*x / a[k]).normal()).collect();
        let offset = (b / a[k]).normal();
        let forced = system
            .loads()
            .iter()
            .any(|l| matches!(l, Load::GeneralizedForce { coordinate, .. } if *coordinate == k));
        let integrable = !forced
            && offset.is_zero()
            && ratios.iter().all(|r| !depends_on(*r, &state))
            && coordinates.len() > 1;
        if !integrable {
            kept.push((name, c));
            continue;
        }
        let value = (0..a.len())
            .filter(|&j| j != k)
            .map(|j| -(ratios[j] * Expr::coordinate(&coordinates[j])))
            .sum::<Expr>()
            .normal();
        let pairs: Vec<(Expr, Expr)> = (0..3u8)
            .map(|order| {
                let mut v = value;
                for _ in 0..order {
                    v = v.dt();
                }
                let target = if order == 0 {
                    Expr::coordinate(&coordinates[k])
                } else {
                    Expr::rate(&coordinates[k], order)
                };
                (target, v)
            })
            .collect();
        system.eliminate(k, &|e: Expr| e.subs(&pairs));
        for (_, f) in &mut pending {
            *f = match f {
                ConstraintForm::Holonomic(x) => ConstraintForm::Holonomic(x.subs(&pairs)),
                ConstraintForm::Velocity(x) => ConstraintForm::Velocity(x.subs(&pairs)),
            };
        }
        for (_, x) in &mut kept {
            *x = x.subs(&pairs);
        }
        eliminated.push(Elimination {
            coordinate: coordinates[k].clone(),
            constraint: name,
            value,
        });
    }
    Ok(kept.into_iter().filter(|(_, c)| !c.is_zero()).collect())
}

/// Derives Lagrange's equations `M(q,t) q̈ = f(q,q̇,t)` of `system`:
/// `K = Σ ½ m v² + Σ (½ m v_G² + ½ ω_Bᵀ I_G ω_B)` with `ω_B = Rᵀω`, `V` from gravity
/// (`−m g·r`), springs and potentials, `Q_j = Σ F·∂r/∂q_j + Σ C·∂ω/∂q̇_j − ∂D/∂q̇_j + Q_j^gen`,
/// `E_j = d/dt(∂L/∂q̇_j) − ∂L/∂q_j − Q_j`, `M_jk = ∂E_j/∂q̈_k`, `f = −E|_{q̈=0}`.
///
/// # Errors
/// A singular mass matrix (naming the coordinates), equations or constraints not linear in
/// the accelerations or rates, or no coordinate left.
pub fn derive(system: &System) -> Result<Equations, MechanicsError> {
    derive_all(system, true, true)
}

/// [`derive()`] without looking for first integrals (`first_integrals()` is empty): `K`, `V`,
/// Lagrange's equations, `M` and `f` — the work of tools that only form the equations, for
/// comparing with them (bench/compare).
///
/// # Errors
/// As [`derive()`].
pub fn derive_without_first_integrals(system: &System) -> Result<Equations, MechanicsError> {
    derive_all(system, true, false)
}

/// [`derive`] for a released system (reactions): a singular mass matrix is accepted and no
/// first integral is looked for, since the released system is only evaluated on the
/// constrained motion, never solved or integrated.
pub(crate) fn derive_released(system: &System) -> Result<Equations, MechanicsError> {
    derive_all(system, false, false)
}

/// [`derive_limited`] within the work limits of the symbolic core ([`cas::limited`]).
fn derive_all(
    system: &System,
    check_mass_matrix: bool,
    first_integrals_wanted: bool,
) -> Result<Equations, MechanicsError> {
    let progress = Progress::new(None);
    let (result, hit) = cas::run_limited(|| {
        derive_limited(system, check_mass_matrix, first_integrals_wanted, &progress)
    });
    match hit {
        None => result,
        Some(error) => Err(MechanicsError::WorkLimit {
            part: progress.take(),
            error,
        }),
    }
}

fn derive_limited(
    system: &System,
    check_mass_matrix: bool,
    first_integrals_wanted: bool,
    progress: &Progress,
) -> Result<Equations, MechanicsError> {
    let mut system = system.clone();
    let mut eliminated = Vec::new();
    let kept = eliminate(&mut system, &mut eliminated, progress)?;
    working_on(progress, None);
    let coordinates = system.coordinates().to_vec();
    if coordinates.is_empty() {
        return Err(MechanicsError::NoCoordinates);
    }
    let vars = Variables::of(&coordinates);
    let (kinetic, omegas) = kinetic_energy(&system, progress);
    let (potential, forces) = potential_and_forces(&system, &omegas, &vars, progress);
    working_on(progress, None);
    let lagrangian = kinetic.sub(&potential);
    // `K` is read again only by the first integrals (`Equations` rebuilds it from `L` and
    // `V`); dropped here, its O(n³) terms are not held through the rows.
    let kinetic = first_integrals_wanted.then_some(kinetic);
    let rows = lagrange_rows(
        &lagrangian,
        &forces,
        &vars,
        &coordinates,
        first_integrals_wanted,
    )?;
    let (constraint_matrix, constraint_rhs, constraint_names) =
        constraint_rows(&kept, &vars, progress)?;
    working_on(progress, None);
    if check_mass_matrix {
        check_singular(&rows.mass_matrix, &coordinates).or_else(|error| {
            // A coordinate without inertia of its own is well posed when the constraints
            // kept with multipliers fix it: then `[M Aᵀ; A 0]` is regular though `M` is not.
            if constrained_regular(&rows.mass_matrix, &constraint_matrix) {
                Ok(())
            } else {
                Err(error)
            }
        })?;
    }
    let constraint_rank = crate::constraint_rank::generic_rank(&system, &constraint_matrix);
    let accelerations = if coordinates.len() <= 2 && kept.is_empty() {
        explicit_accelerations(&rows.mass_matrix, &rows.forcing)
    } else {
        None
    };
    let first_integrals = if let Some(kinetic) = &kinetic {
        let energies = Energies {
            kinetic,
            potential: &potential,
            lagrangian: &lagrangian,
            forces: &forces,
        };
        first_integrals(
            &energies,
            &rows,
            &kept,
            &constraint_matrix,
            &vars,
            &coordinates,
        )
    } else {
        Vec::new()
    };
    Ok(Equations {
        coordinates,
        lagrangian: LazyTree::new(lagrangian),
        kinetic_energy: OnceLock::new(),
        potential_energy: potential.to_expr(),
        generalized_forces: forces,
        lhs: OnceLock::new(),
        mass_matrix: rows.mass_matrix,
        forcing: rows.forcing,
        constraint_matrix,
        constraint_rhs,
        constraint_rank,
        constraint_names,
        eliminated,
        accelerations,
        first_integrals,
    })
}

/// The coordinates, rates and accelerations of the system as expressions and symbols.
struct Variables {
    qd: Vec<Expr>,
    qdd: Vec<Expr>,
    q_sym: Vec<Option<Symbol>>,
    qd_sym: Vec<Option<Symbol>>,
}

impl Variables {
    fn of(coordinates: &[String]) -> Variables {
        let q: Vec<Expr> = coordinates.iter().map(|c| Expr::coordinate(c)).collect();
        let qd: Vec<Expr> = coordinates.iter().map(|c| Expr::rate(c, 1)).collect();
        let qdd: Vec<Expr> = coordinates.iter().map(|c| Expr::rate(c, 2)).collect();
        let q_sym = q.iter().map(|e| sym(*e)).collect();
        let qd_sym = qd.iter().map(|e| sym(*e)).collect();
        Variables {
            qd,
            qdd,
            q_sym,
            qd_sym,
        }
    }
}

fn partial(e: Expr, s: Option<Symbol>) -> Expr {
    s.map_or_else(Expr::zero, |s| e.diff(s))
}

/// `K = Σ ½ m v² + Σ (½ m v_G² + ½ ω_Bᵀ I_G ω_B)`, and each body's angular velocity.
///
/// Each part's term is brought to normal form on its own, so that a work limit is hit (and
/// reported) at the particle or body whose term outgrows it.
fn kinetic_energy(system: &System, progress: &Progress) -> (NormalForm, Vec<Vector>) {
    // The parts are summed at the end, in one merge (`NormalForm::sum`).
    let mut parts: Vec<NormalForm> = Vec::new();
    for p in system.particles() {
        working_on(progress, Some(Part::Particle(p.name.clone())));
        // `½ m v·v` on working forms: the velocity's trees were built only to be converted
        // back, and `v·v` as a tree re-sorted every product before its expansion.
        let v = p.position.map(|x| x.normal_form().dt());
        let speed_squared = NormalForm::sum(&v.map(|c| c.mul(&c)));
        parts.push((p.mass / 2).normal_form().mul(&speed_squared));
    }
    let mut omegas: Vec<Vector> = Vec::with_capacity(system.bodies().len());
    for b in system.bodies() {
        working_on(progress, Some(Part::Body(b.name.clone())));
        let w = &angular_velocity(&b.rotation);
        let v: Vector = b.centre.map(|x| x.dt().normal());
        let r = &b.rotation;
        let wb: Vec<Expr> = (0..3)
            .map(|i| (0..3).map(|k| r[k][i] * w[k]).sum::<Expr>().normal())
            .collect();
        let mut rot = Expr::zero();
        for i in 0..3 {
            for j in 0..3 {
                rot += wb[i] * b.inertia[i][j] * wb[j];
            }
        }
        parts.push((b.mass * dot(&v, &v) / 2 + rot / 2).normal_form());
        omegas.push(*w);
    }
    (NormalForm::sum(&parts), omegas)
}

/// `V` (gravity, springs, potentials) and `Q_j` by virtual work, damping `−∂D/∂q̇_j` included.
///
/// Each load's potential is brought to normal form on its own, so that a work limit is hit
/// (and reported) at the load that outgrows it.
fn potential_and_forces(
    system: &System,
    omegas: &[Vector],
    vars: &Variables,
    progress: &Progress,
) -> (NormalForm, Vec<Expr>) {
    let n = vars.qd.len();
    let mut potential = NormalForm::zero();
    let mut dissipation = Expr::zero();
    let mut forces = vec![Expr::zero(); n];
    let gravity_load = system
        .loads()
        .iter()
        .position(|l| matches!(l, Load::Gravity(_)));
    if let Some(index) = gravity_load {
        working_on(progress, Some(Part::Load(index)));
        let g = system.gravity();
        let weight = system
            .particles()
            .iter()
            .map(|p| p.mass * dot(&g, &p.position))
            .chain(system.bodies().iter().map(|b| b.mass * dot(&g, &b.centre)))
            .sum::<Expr>();
        potential = potential.sub(&weight.normal_form());
    }
    for (index, load) in system.loads().iter().enumerate() {
        working_on(progress, Some(Part::Load(index)));
        match load {
            Load::Gravity(_) => {}
            Load::Potential(v) => potential = potential.add(&v.normal_form()),
            Load::Dissipation(d) => dissipation += *d,
            Load::Force { force, point } => {
                for (f, s) in forces.iter_mut().zip(&vars.q_sym) {
                    let dr: Vector = point.map(|x| partial(x, *s));
                    *f += dot(force, &dr);
                }
            }
            Load::Couple { moment, body } => {
                if let Some(w) = omegas.get(*body) {
                    for (f, s) in forces.iter_mut().zip(&vars.qd_sym) {
                        let dw: Vector = w.map(|x| partial(x, *s));
                        *f += dot(moment, &dw);
                    }
                }
            }
            Load::GeneralizedForce { force, coordinate } => {
                if let Some(f) = forces.get_mut(*coordinate) {
                    *f += *force;
                }
            }
        }
    }
    working_on(progress, None);
    for (f, s) in forces.iter_mut().zip(&vars.qd_sym) {
        *f = (*f - partial(dissipation, *s)).normal();
    }
    (potential, forces)
}

/// Lagrange's equations row by row, with the working forms the first integrals need.
struct Rows {
    /// `∂L/∂q̇_j`, kept only when the first integrals are wanted (zero otherwise).
    momenta: Vec<NormalForm>,
    /// Whether `∂L/∂q_j` is zero (a cyclic coordinate).
    cyclic: Vec<bool>,
    /// `E_j`, kept only where the energy integral's check reads them
    /// ([`ENERGY_CHECK_MAX_DOF`]).
    lhs_forms: Vec<NormalForm>,
    mass_matrix: Vec<Vec<Expr>>,
    forcing: Vec<Expr>,
}

/// `∂f/∂s` for each of `symbols` (zero where there is no symbol), in one reading of `f`.
fn gradient(f: &NormalForm, symbols: &[Option<Symbol>]) -> Vec<NormalForm> {
    let present: Vec<Symbol> = symbols.iter().flatten().copied().collect();
    let mut parts = f.gradient(&present).into_iter();
    let part = |s: &Option<Symbol>| {
        s.and_then(|_| parts.next())
            .unwrap_or_else(NormalForm::zero)
    };
    symbols.iter().map(part).collect()
}

/// `E_j = d/dt(∂L/∂q̇_j) − ∂L/∂q_j`, `M_jk = ∂(E_j − Q_j)/∂q̈_k`, `f = −(E − Q)|_{q̈=0}`,
/// on working forms: only the results that are kept become trees (building a large tree
/// costs more than the derivative it comes from).
///
/// `M` and `f` become trees without their working forms remembered
/// ([`NormalForm::to_expr_unremembered`]): every later stage reads the trees, and for an
/// n-link chain their O(n³) terms held twice were most of the memory. The momenta are
/// dropped row by row unless `keep_momenta` (the first integrals read them).
fn lagrange_rows(
    lagrangian: &NormalForm,
    forces: &[Expr],
    vars: &Variables,
    coordinates: &[String],
    keep_momenta: bool,
) -> Result<Rows, MechanicsError> {
    let n = coordinates.len();
    let mut momenta = gradient(lagrangian, &vars.qd_sym);
    let generalized_gradient = gradient(lagrangian, &vars.q_sym);
    let cyclic = generalized_gradient
        .iter()
        .map(NormalForm::is_zero)
        .collect();
    let mut lhs_forms = Vec::with_capacity(n);
    let mut mass_matrix = Vec::with_capacity(n);
    let mut forcing = Vec::with_capacity(n);
    // Each `∂L/∂q_j` is dropped once its row is formed.
    for (j, partial_q) in generalized_gradient.into_iter().enumerate() {
        let e = momenta[j].dt().sub(&partial_q);
        drop(partial_q);
        if !keep_momenta {
            momenta[j] = NormalForm::zero();
        }
        let with_forces = if forces[j].is_literal_zero() {
            e.clone()
        } else {
            e.sub(&forces[j].normal_form())
        };
        let Some((row, rest)) = with_forces.affine_coefficients(&vars.qdd) else {
            return Err(MechanicsError::NotLinearInAccelerations {
                coordinate: coordinates[j].clone(),
            });
        };
        if n <= ENERGY_CHECK_MAX_DOF {
            lhs_forms.push(e);
        }
        mass_matrix.push(row.iter().map(NormalForm::to_expr_unremembered).collect());
        forcing.push(rest.neg().to_expr_unremembered());
    }
    Ok(Rows {
        momenta,
        cyclic,
        lhs_forms,
        mass_matrix,
        forcing,
    })
}

/// The constraint matrix, right-hand side and names of the constraints kept with
/// multipliers: `c = A q̇ + a₀ = 0` ⇒ `A q̈ = −(ċ with q̈ = 0)`.
#[allow(clippy::type_complexity)]
fn constraint_rows(
    kept: &[(String, Expr)],
    vars: &Variables,
    progress: &Progress,
) -> Result<(Vec<Vec<Expr>>, Vec<Expr>, Vec<String>), MechanicsError> {
    let mut constraint_matrix = Vec::new();
    let mut constraint_rhs = Vec::new();
    let mut constraint_names = Vec::new();
    for (name, c) in kept {
        working_on(progress, Some(Part::Constraint(name.clone())));
        let Some((row, rest)) = c.dt().affine_coefficients(&vars.qdd) else {
            return Err(MechanicsError::NonlinearConstraint {
                constraint: name.clone(),
            });
        };
        constraint_matrix.push(row);
        constraint_rhs.push((-rest).normal());
        constraint_names.push(name.clone());
    }
    Ok((constraint_matrix, constraint_rhs, constraint_names))
}

/// `q̈ = M⁻¹ f` in closed form (small systems only: the expressions swell with n).
fn explicit_accelerations(mass_matrix: &[Vec<Expr>], forcing: &[Expr]) -> Option<Vec<Expr>> {
    let n = forcing.len();
    Matrix::from_rows(mass_matrix.to_vec())
        .and_then(|m| m.solve(&Matrix::column(forcing.to_vec())).ok())
        .map(|x| {
            (0..n)
                .filter_map(|i| x.get(i, 0).map(Expr::normal))
                .collect()
        })
}

/// The energies and forces the first integrals are built from.
struct Energies<'a> {
    kinetic: &'a NormalForm,
    potential: &'a NormalForm,
    lagrangian: &'a NormalForm,
    forces: &'a [Expr],
}

/// The energy or Jacobi integral and the momenta of cyclic coordinates, each checked.
fn first_integrals(
    energies: &Energies<'_>,
    rows: &Rows,
    kept: &[(String, Expr)],
    constraint_matrix: &[Vec<Expr>],
    vars: &Variables,
    coordinates: &[String],
) -> Vec<FirstIntegral> {
    let n = coordinates.len();
    let mut state: Vec<Symbol> = vars
        .q_sym
        .iter()
        .chain(&vars.qd_sym)
        .flatten()
        .copied()
        .collect();
    state.extend(sym(Expr::time()));
    let mut first_integrals: Vec<FirstIntegral> =
        energy_integral(energies, rows, kept, vars, &state)
            .into_iter()
            .collect();
    for j in 0..n {
        let free_of_constraints = constraint_matrix.iter().all(|row| row[j].is_zero());
        if !free_of_constraints || !rows.cyclic[j] {
            continue;
        }
        if let Some(conditions) = condition_for(energies.forces[j], &state) {
            first_integrals.push(FirstIntegral {
                kind: "momentum",
                coordinate: Some(coordinates[j].clone()),
                value: rows.momenta[j].to_expr(),
                conditions,
            });
        }
    }
    first_integrals
}

/// A generalized force that depends on inputs and parameters only does not stop a
/// conservation law from holding while the inputs keep it at zero: it is a condition. One
/// that depends on the state (damping, a spring written as a force) does: `None`.
fn condition_for(f: Expr, state: &[Symbol]) -> Option<Vec<Expr>> {
    if f.is_zero() {
        Some(Vec::new())
    } else if depends_on(f, state) {
        None
    } else {
        Some(vec![f])
    }
}

/// Up to this many coordinates the energy integral is confirmed by its time derivative.
const ENERGY_CHECK_MAX_DOF: usize = 8;

/// The energy (or Jacobi) integral `h = Σ q̇ ∂L/∂q̇ − L`. Constraints kept with multipliers
/// do no work when they are `A q̇ = 0` with no rate-free term (scleronomic), so energy
/// survives them.
fn energy_integral(
    energies: &Energies<'_>,
    rows: &Rows,
    kept: &[(String, Expr)],
    vars: &Variables,
    state: &[Symbol],
) -> Option<FirstIntegral> {
    let n = vars.qd.len();
    let workless = kept.iter().all(|(_, c)| {
        c.affine_coefficients(&vars.qd)
            .is_some_and(|(_, offset)| offset.is_zero())
    });
    let time = sym(Expr::time());
    let lagrangian = energies.lagrangian;
    let explicit_time = workless && time.is_some_and(|t| !lagrangian.diff(t).is_zero());
    if explicit_time || !workless {
        return None;
    }
    let conditions: Vec<Expr> = energies
        .forces
        .iter()
        .map(|f| condition_for(*f, state))
        .collect::<Option<Vec<Vec<Expr>>>>()?
        .into_iter()
        .flatten()
        .collect();
    let qd = &vars.qd;
    let mut h_parts = vec![lagrangian.neg()];
    h_parts.extend((0..n).map(|j| qd[j].normal_form().mul(&rows.momenta[j])));
    let h = NormalForm::sum(&h_parts);
    // dh/dt = Σ q̇_j (E_j + Q_j) − ∂L/∂t identically; with Q = 0, no explicit time and
    // workless constraints h is conserved. The identity is checked rather than assumed
    // up to 8 degrees of freedom; beyond, the check costs more than the derivation and
    // the theorem (whose premises were checked exactly above) stands alone.
    let confirmed = n > ENERGY_CHECK_MAX_DOF || {
        let power = (0..n).fold(NormalForm::zero(), |p, j| {
            p.add(&qd[j].normal_form().mul(&rows.lhs_forms[j]))
        });
        h.dt().sub(&power).is_zero()
    };
    if !confirmed {
        return None;
    }
    let energy = energies.kinetic.add(energies.potential);
    let kind = if energy.sub(&h).is_zero() {
        "energy"
    } else {
        "jacobi"
    };
    Some(FirstIntegral {
        kind,
        coordinate: None,
        value: h.to_expr(),
        conditions,
    })
}

/// Whether the constrained system's matrix `[M Aᵀ; A 0]` is regular at generic points: the
/// accelerations and multipliers are then determined though `M` alone may be singular.
fn constrained_regular(mass: &[Vec<Expr>], constraints: &[Vec<Expr>]) -> bool {
    if constraints.is_empty() {
        return false;
    }
    let (n, m) = (mass.len(), constraints.len());
    let mut kkt: Vec<Vec<Expr>> = Vec::with_capacity(n + m);
    for (i, row) in mass.iter().enumerate() {
        let mut full = row.clone();
        full.extend(constraints.iter().map(|a| a[i]));
        kkt.push(full);
    }
    for a in constraints {
        let mut full = a.clone();
        full.extend(std::iter::repeat_n(Expr::zero(), m));
        kkt.push(full);
    }
    regular_at_sample_points(&kkt)
}

/// Whether `M` is regular at one of a few pseudo-random points (every symbol a value in
/// `[0.35, 1.65]` drawn from its name). A determinant that is not zero at one point is not
/// identically zero, so this settles the usual case in O(n³) flops; the exact determinant,
/// whose expression swell is exponential in n, is only needed when the numbers look singular.
fn regular_at_sample_points(mass: &[Vec<Expr>]) -> bool {
    let n = mass.len();
    (0..2u64).any(|round| {
        let env = |s: Symbol| {
            let mut h: u64 = 0xcbf2_9ce4_8422_2325 ^ round.wrapping_mul(0x9e37_79b9_7f4a_7c15);
            for b in s.name().bytes().chain([s.order()]) {
                h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
            }
            Some(0.35 + 1.3 * ((h >> 11) as f64 / (1u64 << 53) as f64))
        };
        let mut a = Vec::with_capacity(n);
        for row in mass {
            let values: Result<Vec<f64>, _> = row.iter().map(|e| e.eval(&env)).collect();
            match values {
                Ok(v) if v.iter().all(|x| x.is_finite()) => a.push(v),
                _ => return false,
            }
        }
        numerically_regular(a)
    })
}

/// Gaussian elimination with partial pivoting; regular when every pivot stays well above
/// rounding level relative to the matrix's size.
fn numerically_regular(mut a: Vec<Vec<f64>>) -> bool {
    let n = a.len();
    let scale = a
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()))
        .max(f64::MIN_POSITIVE);
    for col in 0..n {
        let Some(pivot) = (col..n).max_by(|&r, &s| a[r][col].abs().total_cmp(&a[s][col].abs()))
        else {
            return false;
        };
        if a[pivot][col].abs() <= 1e-9 * scale {
            return false;
        }
        a.swap(col, pivot);
        let pivot_row = a[col].clone();
        for row in a.iter_mut().skip(col + 1) {
            let factor = row[col] / pivot_row[col];
            for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                *x -= factor * p;
            }
        }
    }
    true
}

/// Errors when `M` is singular: a zero row names its coordinate; for up to four degrees of
/// freedom the determinant is checked exactly, and the coordinates of the pivot-less column
/// are named.
fn check_singular(mass: &[Vec<Expr>], coordinates: &[String]) -> Result<(), MechanicsError> {
    // The entries are normal forms, whose zero is the literal zero: testing them with
    // `is_zero` converted every entry of a large matrix back to its working form.
    let zero_rows: Vec<String> = mass
        .iter()
        .zip(coordinates)
        .filter(|(row, _)| row.iter().all(|e| e.is_literal_zero()))
        .map(|(_, c)| c.clone())
        .collect();
    if !zero_rows.is_empty() {
        return Err(MechanicsError::SingularMassMatrix {
            coordinates: zero_rows,
        });
    }
    if regular_at_sample_points(mass) {
        return Ok(());
    }
    if coordinates.len() <= 4 {
        let Some(m) = Matrix::from_rows(mass.to_vec()) else {
            return Ok(());
        };
        let singular = m.determinant().is_some_and(Expr::is_zero);
        if singular {
            let named = match m.solve(&Matrix::zeros(coordinates.len(), 1)) {
                Err(SolveError::Singular { column }) => coordinates
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| *k <= column)
                    .filter(|(k, _)| mass.iter().any(|row| !row[*k].is_zero()) || *k == column)
                    .map(|(_, c)| c.clone())
                    .collect(),
                _ => coordinates.to_vec(),
            };
            return Err(MechanicsError::SingularMassMatrix { coordinates: named });
        }
    }
    Ok(())
}
