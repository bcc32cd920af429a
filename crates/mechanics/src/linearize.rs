//! Linearized dynamics `M0 δq̈ + C0 δq̇ + K0 δq = B0 δu` about an equilibrium, and its
//! stability.
//!
//! With `M q̈ = f(q, q̇, u)`: `M0 = M(q0)`, `C0 = −∂f/∂q̇`, `K0 = −∂f/∂q`, `B0 = ∂f/∂u`, all at
//! `q = q0`, `q̇ = 0` (the `M q̈` term contributes nothing to `K0` because `q̈ = 0` at rest).
//!
//! Stability, never guessed:
//! * Lagrange–Dirichlet when the system is conservative at rest (`K0` is the Hessian of the
//!   effective potential `V − K|_{q̇=0}`, plus the potential of the generalized forces at rest
//!   when they have one — constant forces and couples — and `C0` has no dissipation of the
//!   wrong sign): a positive definite Hessian means *stable*;
//! * otherwise, and as a cross-check, Lyapunov's indirect method on the state matrix
//!   `A = [[0, I], [−M0⁻¹K0, −M0⁻¹C0]]`: an eigenvalue with a positive real part means
//!   *unstable*, all in the open left half-plane *asymptotically stable*, anything else
//!   *undecided by linearization*.

use cas::{Expr, Symbol};

use crate::equations::Equations;
use crate::equilibria::{environment, spin_rate, RestEquations, Values};

/// The symbolic linearization as functions of `q` (evaluate at an equilibrium).
#[derive(Clone, Debug)]
pub struct LinearModel {
    /// `M(q)`.
    pub mass: Vec<Vec<Expr>>,
    /// `−∂f/∂q̇` at rest.
    pub damping: Vec<Vec<Expr>>,
    /// `−∂f/∂q` at rest.
    pub stiffness: Vec<Vec<Expr>>,
    /// `∂f/∂u` at rest, one column per input.
    pub input: Vec<Vec<Expr>>,
    /// The inputs' names (columns of `input`).
    pub inputs: Vec<String>,
    /// The Hessian of the effective potential `V − K|_{q̇=0}`, with the potential of the
    /// generalized forces at rest added when they have one (constant forces and couples).
    pub hessian: Vec<Vec<Expr>>,
    /// For steady motions: Routh's reduced potential.
    pub routh: Option<Routh>,
}

/// Routh's reduced potential `V_R = V − K|_{q̇=0} + ½ pᵀ M_ff⁻¹ p` of steady motions, at fixed
/// momenta `p` of the spinning coordinates (symbols `p_{q}`).
#[derive(Clone, Debug)]
pub struct Routh {
    /// The momentum symbols, one per spinning coordinate.
    pub momenta: Vec<Expr>,
    /// `p_f = ∂K/∂q̇_f` at the steady motion (in `q` and the spin rates).
    pub momentum_values: Vec<Expr>,
    /// The Hessian of `V_R` in all coordinates (rows of cyclic ones are zero).
    pub hessian: Vec<Vec<Expr>>,
}

/// Builds Routh's reduced potential when some coordinates spin.
fn routh(
    equations: &Equations,
    rest: &RestEquations,
    zero_rates: &[(Expr, Expr)],
    steady: &[(Expr, Expr)],
) -> Option<Routh> {
    if rest.spinning.is_empty() {
        return None;
    }
    let names = equations.coordinates();
    let idx: Vec<usize> = rest
        .spinning
        .iter()
        .filter_map(|q| names.iter().position(|n| n == q))
        .collect();
    let kinetic = equations.kinetic_energy();
    let momenta: Vec<Expr> = rest
        .spinning
        .iter()
        .map(|q| Expr::symbol(&format!("p_{q}")))
        .collect();
    let momentum_values = rest
        .spinning
        .iter()
        .map(|q| {
            Expr::rate(q, 1)
                .as_symbol()
                .map_or(Expr::zero(), |r| kinetic.diff(r).subs(steady).normal())
        })
        .collect();
    let m = equations.mass_matrix();
    let m_ff: Vec<Vec<Expr>> = idx
        .iter()
        .map(|i| idx.iter().map(|j| m[*i][*j]).collect())
        .collect();
    let x = cas::Matrix::from_rows(m_ff)?
        .solve(&cas::Matrix::column(momenta.clone()))
        .ok()?;
    let quadratic: Expr = momenta
        .iter()
        .enumerate()
        .filter_map(|(k, p)| x.get(k, 0).map(|xk| *p * xk))
        .sum();
    let reduced =
        (equations.potential_energy() - kinetic.subs(zero_rates) + quadratic / 2).normal();
    let hessian = rest
        .symbols
        .iter()
        .map(|a| {
            let da = reduced.diff(*a);
            rest.symbols.iter().map(|b| da.diff(*b).normal()).collect()
        })
        .collect();
    Some(Routh {
        momenta,
        momentum_values,
        hessian,
    })
}

