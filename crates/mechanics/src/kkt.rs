//! Equilibria of systems whose holonomic constraints `Φ(q) = 0` are kept by multipliers: the
//! rest equations are the KKT system
//!
//! ```text
//! f(q, 0) − A(q)ᵀλ = 0    (n rows, M q̈ + Aᵀλ = f at q̇ = 0, q̈ = 0)
//!            Φ(q) = 0    (m rows, A = ∂Φ/∂q)
//! ```
//!
//! in the unknowns `q` and `λ`. Exactly first: for each choice of m coordinates whose rows of
//! `Aᵀ` are independent, those rows give `λ(q)`, and the other rows with `Φ = 0` go to the
//! exact solver of [`crate::equilibria`]; at every configuration where the constraints are
//! independent some choice applies, so the union is complete there. Otherwise numbers: Newton
//! on the whole system from a grid of starts over `q`, each first projected onto `Φ = 0` and
//! given the least-squares multipliers.

use cas::{Expr, Matrix, Symbol};

use crate::compiled_eval::CompiledExprs;
use crate::equations::Equations;
use crate::equilibria::{
    eval_at, full_branches, in_stable_order, is_rest_state, same_point, solve_in_blocks, wrap,
    Branch, Equilibrium, EquilibriumError, RestEquations, Values,
};
use crate::system::{ConstraintForm, System};

/// The holonomic constraints kept by multipliers, as the rest equations use them.
#[derive(Clone, Debug)]
pub struct KeptRest {
    /// The constraints' names, one per row of `A` (in the order of the equations' rows).
    pub names: Vec<String>,
    /// The multipliers' symbols `lambda1`, `lambda2`, … (as the equations of motion name them).
    pub multipliers: Vec<Expr>,
    /// `Φ_k(q)`, one per row.
    pub functions: Vec<Expr>,
    /// `A = ∂Φ/∂q`, one row per constraint.
    pub gradient: Vec<Vec<Expr>>,
    /// Expressions in the parameters that, where one vanishes, leave a choice of rows of the
    /// exact solve with equations it cannot solve (the Atwood machine's `(m1 − m2) g` when the
    /// masses balance, and the equilibria form a family): then the exact branches may miss
    /// equilibria, and the search is numeric.
    pub degenerate_when: Vec<Expr>,
}

impl KeptRest {
    /// `(Aᵀλ)_j`, the multipliers' generalized force on coordinate `j` (with a minus, the
    /// constraints' generalized reaction).
    pub(crate) fn reaction(&self, j: usize) -> Expr {
        self.gradient
            .iter()
            .zip(&self.multipliers)
            .map(|(row, l)| row[j] * *l)
            .sum()
    }

    /// `values` with the multipliers' symbols bound to `lambda` (what evaluates the residuals
    /// and the stiffness at an equilibrium).
    #[must_use]
    pub fn with_multipliers(&self, values: &Values, lambda: &[f64]) -> Values {
        let mut out = values.clone();
        for (m, v) in self.multipliers.iter().zip(lambda) {
            if let Some(s) = m.as_symbol() {
                out.insert(s.name().to_owned(), *v);
            }
        }
        out
    }

    /// `Σ_k λ_k ∂²Φ_k/∂q_i∂q_j`: the constraints' curvature, weighted by the multipliers, that
    /// the Hessian of the potential gains on the constraint manifold.
    pub(crate) fn curvature(&self, symbols: &[Symbol]) -> Vec<Vec<Expr>> {
        let weighted: Expr = self
            .functions
            .iter()
            .zip(&self.multipliers)
            .map(|(f, l)| *f * *l)
            .sum();
        symbols
            .iter()
            .map(|a| {
                let da = weighted.diff(*a);
                symbols.iter().map(|b| da.diff(*b).normal()).collect()
            })
            .collect()
    }

    /// `A(q0)` (m × n) at coordinates `q0` in the order of `rest.symbols`; `None` when an entry
    /// does not evaluate.
    #[must_use]
    pub fn gradient_at(
        &self,
        rest: &RestEquations,
        q0: &[f64],
        values: &Values,
    ) -> Option<Vec<Vec<f64>>> {
        self.gradient
            .iter()
            .map(|row| row.iter().map(|e| eval_at(*e, rest, q0, values)).collect())
            .collect()
    }