/// The criterion that decided (or failed to decide) an equilibrium's stability.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Criterion {
    /// Lagrange–Dirichlet: the Hessian of the effective potential is positive definite.
    LagrangeDirichlet,
    /// Lyapunov's indirect method: an eigenvalue has a positive real part (unstable).
    GrowingEigenvalue,
    /// Lyapunov's indirect method: every eigenvalue has a negative real part.
    DecayingEigenvalues,
    /// Undecided: the Hessian of the effective potential is singular (a critical case).
    SingularHessian,
    /// Undecided: the Hessian is not positive definite and no eigenvalue grows.
    IndefiniteHessian,
    /// Undecided: eigenvalues on the imaginary axis of a non-conservative system.
    ImaginaryAxis,
    /// Routh: the reduced potential's Hessian at fixed momenta is positive definite.
    Routh,
    /// An eigenvalue of the linearization about the steady motion grows (unstable).
    GrowingEigenvalueOfSteadyMotion,
    /// Undecided: the reduced potential's Hessian is not positive definite and no eigenvalue
    /// grows.
    IndefiniteReducedHessian,
    /// Decided for the `bound` coordinates after Routh reduction of the `free` ones (which
    /// drift at constant momentum).
    Reduced {
        /// What decided on the reduced system.
        criterion: Box<Criterion>,
        /// The coordinates the decision is about.
        bound: Vec<String>,
        /// The reduced coordinates.
        free: Vec<String>,
    },
}

impl std::fmt::Display for Criterion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let text = match self {
            Criterion::LagrangeDirichlet => "Lagrange–Dirichlet: the Hessian of the effective potential is positive definite",
            Criterion::GrowingEigenvalue => "Lyapunov (indirect): an eigenvalue of the linearization has a positive real part",
            Criterion::DecayingEigenvalues => "Lyapunov (indirect): every eigenvalue has a negative real part (asymptotically stable)",
            Criterion::SingularHessian => "undecided by linearization: the Hessian of the effective potential is singular (a critical case)",
            Criterion::IndefiniteHessian => "undecided by linearization: the Hessian is not positive definite and no eigenvalue has a positive real part",
            Criterion::ImaginaryAxis => "undecided by linearization: eigenvalues on the imaginary axis of a non-conservative system",
            Criterion::Routh => "Routh: the Hessian of the reduced potential V − K₀ + ½ pᵀ M_ff⁻¹ p at fixed momenta is positive definite (stable with respect to the non-cyclic coordinates)",
            Criterion::GrowingEigenvalueOfSteadyMotion => "Lyapunov (indirect): an eigenvalue of the linearization about the steady motion has a positive real part",
            Criterion::IndefiniteReducedHessian => "undecided by linearization: the reduced potential's Hessian is not positive definite and no eigenvalue has a positive real part",
            Criterion::Reduced { criterion, bound, free } => {
                return write!(
                    f,
                    "{criterion}, for ({}) after Routh reduction of the free coordinate(s) ({}), which drift at constant momentum",
                    bound.join(", "),
                    free.join(", ")
                );
            }
        };
        f.write_str(text)
    }
}

/// The numbers of a linearization at one equilibrium, with its stability.
#[derive(Clone, Debug)]
pub struct Linearized {
    /// `M0`.
    pub m0: Vec<Vec<f64>>,
    /// `C0`.
    pub c0: Vec<Vec<f64>>,
    /// `K0`.
    pub k0: Vec<Vec<f64>>,
    /// `B0` (n × inputs).
    pub b0: Vec<Vec<f64>>,
    /// `M0`, `C0`, `K0`, `B0` with the exact equilibrium substituted, when it is known.
    pub exact: Option<[Vec<Vec<Expr>>; 4]>,
    /// State matrix `A` (2n × 2n).
    pub a: Vec<Vec<f64>>,
    /// State input matrix `B` (2n × inputs).
    pub b: Vec<Vec<f64>>,
    /// Eigenvalues of `A` as (re, im).
    pub eigenvalues: Vec<(f64, f64)>,
    /// `ω²` of `K0 x = ω² M0 x` (symmetric part of `K0`), increasing; when `C0` couples the
    /// coordinates gyroscopically, those of the state matrix `A` instead (`(Im λ)²`, or
    /// `−(Re λ)²` for a divergent pair), equal to its eigenvalues; `None` when `M0` is not
    /// positive definite.
    pub omega_squared: Option<Vec<f64>>,
    /// Mode shapes (`xᵀ M0 x = 1`), one per `omega_squared`; empty when `C0` couples the
    /// coordinates gyroscopically (the modes are complex there).
    pub modes: Vec<Vec<f64>>,
    /// Damping ratios `ζ = −Re λ / |λ|` of the oscillatory eigenvalue pairs (Im λ > 0),
    /// by increasing `|λ|`.
    pub damping_ratios: Vec<f64>,
    /// The rank of the controllability matrix (`None` without inputs).
    pub controllability_rank: Option<usize>,
    /// `true` stable, `false` unstable, `None` undecided by linearization.
    pub stable: Option<bool>,
    /// Which criterion decided (its `Display` is the sentence the reports print).
    pub criterion: Criterion,
    /// Eigenvalues of the Hessian of the effective potential, when Lagrange–Dirichlet applied.
    pub hessian_eigenvalues: Option<Vec<f64>>,
    /// With constraints kept by multipliers: the linearization in independent coordinates
    /// `δq = N y` along the directions the constraints allow, from which `A`, the
    /// eigenvalues, the frequencies and the stability come (`m0`, `c0`, `k0`, `b0` stay the
    /// full matrices, `k0` with the constraints' curvature; `modes` are `N v`, in all the
    /// coordinates).
    pub reduced: Option<Reduced>,
}