    /// The point of `Φ = 0` nearest `q` along the constraints' normals (Gauss–Newton with
    /// minimum-norm steps), for drawing a mode's motion on the constraints; `q` itself when the
    /// iteration does not converge.
    #[must_use]
    pub fn project(&self, rest: &RestEquations, q: &[f64], values: &Values) -> Vec<f64> {
        let mut x = q.to_vec();
        for _ in 0..30 {
            let phi: Option<Vec<f64>> = self
                .functions
                .iter()
                .map(|f| eval_at(*f, rest, &x, values))
                .collect();
            let (Some(phi), Some(a)) = (phi, self.gradient_at(rest, &x, values)) else {
                return q.to_vec();
            };
            if phi.iter().all(|v| v.abs() < 1e-13) {
                return x;
            }
            let Some(step) = min_norm_step(&a, &phi) else {
                return q.to_vec();
            };
            for (xi, d) in x.iter_mut().zip(step) {
                *xi -= d;
            }
        }
        q.to_vec()
    }
}

/// The minimum-norm `d` with `A d = r`: `Aᵀ (A Aᵀ)⁻¹ r`.
fn min_norm_step(a: &[Vec<f64>], r: &[f64]) -> Option<Vec<f64>> {
    let m = a.len();
    let n = a.first().map_or(0, Vec::len);
    let aat: Vec<Vec<f64>> = (0..m)
        .map(|i| {
            (0..m)
                .map(|j| (0..n).map(|k| a[i][k] * a[j][k]).sum())
                .collect()
        })
        .collect();
    let rhs: Vec<Vec<f64>> = r.iter().map(|v| vec![*v]).collect();
    let y = numeric::eigen::solve(&aat, &rhs).ok()?;
    Some(
        (0..n)
            .map(|k| (0..m).map(|i| a[i][k] * y[i][0]).sum())
            .collect(),
    )
}

/// The least-squares multipliers of `f = Aᵀλ`: `(A Aᵀ) λ = A f`.
fn least_squares_multipliers(a: &[Vec<f64>], f: &[f64]) -> Option<Vec<f64>> {
    let af: Vec<f64> = a
        .iter()
        .map(|row| row.iter().zip(f).map(|(x, y)| x * y).sum())
        .collect();
    let m = a.len();
    let n = f.len();
    let aat: Vec<Vec<f64>> = (0..m)
        .map(|i| {
            (0..m)
                .map(|j| (0..n).map(|k| a[i][k] * a[j][k]).sum())
                .collect()
        })
        .collect();
    let rhs: Vec<Vec<f64>> = af.iter().map(|v| vec![*v]).collect();
    let y = numeric::eigen::solve(&aat, &rhs).ok()?;
    Some(y.iter().map(|r| r[0]).collect())
}

/// The holonomic function `Φ_k(q)` of every row of the equations' constraint matrix: the
/// system's `Holonomic` equation of that row's constraint whose gradient is the row (the
/// coordinates that integrable velocity constraints eliminated substituted).
///
/// # Errors
/// [`EquilibriumError::NonholonomicKept`] for rows that no holonomic equation gives.
pub(crate) fn kept_constraints(
    system: &System,
    equations: &Equations,
) -> Result<KeptRest, EquilibriumError> {
    let eliminated: Vec<(Expr, Expr)> = equations
        .eliminated()
        .iter()
        .map(|e| (Expr::coordinate(&e.coordinate), e.value))
        .collect();
    let symbols: Vec<Option<Symbol>> = equations
        .coordinates()
        .iter()
        .map(|q| Expr::coordinate(q).as_symbol())
        .collect();
    let mut functions = Vec::new();
    let mut missing = Vec::new();
    for (name, row) in equations
        .constraint_names()
        .iter()
        .zip(equations.constraint_matrix())
    {
        let candidates = system
            .constraints()
            .iter()
            .filter(|c| c.name == *name)
            .flat_map(|c| c.equations.iter())
            .filter_map(|form| match form {
                ConstraintForm::Holonomic(f) => Some(f.subs(&eliminated).normal()),
                ConstraintForm::Velocity(_) => None,
            });
        let matches = |f: &Expr| {
            row.iter().zip(&symbols).all(|(a, q)| match q {
                Some(q) => (*a - f.diff(*q)).is_zero(),
                None => false,
            })
        };
        match candidates.into_iter().find(matches) {
            Some(f) => functions.push(f),
            None => missing.push(name.clone()),
        }
    }
    if !missing.is_empty() {
        missing.dedup();
        return Err(EquilibriumError::NonholonomicKept { names: missing });
    }
    let gradient = functions
        .iter()
        .map(|f| {
            symbols
                .iter()
                .map(|q| q.map_or(Expr::zero(), |q| f.diff(q).normal()))
                .collect()
        })
        .collect();
    Ok(KeptRest {
        names: equations.constraint_names().to_vec(),
        multipliers: (1..=functions.len())
            .map(|i| Expr::symbol(&format!("lambda{i}")))
            .collect(),
        functions,
        gradient,
        degenerate_when: Vec::new(),
    })
}