/// The linearization on the constraint manifold at an equilibrium: `N` an orthonormal basis
/// of the null space of `A(q0)` (n × r, r = n − rank A), `δq = N y`, and
/// `NᵀM0N ÿ + NᵀC0N ẏ + NᵀK0N y = NᵀB0 δu` with `K0 = −∂(f − Aᵀλ)/∂q`.
#[derive(Clone, Debug)]
pub struct Reduced {
    /// The columns of `N`, each with one entry per coordinate.
    pub basis: Vec<Vec<f64>>,
    /// `NᵀM0N` (r × r).
    pub mass: Vec<Vec<f64>>,
    /// `NᵀC0N`.
    pub damping: Vec<Vec<f64>>,
    /// `NᵀK0N`.
    pub stiffness: Vec<Vec<f64>>,
    /// `NᵀB0` (r × inputs).
    pub input: Vec<Vec<f64>>,
}

/// One mode's part of the free response: `shape · (a c(t) + b s(t))` with `(c, s)` =
/// `(cos ωt, sin ωt / ω)`, `(cosh γt, sinh γt / γ)` for `ω² = −γ² < 0`, `(1, t)` for `ω² = 0`.
#[derive(Clone, Debug)]
pub struct ModalTerm {
    /// `ω²`.
    pub omega_squared: f64,
    /// The mode shape `x` (`xᵀ M0 x = 1`).
    pub shape: Vec<f64>,
    /// `xᵀ M0 δq(0)`.
    pub a: f64,
    /// `xᵀ M0 δq̇(0)`.
    pub b: f64,
}

/// Builds the symbolic linear model of a system's equations; `inputs` are the names of the
/// input symbols.
#[must_use]
pub fn linear_model(equations: &Equations, rest: &RestEquations, inputs: &[String]) -> LinearModel {
    let names = equations.coordinates();
    let zero_rates: Vec<(Expr, Expr)> = names
        .iter()
        .flat_map(|q| [Expr::rate(q, 1), Expr::rate(q, 2)].map(|r| (r, Expr::zero())))
        .collect();
    // At a steady motion the spinning coordinates keep their rates.
    let steady: Vec<(Expr, Expr)> = names
        .iter()
        .flat_map(|q| {
            let v = if rest.spinning.contains(q) {
                spin_rate(q)
            } else {
                Expr::zero()
            };
            [(Expr::rate(q, 1), v), (Expr::rate(q, 2), Expr::zero())]
        })
        .collect();
    let rate_symbols: Vec<Option<Symbol>> =
        names.iter().map(|q| Expr::rate(q, 1).as_symbol()).collect();
    let forcing = equations.forcing();
    let damping = forcing
        .iter()
        .map(|f| {
            rate_symbols
                .iter()
                .map(|r| match r {
                    Some(r) => (-f.diff(*r)).subs(&steady).normal(),
                    None => Expr::zero(),
                })
                .collect()
        })
        .collect();
    let stiffness = rest
        .jacobian
        .iter()
        .map(|row| row.iter().map(|j| (-*j).normal()).collect())
        .collect();
    let input_symbols: Vec<Option<Symbol>> =
        inputs.iter().map(|u| Expr::symbol(u).as_symbol()).collect();
    let input = rest
        .residuals
        .iter()
        .map(|f| {
            input_symbols
                .iter()
                .map(|u| u.map_or(Expr::zero(), |u| f.diff(u).normal()))
                .collect()
        })
        .collect();
    let effective =
        (equations.potential_energy() - equations.kinetic_energy().subs(&zero_rates)).normal();
    let mut hessian: Vec<Vec<Expr>> = rest
        .symbols
        .iter()
        .map(|a| {
            let da = effective.diff(*a);
            rest.symbols.iter().map(|b| da.diff(*b).normal()).collect()
        })
        .collect();
    if let Some(loads) = load_potential_hessian(equations, rest, &zero_rates) {
        for (row, load_row) in hessian.iter_mut().zip(loads) {
            for (h, l) in row.iter_mut().zip(load_row) {
                *h = (*h + l).normal();
            }
        }
    }
    if let Some(kept) = &rest.constraints {
        // On the constraint manifold the potential's Hessian gains the constraints' curvature
        // weighted by the multipliers: the Hessian of `V + λᵀΦ`, as `K0` does.
        for (row, curved) in hessian.iter_mut().zip(kept.curvature(&rest.symbols)) {
            for (h, c) in row.iter_mut().zip(curved) {
                *h = (*h + c).normal();
            }
        }
    }
    let routh = routh(equations, rest, &zero_rates, &steady);
    LinearModel {
        routh,
        mass: equations.mass_matrix().to_vec(),
        damping,
        stiffness,
        input,
        inputs: inputs.to_vec(),
        hessian,
    }
}