/// At most this many choices of the coordinates whose rows give the multipliers are tried.
const MAX_PARTITIONS: usize = 64;

/// All equilibria as exact branches (with the multipliers), or `None` when a choice of rows
/// that gives the multipliers leaves equations the exact solver cannot solve. A choice that
/// leaves an equation free of the coordinates has no equilibria unless that expression of the
/// parameters vanishes: it is recorded in [`KeptRest::degenerate_when`] instead.
pub(crate) fn exact_branches(
    residuals: &[Expr],
    kept: &mut KeptRest,
    symbols: &[Symbol],
    free: &[bool],
) -> Option<Vec<Branch>> {
    let n = symbols.len();
    let m = kept.multipliers.len();
    let bound: Vec<Symbol> = (0..n).filter(|i| !free[*i]).map(|i| symbols[i]).collect();
    let mut branches = Vec::new();
    let mut tried = 0;
    for rows in subsets(n, m) {
        // The rows' equations `f_S − A_Sᵀ λ = 0`, linear in λ: solved exactly.
        let coefficients: Vec<Vec<Expr>> = rows
            .iter()
            .map(|i| kept.gradient.iter().map(|g| g[*i]).collect())
            .collect();
        let Some(matrix) = Matrix::from_rows(coefficients) else {
            continue;
        };
        let zero: Vec<(Expr, Expr)> = kept
            .multipliers
            .iter()
            .map(|l| (*l, Expr::zero()))
            .collect();
        let forces: Vec<Expr> = rows
            .iter()
            .map(|i| residuals[*i].subs(&zero).normal())
            .collect();
        let Ok(solved) = matrix.solve(&Matrix::column(forces)) else {
            continue;
        };
        tried += 1;
        if tried > MAX_PARTITIONS {
            return None;
        }
        let lambda: Vec<Expr> = (0..m)
            .map(|k| solved.get(k, 0).map_or(Expr::zero(), Expr::normal))
            .collect();
        let pairs: Vec<(Expr, Expr)> = kept
            .multipliers
            .iter()
            .copied()
            .zip(lambda.iter().copied())
            .collect();
        // The other rows with λ(q), cleared of denominators (non-zero where this choice
        // applies), and the constraints.
        let equations: Vec<Expr> = (0..n)
            .filter(|i| !rows.contains(i))
            .map(|i| residuals[i].subs(&pairs).normal().numer_denom().0)
            .chain(kept.functions.iter().copied())
            .collect();
        let constant = equations
            .iter()
            .find(|e| !e.is_zero() && bound.iter().all(|q| e.diff(*q).is_zero()));
        if let Some(e) = constant {
            kept.degenerate_when.push(*e);
            continue;
        }
        let partials = solve_in_blocks(&equations, &bound)?;
        for branch in full_branches(partials, symbols, free) {
            let at: Vec<(Expr, Expr)> = symbols
                .iter()
                .zip(&branch.values)
                .flat_map(|(q, v)| substitution(Expr::from_symbol(*q), *v))
                .collect();
            branches.push(Branch {
                multipliers: lambda.iter().map(|l| l.subs(&at).normal()).collect(),
                conditions: in_stable_order(branch.conditions),
                values: branch.values,
            });
        }
    }
    (tried > 0).then_some(branches)
}

/// `q = value` with `sin q`, `cos q`, `tan q` rewritten so the normal form simplifies them.
fn substitution(q: Expr, value: Expr) -> [(Expr, Expr); 4] {
    let (s, c) = (value.sin(), value.cos());
    [(q.sin(), s), (q.cos(), c), (q.tan(), s / c), (q, value)]
}

/// The `k`-element subsets of `0..n`, in lexicographic order.
fn subsets(n: usize, k: usize) -> Vec<Vec<usize>> {
    if k == 0 {
        return vec![Vec::new()];
    }
    if k > n {
        return Vec::new();
    }
    let mut out = Vec::new();
    for first in 0..n {
        for mut rest in subsets(n, k - 1)
            .into_iter()
            .filter(|r| r.iter().all(|x| *x > first))
        {
            rest.insert(0, first);
            out.push(rest);
        }
    }
    out
}

/// Whether `(x, λ)` satisfies the KKT system to rounding (the force rows through
/// [`is_rest_state`], the constraints scaled by their gradients).
fn is_kkt_state(rest: &RestEquations, kept: &KeptRest, x: &[f64], values: &Values) -> bool {
    is_rest_state(rest, x, values)
        && kept.functions.iter().zip(&kept.gradient).all(|(f, g)| {
            let Some(v) = eval_at(*f, rest, x, values) else {
                return false;
            };
            let scale: f64 = g
                .iter()
                .zip(x)
                .filter_map(|(d, xi)| {
                    eval_at(*d, rest, x, values).map(|d| d.abs() * (1.0 + xi.abs()))
                })
                .sum();
            v.abs() <= 1e-8 * (1.0 + scale)
        })
}

/// Keeps `candidate` when it satisfies the KKT system and is not one already found.
fn add_if_new(
    found: &mut Vec<Equilibrium>,
    rest: &RestEquations,
    kept: &KeptRest,
    values: &Values,
    candidate: Equilibrium,
) {
    if found
        .iter()
        .any(|e| same_point(&e.values, &candidate.values, &rest.periodic))
    {
        return;
    }
    let with = kept.with_multipliers(values, &candidate.multipliers);
    if is_kkt_state(rest, kept, &candidate.values, &with) {
        found.push(candidate);
    }
}

/// The exact branches that exist for these values, evaluated and checked.
pub(crate) fn exact_kkt_equilibria(
    rest: &RestEquations,
    kept: &KeptRest,
    branches: &[Branch],
    values: &Values,
) -> Vec<Equilibrium> {
    let env = crate::equilibria::environment(values);
    let mut found = Vec::new();
    for b in branches {
        if b.conditions.iter().any(|c| c.holds(&env) != Some(true)) {
            continue;
        }
        let evaluate = |exprs: &[Expr]| {
            exprs
                .iter()
                .map(|v| v.eval(&env).ok().filter(|v| v.is_finite()))
                .collect::<Option<Vec<f64>>>()
        };
        let (Some(mut x), Some(lambda)) = (evaluate(&b.values), evaluate(&b.multipliers)) else {
            continue;
        };
        wrap(rest, &mut x);
        let candidate = Equilibrium {
            values: x,
            exact: Some(b.values.clone()),
            conditions: b.conditions.clone(),
            multipliers: lambda,
            exact_multipliers: Some(b.multipliers.clone()),
        };
        add_if_new(&mut found, rest, kept, values, candidate);
    }
    found
}

/// The tapes of the numeric search: the unknowns are the coordinates that occur and the
/// multipliers.
struct Tapes {
    /// `[f − Aᵀλ]_active ; Φ`.
    residual: Vec<Expr>,
    /// Its Jacobian in (q_active, λ), row-major.
    jacobian: Vec<Expr>,
    /// `Φ` then `A` (m × n_active, row-major) for the projection.
    constraints: Vec<Expr>,
}