/// The Hessian `−∂Q/∂q` of the potential of the generalized forces at rest, when they have
/// one: `Q(q)` (rates at zero, inputs as symbols) is a gradient exactly when its Jacobian is
/// symmetric as a function of `q` (checked in the normal form, so for every value of the
/// inputs). Constant forces and couples fixed in the inertial frame (a push on a slider, a
/// motor torque, `generalized force C on theta`) pass, and their potential `−F·r`, `−C θ` then
/// counts in Lagrange–Dirichlet's criterion; a follower force, whose Jacobian is not
/// symmetric (circulatory), does not, and the eigenvalues decide as before.
fn load_potential_hessian(
    equations: &Equations,
    rest: &RestEquations,
    zero_rates: &[(Expr, Expr)],
) -> Option<Vec<Vec<Expr>>> {
    let forces: Vec<Expr> = equations
        .generalized_forces()
        .iter()
        .map(|q| q.subs(zero_rates).normal())
        .collect();
    if forces.iter().all(|q| q.is_zero()) {
        return None;
    }
    let jacobian: Vec<Vec<Expr>> = forces
        .iter()
        .map(|q| rest.symbols.iter().map(|s| q.diff(*s)).collect())
        .collect();
    let n = jacobian.len();
    let symmetric = (0..n).all(|i| (i + 1..n).all(|j| (jacobian[i][j] - jacobian[j][i]).is_zero()));
    symmetric.then(|| {
        jacobian
            .iter()
            .map(|row| row.iter().map(|x| (-*x).normal()).collect())
            .collect()
    })
}

/// What can go wrong evaluating a linearization.
#[derive(Debug, thiserror::Error, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum LinearizeError {
    /// An entry could not be evaluated (a missing value, or outside its domain).
    #[error("the linearization cannot be evaluated at the equilibrium: {0}")]
    Evaluation(String),
    /// The numeric eigenproblem failed.
    #[error("eigenproblem: {0}")]
    Eigen(#[from] numeric::eigen::EigenError),
}

/// The entries of `m` at the coordinates `q0` (in the order of `rest.symbols`) with `values`.
///
/// # Errors
/// [`LinearizeError::Evaluation`] when an entry does not evaluate to a finite number.
pub fn evaluate_matrix(
    m: &[Vec<Expr>],
    rest: &RestEquations,
    q0: &[f64],
    values: &Values,
) -> Result<Vec<Vec<f64>>, LinearizeError> {
    let base = environment(values);
    let env = |s: Symbol| {
        rest.symbols
            .iter()
            .position(|q| *q == s)
            .map(|i| q0[i])
            .or_else(|| base(s))
    };
    m.iter()
        .map(|row| {
            row.iter()
                .map(|e| match e.eval(&env) {
                    Ok(v) if v.is_finite() => Ok(v),
                    Ok(v) => Err(LinearizeError::Evaluation(format!("{e} = {v}"))),
                    Err(err) => Err(LinearizeError::Evaluation(err.to_string())),
                })
                .collect()
        })
        .collect()
}

pub(crate) fn substitute(m: &[Vec<Expr>], rest: &RestEquations, exact: &[Expr]) -> Vec<Vec<Expr>> {
    let pairs: Vec<(Expr, Expr)> = rest
        .symbols
        .iter()
        .zip(exact)
        .flat_map(|(q, v)| {
            let q = Expr::from_symbol(*q);
            let (s, c) = (v.sin(), v.cos());
            [(q.sin(), s), (q.cos(), c), (q.tan(), s / c), (q, *v)]
        })
        .collect();
    m.iter()
        .map(|row| row.iter().map(|e| e.subs(&pairs).normal()).collect())
        .collect()
}