impl Tapes {
    fn new(rest: &RestEquations, kept: &KeptRest, active: &[usize]) -> Tapes {
        let m = kept.multipliers.len();
        let mut residual: Vec<Expr> = active.iter().map(|i| rest.residuals[*i]).collect();
        residual.extend(kept.functions.iter().copied());
        let mut jacobian = Vec::new();
        for i in active {
            jacobian.extend(active.iter().map(|j| rest.jacobian[*i][*j]));
            jacobian.extend(kept.gradient.iter().map(|g| (-g[*i]).normal()));
        }
        for g in &kept.gradient {
            jacobian.extend(active.iter().map(|j| g[*j]));
            jacobian.extend(std::iter::repeat_n(Expr::zero(), m));
        }
        let mut constraints = kept.functions.clone();
        for g in &kept.gradient {
            constraints.extend(active.iter().map(|j| g[*j]));
        }
        Tapes {
            residual,
            jacobian,
            constraints,
        }
    }
}

/// An evaluator of expressions at `(q, λ)`: a compiled tape, or the trees.
struct Evaluator<'a> {
    exprs: &'a [Expr],
    tape: Option<CompiledExprs>,
    variables: Vec<Symbol>,
    values: &'a Values,
}

impl<'a> Evaluator<'a> {
    fn new(exprs: &'a [Expr], variables: Vec<Symbol>, values: &'a Values) -> Evaluator<'a> {
        let known: Vec<(Symbol, f64)> = values
            .iter()
            .filter_map(|(name, v)| Some((Expr::symbol(name).as_symbol()?, *v)))
            .collect();
        let tape = CompiledExprs::new(exprs, &variables, &known, &|_| None);
        Evaluator {
            exprs,
            tape,
            variables,
            values,
        }
    }

    fn eval(&self, x: &[f64]) -> Option<Vec<f64>> {
        if let Some(tape) = &self.tape {
            return tape.eval(x);
        }
        let env = |s: Symbol| {
            self.variables
                .iter()
                .position(|v| *v == s)
                .map(|i| x[i])
                .or_else(|| self.values.get(s.name()).copied())
        };
        self.exprs
            .iter()
            .map(|e| e.eval(&env).ok().filter(|v| v.is_finite()))
            .collect()
    }
}

/// The equilibria by Newton on the KKT system from a grid of starts over the coordinates
/// that occur (free ones stay at 0).
pub(crate) fn kkt_equilibria(
    rest: &RestEquations,
    kept: &KeptRest,
    values: &Values,
    bounds: &[(f64, f64)],
) -> Vec<Equilibrium> {
    let n = rest.symbols.len();
    let m = kept.multipliers.len();
    let active: Vec<usize> = (0..n).filter(|i| !rest.free[*i]).collect();
    let na = active.len();
    let mut variables = rest.symbols.clone();
    variables.extend(kept.multipliers.iter().filter_map(|l| l.as_symbol()));
    if variables.len() != n + m || na == 0 {
        return Vec::new();
    }
    let tapes = Tapes::new(rest, kept, &active);
    let residual = Evaluator::new(&tapes.residual, variables.clone(), values);
    let jacobian = Evaluator::new(&tapes.jacobian, variables.clone(), values);
    let constraints = Evaluator::new(&tapes.constraints, variables, values);
    // z = (q_active, λ) → the full (q, λ) the tapes read.
    let full = |z: &[f64]| -> Vec<f64> {
        let mut x = vec![0.0; n + m];
        for (k, i) in active.iter().enumerate() {
            x[*i] = z[k];
        }
        x[n..].copy_from_slice(&z[na..]);
        x
    };
    let f = |z: &[f64]| residual.eval(&full(z));
    let j = |z: &[f64]| jacobian.eval(&full(z));
    let mut found: Vec<Equilibrium> = Vec::new();
    for start in starts(rest, &active, bounds) {
        let Some(z0) = initial_point(&start, na, m, &constraints, &residual, &jacobian, &full)
        else {
            continue;
        };
        let Some(z) = numeric::roots::newton(&f, &j, &z0, 1e-10) else {
            continue;
        };
        // Polished to rounding where it gets there (the acceptance test above is relative to
        // the equations' scale; this makes the values good to the last digits).
        let z = numeric::roots::newton(&f, &j, &z, 1e-13).unwrap_or(z);
        let mut x = full(&z)[..n].to_vec();
        wrap(rest, &mut x);
        let outside = active
            .iter()
            .any(|i| !rest.periodic[*i] && (x[*i] < bounds[*i].0 || x[*i] > bounds[*i].1));
        if outside {
            continue;
        }
        let candidate = Equilibrium {
            values: x,
            exact: None,
            conditions: Vec::new(),
            multipliers: z[na..].to_vec(),
            exact_multipliers: None,
        };
        add_if_new(&mut found, rest, kept, values, candidate);
    }
    found
}