/// Whether `C0` couples the coordinates gyroscopically (a skew-symmetric part, as about a
/// steady motion or in a rotating frame) without dissipating: the undamped natural frequencies
/// are then those of the whole linearization, not of `K0` and `M0` alone.
fn gyroscopic(c0: &[Vec<f64>]) -> bool {
    let n = c0.len();
    let scale = max_abs(c0);
    let part = |sign: f64| {
        (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .fold(0.0_f64, |m, (i, j)| {
                m.max((c0[i][j] + sign * c0[j][i]).abs() / 2.0)
            })
    };
    scale > 0.0 && part(-1.0) > 1e-9 * scale && part(1.0) <= 1e-9 * scale
}

/// `ω²` of each mode from the eigenvalues `λ` of the state matrix (2n of them, in pairs):
/// `ω²` = (Im λ)² for an oscillation (one of each conjugate pair), −(Re λ)² for a real pair
/// ±γ (divergent), 0 for a neutral pair; n values, ascending, as `K0 x = ω² M0 x` gives them
/// when there is no coupling.
fn frequencies_of_state_matrix(eigenvalues: &[(f64, f64)]) -> Vec<f64> {
    let scale = eigenvalues
        .iter()
        .fold(0.0_f64, |s, (re, im)| s.max(re.hypot(*im)));
    let tol = 1e-7 * scale.max(1e-300);
    let mut oscillating: Vec<f64> = eigenvalues
        .iter()
        .filter(|(_, im)| *im > tol)
        .map(|(_, im)| im * im)
        .collect();
    let mut real: Vec<f64> = eigenvalues
        .iter()
        .filter(|(_, im)| im.abs() <= tol)
        .map(|(re, _)| if re.abs() <= tol { 0.0 } else { -re * re })
        .collect();
    // A real pair ±γ (or a double zero) is one mode.
    real.sort_by(f64::total_cmp);
    let mut omega_squared: Vec<f64> = real.chunks(2).map(|pair| pair[0]).collect();
    omega_squared.append(&mut oscillating);
    omega_squared.sort_by(f64::total_cmp);
    omega_squared
}

fn max_abs(m: &[Vec<f64>]) -> f64 {
    m.iter().flatten().fold(0.0_f64, |a, v| a.max(v.abs()))
}

fn symmetric(m: &[Vec<f64>], tol: f64) -> bool {
    m.iter().enumerate().all(|(i, row)| {
        row.iter()
            .enumerate()
            .all(|(j, v)| (v - m[j][i]).abs() <= tol)
    })
}

/// Evaluates the linear model at an equilibrium `q0` (with exact values if known) and decides
/// its stability.
pub fn linearize_at(
    model: &LinearModel,
    rest: &RestEquations,
    q0: &[f64],
    exact: Option<&[Expr]>,
    values: &Values,
) -> Result<Linearized, LinearizeError> {
    if q0.len() != rest.symbols.len() || exact.is_some_and(|x| x.len() != q0.len()) {
        return Err(LinearizeError::Evaluation(format!(
            "{} values given for {} coordinates",
            q0.len(),
            rest.symbols.len()
        )));
    }
    let m0 = evaluate_matrix(&model.mass, rest, q0, values)?;
    let c0 = evaluate_matrix(&model.damping, rest, q0, values)?;
    let k0 = evaluate_matrix(&model.stiffness, rest, q0, values)?;
    let b0 = evaluate_matrix(&model.input, rest, q0, values)?;
    let hessian = evaluate_matrix(&model.hessian, rest, q0, values)?;
    // The stiffness of a constrained system holds the multipliers' symbols: its exact form
    // would need their exact values too, so only the numbers are given.
    let exact = exact.filter(|_| rest.constraints.is_none()).map(|x| {
        [
            substitute(&model.mass, rest, x),
            substitute(&model.damping, rest, x),
            substitute(&model.stiffness, rest, x),
            substitute(&model.input, rest, x),
        ]
    });
    let reduced = match &rest.constraints {
        Some(kept) => Some(reduce(kept, rest, q0, values, [&m0, &c0, &k0, &b0])?),
        None => None,
    };
    let basis = reduced.as_ref().map(|r| r.basis.clone());
    let project = |m: &[Vec<f64>]| match &basis {
        Some(n) => congruence(n, m),
        None => m.to_vec(),
    };
    let (mr, cr, kr, hr) = (project(&m0), project(&c0), project(&k0), project(&hessian));
    let br = reduced
        .as_ref()
        .map_or_else(|| b0.clone(), |r| r.input.clone());
    let a = numeric::eigen::state_matrix(&mr, &cr, &kr)?;
    let b = if model.inputs.is_empty() {
        vec![Vec::new(); a.len()]
    } else {
        numeric::eigen::state_input(&mr, &br)?
    };
    let eigenvalues = numeric::eigen::eigenvalues(&a)?;
    let (omega_squared, modes) = if gyroscopic(&cr) {
        // `K0 x = ω² M0 x` ignores the coupling: the frequencies are the state matrix's.
        (Some(frequencies_of_state_matrix(&eigenvalues)), Vec::new())
    } else {
        match numeric::eigen::symmetric_generalized(&kr, &mr) {
            Ok(e) => (
                Some(e.values),
                in_all_coordinates(basis.as_deref(), e.modes),
            ),
            Err(_) => (None, Vec::new()),
        }
    };
    let mut oscillatory: Vec<(f64, f64)> = eigenvalues
        .iter()
        .copied()
        .filter(|(_, im)| *im > 0.0)
        .collect();
    oscillatory.sort_by(|x, y| x.0.hypot(x.1).total_cmp(&y.0.hypot(y.1)));
    let damping_ratios = oscillatory
        .iter()
        .map(|(re, im)| -re / re.hypot(*im))
        .collect();
    let controllability_rank = if model.inputs.is_empty() {
        None
    } else {
        Some(numeric::eigen::controllability_rank(&a, &b)?)
    };

    let (mut stable, mut criterion, mut hessian_eigenvalues) = match &model.routh {
        Some(r) => decide_steady(r, rest, q0, values, &eigenvalues)?,
        None => decide(&mr, &cr, &kr, &hr, &eigenvalues)?,
    };
    if stable.is_none() && model.routh.is_none() && reduced.is_none() {
        if let Some((s, c, h)) = decide_reduced(rest, &m0, &c0, &k0, &hessian)? {
            (stable, criterion, hessian_eigenvalues) = (s, c, h);
        }
    }
    Ok(Linearized {
        m0,
        c0,
        k0,
        b0,
        exact,
        a,
        b,
        eigenvalues,
        omega_squared,
        modes,
        damping_ratios,
        controllability_rank,
        stable,
        criterion,
        hessian_eigenvalues,
        reduced,
    })
}

/// `Nᵀ X N` for the basis `N` given by its columns.
fn congruence(basis: &[Vec<f64>], x: &[Vec<f64>]) -> Vec<Vec<f64>> {
    basis
        .iter()
        .map(|u| {
            basis
                .iter()
                .map(|v| {
                    (0..u.len())
                        .map(|i| u[i] * (0..v.len()).map(|j| x[i][j] * v[j]).sum::<f64>())
                        .sum()
                })
                .collect()
        })
        .collect()
}

/// The modes `v` of the reduced system as `N v`, one entry per coordinate.
fn in_all_coordinates(basis: Option<&[Vec<f64>]>, modes: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
    let Some(basis) = basis else {
        return modes;
    };
    let n = basis.first().map_or(0, Vec::len);
    modes
        .iter()
        .map(|v| {
            (0..n)
                .map(|i| basis.iter().zip(v).map(|(col, y)| col[i] * y).sum())
                .collect()
        })
        .collect()
}

/// The linearization on the constraint manifold at `q0` (see [`Reduced`]).
fn reduce(
    kept: &crate::KeptRest,
    rest: &RestEquations,
    q0: &[f64],
    values: &Values,
    [m0, c0, k0, b0]: [&[Vec<f64>]; 4],
) -> Result<Reduced, LinearizeError> {
    let a = kept.gradient_at(rest, q0, values).ok_or_else(|| {
        LinearizeError::Evaluation("the constraints' gradient at the equilibrium".to_owned())
    })?;
    let basis = crate::kkt::null_space(&a, q0.len()).ok_or_else(|| {
        LinearizeError::Evaluation("the null space of the constraints' gradient".to_owned())
    })?;
    if basis.is_empty() {
        return Err(LinearizeError::Evaluation(
            "the constraints fix every coordinate: no motion to linearize".to_owned(),
        ));
    }
    let input = basis
        .iter()
        .map(|u| {
            let columns = b0.first().map_or(0, Vec::len);
            (0..columns)
                .map(|j| u.iter().zip(b0).map(|(x, row)| x * row[j]).sum())
                .collect()
        })
        .collect();
    Ok(Reduced {
        mass: congruence(&basis, m0),
        damping: congruence(&basis, c0),
        stiffness: congruence(&basis, k0),
        input,
        basis,
    })
}

fn identity(n: usize) -> Vec<Vec<f64>> {
    (0..n)
        .map(|i| (0..n).map(|j| if i == j { 1.0 } else { 0.0 }).collect())
        .collect()
}

impl Linearized {
    /// The natural frequencies `ω = √(ω²)` in rad/s; `None` for a non-positive `ω²`.
    #[must_use]
    pub fn frequencies(&self) -> Vec<Option<f64>> {
        self.omega_squared
            .as_deref()
            .unwrap_or(&[])
            .iter()
            .map(|w2| (*w2 > 0.0).then(|| w2.sqrt()))
            .collect()
    }

    /// The free response in closed form, one term per mode: `δq(t) = Σ x_i (a_i c_i(t) +
    /// b_i s_i(t))` (see [`Linearized::free_response`]). `None` when `C0 ≠ 0`, there are no
    /// modes, or the initial conditions do not have one entry per coordinate.
    #[must_use]
    pub fn modal_terms(&self, dq0: &[f64], dv0: &[f64]) -> Option<Vec<ModalTerm>> {
        if max_abs(&self.c0) > 1e-12 * max_abs(&self.k0).max(1.0) {
            return None;
        }
        let w2 = self.omega_squared.as_ref()?;
        let n = self.m0.len();
        if dq0.len() != n || dv0.len() != n {
            return None;
        }
        let project = |x: &[f64], v: &[f64]| -> f64 {
            (0..n)
                .map(|i| (0..n).map(|j| x[i] * self.m0[i][j] * v[j]).sum::<f64>())
                .sum()
        };
        Some(
            self.modes
                .iter()
                .zip(w2)
                .map(|(x, w2)| ModalTerm {
                    omega_squared: *w2,
                    shape: x.clone(),
                    a: project(x, dq0),
                    b: project(x, dv0),
                })
                .collect(),
        )
    }

    /// The undamped free response `δq(t)` from `δq(0) = dq0`, `δq̇(0) = dv0`, as a sum of
    /// modes: `Σ x_i (a_i c_i(t) + b_i s_i(t))` with `a_i = x_iᵀ M0 δq0`, `b_i = x_iᵀ M0 δq̇0`
    /// and `(c, s) = (cos ωt, sin ωt / ω)`, `(cosh γt, sinh γt / γ)` for `ω² = −γ² < 0`, or
    /// `(1, t)` for `ω² = 0`. `None` when `C0 ≠ 0`, there are no modes, or the initial
    /// conditions do not have one entry per coordinate.
    #[must_use]
    pub fn free_response(&self, dq0: &[f64], dv0: &[f64], t: f64) -> Option<Vec<f64>> {
        let mut out = vec![0.0; self.m0.len()];
        for term in self.modal_terms(dq0, dv0)? {
            let w2 = term.omega_squared;
            let tol = 1e-12 * w2.abs().max(1.0);
            let (c, s) = if w2 > tol {
                let w = w2.sqrt();
                ((w * t).cos(), (w * t).sin() / w)
            } else if w2 < -tol {
                let g = (-w2).sqrt();
                ((g * t).cosh(), (g * t).sinh() / g)
            } else {
                (1.0, t)
            };
            for (o, x) in out.iter_mut().zip(&term.shape) {
                *o += x * (term.a * c + term.b * s);
            }
        }
        Some(out)
    }
}

type Decision = (Option<bool>, Criterion, Option<Vec<f64>>);

/// Stability of `M q̈ + C q̇ + K q = 0` with `hessian` the Hessian of the effective potential
/// and `eigenvalues` those of the state matrix (see the module doc).
fn decide(
    m0: &[Vec<f64>],
    c0: &[Vec<f64>],
    k0: &[Vec<f64>],
    hessian: &[Vec<f64>],
    eigenvalues: &[(f64, f64)],
) -> Result<Decision, LinearizeError> {
    let scale = max_abs(k0).max(max_abs(m0)).max(max_abs(c0)).max(1e-300);
    let tol = 1e-9 * scale;
    let lambda_scale = eigenvalues
        .iter()
        .fold(0.0_f64, |s, (re, im)| s.max(re.hypot(*im)))
        .max(1e-300);
    let lambda_tol = 1e-7 * lambda_scale;
    let any_growing = eigenvalues.iter().any(|(re, _)| *re > lambda_tol);
    let all_decaying = eigenvalues.iter().all(|(re, _)| *re < -lambda_tol);
    let conservative_stiffness = k0
        .iter()
        .zip(hessian)
        .all(|(r, h)| r.iter().zip(h).all(|(x, y)| (x - y).abs() <= tol * 10.0));
    // Rayleigh damping must be positive semi-definite for Lagrange–Dirichlet to survive it
    // (Thomson–Tait); the skew (gyroscopic) part never spoils it.
    let n = c0.len();
    let c_sym: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| 0.5 * (c0[i][j] + c0[j][i])).collect())
        .collect();
    let dissipation_ok = max_abs(&c_sym) <= tol
        || numeric::eigen::symmetric_generalized(&c_sym, &identity(n))
            .map(|e| e.values.iter().all(|v| *v >= -tol))
            .unwrap_or(false);
    let growing = || (Some(false), Criterion::GrowingEigenvalue);
    if conservative_stiffness && dissipation_ok && symmetric(k0, tol) {
        let h = numeric::eigen::symmetric_generalized(hessian, &identity(n))?.values;
        let h_tol = 1e-9 * h.iter().fold(scale, |s, v| s.max(v.abs()));
        let positive = h.iter().all(|v| *v > h_tol);
        // A Hessian that is only semi-definite (a bifurcation point) is a critical case: tiny
        // eigenvalues of either sign there are rounding, not instability.
        let clearly_negative = h.iter().any(|v| *v < -h_tol);
        let (stable, criterion) = if positive {
            (Some(true), Criterion::LagrangeDirichlet)
        } else if !clearly_negative {
            (None, Criterion::SingularHessian)
        } else if any_growing {
            growing()
        } else {
            (None, Criterion::IndefiniteHessian)
        };
        return Ok((stable, criterion, Some(h)));
    }
    let (stable, criterion) = if any_growing {
        growing()
    } else if all_decaying {
        (Some(true), Criterion::DecayingEigenvalues)
    } else {
        (None, Criterion::ImaginaryAxis)
    };
    Ok((stable, criterion, None))
}