/// A start `(q, λ)` for Newton: `q` projected onto `Φ = 0`, `λ` the least-squares multipliers
/// there.
fn initial_point(
    start: &[f64],
    na: usize,
    m: usize,
    constraints: &Evaluator<'_>,
    residual: &Evaluator<'_>,
    jacobian: &Evaluator<'_>,
    full: &dyn Fn(&[f64]) -> Vec<f64>,
) -> Option<Vec<f64>> {
    let mut z: Vec<f64> = start
        .iter()
        .copied()
        .chain(std::iter::repeat_n(0.0, m))
        .collect();
    for _ in 0..30 {
        let c = constraints.eval(&full(&z))?;
        let (phi, g) = c.split_at(m);
        if phi.iter().all(|v| v.abs() < 1e-12) {
            break;
        }
        let a: Vec<Vec<f64>> = g.chunks(na).map(<[f64]>::to_vec).collect();
        let step = min_norm_step(&a, phi)?;
        for (zi, d) in z.iter_mut().zip(step) {
            *zi -= d;
        }
    }
    // At λ = 0 the force rows are f and the λ columns of the Jacobian are −Aᵀ.
    let f = residual.eval(&full(&z))?;
    let jac = jacobian.eval(&full(&z))?;
    let width = na + m;
    let a: Vec<Vec<f64>> = (0..m)
        .map(|k| (0..na).map(|i| -jac[i * width + na + k]).collect())
        .collect();
    let lambda = least_squares_multipliers(&a, &f[..na])?;
    z[na..].copy_from_slice(&lambda);
    Some(z)
}

/// Newton starts over the active coordinates: a grid of at most 600 points (angles over a
/// turn, shifted by an irrational fraction of a cell so that no start sits on a symmetric
/// model's singular points; other coordinates over their range).
fn starts(rest: &RestEquations, active: &[usize], bounds: &[(f64, f64)]) -> Vec<Vec<f64>> {
    let na = active.len();
    let per_axis = (600f64.powf(1.0 / na as f64).floor() as usize).max(2);
    let total = per_axis.saturating_pow(na as u32).min(600);
    let cell = 1.0 / per_axis as f64;
    (0..total)
        .map(|index| {
            let mut left = index;
            active
                .iter()
                .map(|i| {
                    let k = left % per_axis;
                    left /= per_axis;
                    let (lo, hi) = bounds[*i];
                    let shift = if rest.periodic[*i] {
                        std::f64::consts::FRAC_1_PI * cell
                    } else {
                        0.0
                    };
                    lo + (hi - lo) * ((k as f64 + 0.5) * cell + shift).rem_euclid(1.0)
                })
                .collect()
        })
        .collect()
}

/// An orthonormal basis `N` (columns, as vectors of length n) of the null space of `A`
/// (m × n): the directions the constraints allow at a configuration. `None` when the
/// eigenproblem fails.
#[must_use]
pub fn null_space(a: &[Vec<f64>], n: usize) -> Option<Vec<Vec<f64>>> {
    let ata: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| a.iter().map(|row| row[i] * row[j]).sum())
                .collect()
        })
        .collect();
    let identity: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| if i == j { 1.0 } else { 0.0 }).collect())
        .collect();
    let e = numeric::eigen::symmetric_generalized(&ata, &identity).ok()?;
    let scale = e.values.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    let tol = 1e-10 * scale.max(1e-300);
    Some(
        e.values
            .iter()
            .zip(e.modes)
            .filter(|(v, _)| v.abs() <= tol)
            .map(|(_, x)| x)
            .collect(),
    )
}