/// Routh reduction of the free (cyclic at rest) coordinates: when their rows of `C0`, `K0`
/// vanish, `M_ff δẍ_f + M_fb δθ̈ = 0` integrates to a constant momentum, and the remaining
/// coordinates obey `(M_bb − M_bf M_ff⁻¹ M_fb) δθ̈ + C_bb δθ̇ + K_bb δθ = 0`. Their stability
/// is decided on that reduced system (the free coordinates drift at constant momentum).
fn decide_reduced(
    rest: &RestEquations,
    m0: &[Vec<f64>],
    c0: &[Vec<f64>],
    k0: &[Vec<f64>],
    hessian: &[Vec<f64>],
) -> Result<Option<Decision>, LinearizeError> {
    let n = m0.len();
    let free: Vec<usize> = (0..n).filter(|i| rest.free[*i]).collect();
    let bound: Vec<usize> = (0..n).filter(|i| !rest.free[*i]).collect();
    if free.is_empty() || bound.is_empty() {
        return Ok(None);
    }
    let scale = max_abs(k0).max(max_abs(m0)).max(1e-300);
    let coupled = free.iter().any(|f| {
        (0..n).any(|j| {
            c0[*f][j].abs() > 1e-12 * scale
                || c0[j][*f].abs() > 1e-12 * scale
                || k0[*f][j].abs() > 1e-12 * scale
        })
    });
    if coupled {
        return Ok(None);
    }
    let pick = |m: &[Vec<f64>], rows: &[usize], cols: &[usize]| -> Vec<Vec<f64>> {
        rows.iter()
            .map(|i| cols.iter().map(|j| m[*i][*j]).collect())
            .collect()
    };
    let m_bb = pick(m0, &bound, &bound);
    let m_bf = pick(m0, &bound, &free);
    let m_ff = pick(m0, &free, &free);
    let m_fb = pick(m0, &free, &bound);
    // M_ff⁻¹ M_fb column by column, through the state-matrix helper's LU (K = M_fb, C = 0).
    let nf = free.len();
    let nb = bound.len();
    let mut m_red = m_bb.clone();
    let solved = numeric::eigen::solve(&m_ff, &m_fb)?;
    for i in 0..nb {
        for j in 0..nb {
            m_red[i][j] -= (0..nf).map(|k| m_bf[i][k] * solved[k][j]).sum::<f64>();
        }
    }
    let c_bb = pick(c0, &bound, &bound);
    let k_bb = pick(k0, &bound, &bound);
    let h_bb = pick(hessian, &bound, &bound);
    let a = numeric::eigen::state_matrix(&m_red, &c_bb, &k_bb)?;
    let eig = numeric::eigen::eigenvalues(&a)?;
    let (stable, criterion, h) = decide(&m_red, &c_bb, &k_bb, &h_bb, &eig)?;
    let names = |idx: &[usize]| -> Vec<String> {
        idx.iter().map(|i| rest.coordinates[*i].clone()).collect()
    };
    Ok(Some((
        stable,
        Criterion::Reduced {
            criterion: Box::new(criterion),
            bound: names(&bound),
            free: names(&free),
        },
        h,
    )))
}

/// Stability of a steady motion: Routh's theorem (the Hessian of `V_R` at fixed momenta,
/// positive definite over the coordinates that are not cyclic) or an eigenvalue of the
/// linearization about the steady motion with a positive real part.
fn decide_steady(
    routh: &Routh,
    rest: &RestEquations,
    q0: &[f64],
    values: &Values,
    eigenvalues: &[(f64, f64)],
) -> Result<Decision, LinearizeError> {
    let momentum = evaluate_matrix(
        std::slice::from_ref(&routh.momentum_values),
        rest,
        q0,
        values,
    )?;
    let mut with_p = values.clone();
    for (p, v) in routh.momenta.iter().zip(&momentum[0]) {
        if let Some(sym) = p.as_symbol() {
            with_p.insert(sym.name().to_string(), *v);
        }
    }
    let full = evaluate_matrix(&routh.hessian, rest, q0, &with_p)?;
    let bound: Vec<usize> = (0..q0.len()).filter(|i| !rest.free[*i]).collect();
    let h: Vec<Vec<f64>> = bound
        .iter()
        .map(|i| bound.iter().map(|j| full[*i][*j]).collect())
        .collect();
    let lambda_scale = eigenvalues
        .iter()
        .fold(0.0_f64, |s, (re, im)| s.max(re.hypot(*im)))
        .max(1e-300);
    let any_growing = eigenvalues.iter().any(|(re, _)| *re > 1e-7 * lambda_scale);
    let hv = if h.is_empty() {
        Vec::new()
    } else {
        numeric::eigen::symmetric_generalized(&h, &identity(h.len()))?.values
    };
    let h_tol = 1e-9 * hv.iter().fold(1e-300_f64, |s, v| s.max(v.abs()));
    if !hv.is_empty() && hv.iter().all(|v| *v > h_tol) {
        return Ok((Some(true), Criterion::Routh, Some(hv)));
    }
    if any_growing {
        return Ok((
            Some(false),
            Criterion::GrowingEigenvalueOfSteadyMotion,
            Some(hv),
        ));
    }
    Ok((None, Criterion::IndefiniteReducedHessian, Some(hv)))
}
