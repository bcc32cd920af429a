//! Equilibria: the rest states `q̇ = 0`, `q̈ = 0` with inputs held at constant values, i.e.
//! the roots of `f(q, 0) = 0` where `M q̈ = f(q, q̇)`.
//!
//! Exactly first: one equation at a time in one unknown ([`cas::solve_for`]), substituting
//! each branch into the rest, or a linear system solved exactly. The exact branches are
//! symbolic in the parameters, with the conditions for them to exist, and are *all* the
//! equilibria. When that fails, numbers: a dense scan with bisection for one coordinate,
//! Newton from a grid of starts for several, over the coordinates' domain (angles modulo 2π,
//! lengths in a given range) — not guaranteed complete, and said so.

use std::collections::HashMap;

use cas::{solve_for, Condition, Expr, Matrix, Solved, Symbol};

use crate::compiled_eval::CompiledExprs;
use crate::equations::Equations;
use crate::kkt::{kkt_equilibria, KeptRest};
use crate::polynomial_rest::{real_roots, rest_polynomial, RestPolynomial};

/// What can go wrong looking for equilibria.
#[derive(Debug, thiserror::Error, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum EquilibriumError {
    /// Constraints kept with multipliers: their reactions at rest are not eliminated yet.
    #[error("equilibria of systems with constraints kept by multipliers ({}) are not supported yet", names.join(", "))]
    KeptConstraints {
        /// The constraints.
        names: Vec<String>,
    },
    /// The rest equations depend on time (a driven coordinate or a time-dependent input that
    /// does not leave a steady state): there are no equilibria in the ordinary sense.
    #[error("the rest equations depend on time (driven motion or time-dependent inputs): no equilibria of the ordinary kind")]
    TimeDependent,
    /// A coordinate asked to spin steadily is not cyclic (or not a coordinate).
    #[error("`{name}` is not a cyclic coordinate (it must be a coordinate absent from the mass matrix, the forces and the potential) so it cannot spin steadily")]
    NotCyclic {
        /// Its name.
        name: String,
    },
    /// A constraint kept by a multiplier is not holonomic (a rolling or knife-edge condition
    /// on the rates): the rest equations do not fix the configuration it allows.
    #[error("equilibria of systems with non-holonomic constraints kept by multipliers ({}) are not supported", names.join(", "))]
    NonholonomicKept {
        /// The constraints.
        names: Vec<String>,
    },
    /// Steady motions asked for a system with constraints kept by multipliers.
    #[error("steady motions of systems with constraints kept by multipliers ({}) are not supported", names.join(", "))]
    SteadyWithMultipliers {
        /// The constraints.
        names: Vec<String>,
    },
    /// A parameter or input has no numeric value.
    #[error("`{name}` has no numeric value; give it one")]
    MissingValue {
        /// Its name.
        name: String,
    },
}

/// Numeric values of parameters and inputs, by name.
pub type Values = HashMap<String, f64>;

/// The rest equations of a system, and what is known of them symbolically.
#[derive(Clone, Debug)]
pub struct RestEquations {
    /// Coordinate names.
    pub coordinates: Vec<String>,
    /// Coordinate symbols.
    pub symbols: Vec<Symbol>,
    /// `f(q, 0)`, one per coordinate; with constraints kept by multipliers,
    /// `f(q, 0) − A(q)ᵀλ` with the multipliers as the symbols of [`KeptRest::multipliers`].
    pub residuals: Vec<Expr>,
    /// `∂f_i/∂q_j` at rest, row-major.
    pub jacobian: Vec<Vec<Expr>>,
    /// Whether each coordinate enters only through `sin`, `cos`, `tan` (an angle mod 2π).
    pub periodic: Vec<bool>,
    /// Coordinates absent from every rest equation (cyclic at rest, like a cart's position
    /// under no horizontal force): the equilibria form a family along them, represented by
    /// the value 0.
    pub free: Vec<bool>,
    /// All equilibria as exact branches, when the equations were solved exactly.
    pub exact: Option<Vec<Branch>>,
    /// The coordinates turning at a constant rate (steady motions), empty for equilibria.
    pub spinning: Vec<String>,
    /// When not solved exactly but a single coordinate's rest equation is a polynomial (in the
    /// coordinate, or in `tan(q/2)` for an angle): its coefficients.
    pub polynomial: Option<RestPolynomial>,
    /// The holonomic constraints kept by multipliers, `Φ(q) = 0`, that the equilibria must
    /// satisfy besides the residuals (`None` without such constraints).
    pub constraints: Option<KeptRest>,
}

/// One exact family of equilibria: a value per coordinate and when it exists.
#[derive(Clone, Debug)]
pub struct Branch {
    /// Values by coordinate.
    pub values: Vec<Expr>,
    /// Conditions on the parameters for the branch to exist.
    pub conditions: Vec<Condition>,
    /// The multipliers' values, one per kept constraint (empty without constraints).
    pub multipliers: Vec<Expr>,
}

/// How the equilibria were found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Exact solution of the rest equations: complete.
    Exact,
    /// Dense scan with bisection (one coordinate): complete for roots separated by more than
    /// the grid step.
    Scan,
    /// Newton from a grid of starts (several coordinates): not guaranteed complete.
    MultistartNewton,
    /// The real roots of a polynomial rest equation in one coordinate (in `tan(q/2)` for an
    /// angle) by the companion matrix: complete.
    Polynomial,
}

impl Method {
    /// A short name for reports.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Method::Exact => "exact",
            Method::Scan => "dense scan + bisection + Newton",
            Method::MultistartNewton => "Newton from a grid of starts",
            Method::Polynomial => "companion-matrix roots of the rest polynomial",
        }
    }

    /// Whether the method guarantees that no equilibrium is missed.
    #[must_use]
    pub fn complete(self) -> bool {
        matches!(self, Method::Exact | Method::Polynomial)
    }
}

/// One equilibrium.
#[derive(Clone, Debug)]
pub struct Equilibrium {
    /// Numeric values by coordinate (angles in (−π, π]).
    pub values: Vec<f64>,
    /// Exact values by coordinate, when known.
    pub exact: Option<Vec<Expr>>,
    /// Conditions under which the exact branch exists.
    pub conditions: Vec<Condition>,
    /// The multipliers `λ` of the constraints kept by them (`M q̈ + Aᵀλ = f`), in the order of
    /// [`KeptRest::names`]: the constraints' generalized reactions at rest are `−Aᵀλ` (empty
    /// without such constraints).
    pub multipliers: Vec<f64>,
    /// The multipliers' exact values, when known.
    pub exact_multipliers: Option<Vec<Expr>>,
}

/// The equilibria found, and how.
#[derive(Clone, Debug)]
pub struct EquilibriumSet {
    /// The equilibria, sorted by values.
    pub equilibria: Vec<Equilibrium>,
    /// The method.
    pub method: Method,
    /// The search box per coordinate.
    pub bounds: Vec<(f64, f64)>,
    /// Equilibria left out because the coordinates reach the configuration of one kept
    /// (a double cover, like a polar radius of either sign); empty until
    /// [`crate::keep_distinct_configurations`] is applied.
    pub repeated: Vec<Repeated>,
}

/// Other coordinates of the configuration of a kept equilibrium.
#[derive(Clone, Debug)]
pub struct Repeated {
    /// The index of the kept equilibrium.
    pub same_as: usize,
    /// The other coordinates.
    pub values: Vec<f64>,
}

/// The symbols of the rates `q̇`, `q̈` of a coordinate.
fn rates(name: &str) -> [Expr; 2] {
    [Expr::rate(name, 1), Expr::rate(name, 2)]
}

/// Whether `name` enters `exprs` only through `sin`, `cos`, `tan` of itself.
fn is_angle(exprs: &[Expr], name: &str) -> bool {
    let q = Expr::coordinate(name);
    let Some(sym) = q.as_symbol() else {
        return false;
    };
    let marks = [
        (q.sin(), Expr::symbol("__angle_sin")),
        (q.cos(), Expr::symbol("__angle_cos")),
        (q.tan(), Expr::symbol("__angle_tan")),
    ];
    let mut any = false;
    for e in exprs {
        if e.diff(sym).is_zero() {
            continue;
        }
        any = true;
        if !e.subs(&marks).diff(sym).is_zero() {
            return false;
        }
    }
    any
}

/// The rest equations `f(q, 0) = 0` of a system's equations of motion, solved exactly where
/// the equations allow.
pub fn rest_equations(equations: &Equations) -> Result<RestEquations, EquilibriumError> {
    steady_equations(equations, &[])
}

/// The symbol standing for the constant rate of a spinning cyclic coordinate: `{q}_d`.
#[must_use]
pub fn spin_rate(coordinate: &str) -> Expr {
    Expr::symbol(&format!("{coordinate}_d"))
}

/// The equations of steady motions (relative equilibria): the coordinates in `spinning` are
/// cyclic and turn at constant rates (the symbols [`spin_rate`]), the others are at rest.
/// With `spinning` empty these are the rest equations.
pub fn steady_equations(
    equations: &Equations,
    spinning: &[String],
) -> Result<RestEquations, EquilibriumError> {
    if !equations.constraint_names().is_empty() {
        return Err(EquilibriumError::KeptConstraints {
            names: equations.constraint_names().to_vec(),
        });
    }
    build_rest(equations, spinning, None)
}

/// [`steady_equations`] of a system whose constraints may be kept by multipliers: then the
/// rest equations are `f(q, 0) − A(q)ᵀλ = 0` with `Φ(q) = 0` (the holonomic constraints, read
/// off `system`), unknowns `q` and `λ`.
///
/// # Errors
/// As [`steady_equations`]; a constraint kept by a multiplier that is not holonomic, or steady
/// motions asked for with such constraints.
pub fn rest_equations_of(
    system: &crate::System,
    equations: &Equations,
    spinning: &[String],
) -> Result<RestEquations, EquilibriumError> {
    if equations.constraint_names().is_empty() {
        return steady_equations(equations, spinning);
    }
    if !spinning.is_empty() {
        return Err(EquilibriumError::SteadyWithMultipliers {
            names: equations.constraint_names().to_vec(),
        });
    }
    let kept = crate::kkt::kept_constraints(system, equations)?;
    build_rest(equations, &[], Some(kept))
}

/// The rest equations, with the multipliers' terms `−Aᵀλ` when `kept` is given.
fn build_rest(
    equations: &Equations,
    spinning: &[String],
    kept: Option<KeptRest>,
) -> Result<RestEquations, EquilibriumError> {
    let coordinates = equations.coordinates().to_vec();
    check_cyclic(equations, spinning)?;
    let zero_rates: Vec<(Expr, Expr)> = coordinates
        .iter()
        .flat_map(|q| {
            let [v, a] = rates(q);
            let v_value = if spinning.contains(q) {
                spin_rate(q)
            } else {
                Expr::zero()
            };
            [(v, v_value), (a, Expr::zero())]
        })
        .collect();
    let residuals: Vec<Expr> = equations
        .forcing()
        .iter()
        .enumerate()
        .map(|(j, f)| {
            let reaction = kept.as_ref().map_or(Expr::zero(), |k| k.reaction(j));
            (f.subs(&zero_rates) - reaction).normal()
        })
        .collect();
    if let Some(t) = Expr::time().as_symbol() {
        let functions = kept.as_ref().map_or(&[][..], |k| &k.functions[..]);
        if residuals
            .iter()
            .chain(functions)
            .any(|r| !r.diff(t).is_zero())
        {
            return Err(EquilibriumError::TimeDependent);
        }
    }
    let symbols: Vec<Symbol> = coordinates
        .iter()
        .filter_map(|q| Expr::coordinate(q).as_symbol())
        .collect();
    let jacobian = residuals
        .iter()
        .map(|r| symbols.iter().map(|q| r.diff(*q).normal()).collect())
        .collect();
    // The kinetic and potential energies count too: an angle must be periodic in the whole
    // model, not only in the rest equations.
    let mut all = residuals.clone();
    all.push(equations.potential_energy());
    all.extend(equations.mass_matrix().iter().flatten().copied());
    let functions = kept.as_ref().map_or(&[][..], |k| &k.functions[..]);
    all.extend(functions.iter().copied());
    let periodic: Vec<bool> = coordinates.iter().map(|q| is_angle(&all, q)).collect();
    let free: Vec<bool> = symbols
        .iter()
        .map(|q| {
            residuals
                .iter()
                .chain(functions)
                .all(|r| r.diff(*q).is_zero())
        })
        .collect();
    let bound: Vec<Symbol> = symbols
        .iter()
        .zip(&free)
        .filter(|(_, f)| !**f)
        .map(|(q, _)| *q)
        .collect();
    let mut kept = kept;
    let exact = match &mut kept {
        None => solve_in_blocks(&residuals, &bound).map(|b| full_branches(b, &symbols, &free)),
        Some(k) => crate::kkt::exact_branches(&residuals, k, &symbols, &free),
    };
    let polynomial = if exact.is_none() && kept.is_none() {
        single_polynomial(&residuals, &symbols, &free, &periodic)
    } else {
        None
    };
    Ok(RestEquations {
        polynomial,
        coordinates,
        symbols,
        residuals,
        jacobian,
        periodic,
        free,
        exact,
        spinning: spinning.to_vec(),
        constraints: kept,
    })
}

/// Every coordinate in `spinning` is one, and cyclic: absent from `f`, `M` and `V`.
fn check_cyclic(equations: &Equations, spinning: &[String]) -> Result<(), EquilibriumError> {
    for name in spinning {
        if !equations.coordinates().contains(name) {
            return Err(EquilibriumError::NotCyclic { name: name.clone() });
        }
        let Some(q) = Expr::coordinate(name).as_symbol() else {
            return Err(EquilibriumError::NotCyclic { name: name.clone() });
        };
        let appears = equations
            .forcing()
            .iter()
            .chain(equations.mass_matrix().iter().flatten())
            .chain([&equations.potential_energy()])
            .any(|e| !e.diff(q).is_zero());
        if appears {
            return Err(EquilibriumError::NotCyclic { name: name.clone() });
        }
    }
    Ok(())
}

/// Exact solutions as branches with a value for every coordinate: free coordinates at 0; a
/// solution that leaves a bound coordinate without a value is dropped.
pub(crate) fn full_branches(
    solutions: Vec<Partial>,
    symbols: &[Symbol],
    free: &[bool],
) -> Vec<Branch> {
    solutions
        .into_iter()
        .filter_map(|b| {
            let values = symbols
                .iter()
                .zip(free)
                .map(|(s, f)| {
                    if *f {
                        Some(Expr::zero())
                    } else {
                        b.values.get(s).copied()
                    }
                })
                .collect::<Option<Vec<_>>>()?;
            Some(Branch {
                values,
                conditions: in_stable_order(b.conditions),
                multipliers: Vec::new(),
            })
        })
        .collect()
}

/// The polynomial form of the rest equations when exactly one coordinate is not free and
/// exactly one equation involves it.
fn single_polynomial(
    residuals: &[Expr],
    symbols: &[Symbol],
    free: &[bool],
    periodic: &[bool],
) -> Option<RestPolynomial> {
    let bound: Vec<usize> = (0..symbols.len()).filter(|i| !free[*i]).collect();
    let [index] = bound[..] else {
        return None;
    };
    let x = symbols[index];
    let involving: Vec<&Expr> = residuals.iter().filter(|r| !r.diff(x).is_zero()).collect();
    let [residual] = involving[..] else {
        return None;
    };
    rest_polynomial(*residual, index, x, periodic[index])
}

/// The conditions of a branch in an order that does not depend on how the solve went (which
/// block came first, which arena ids the expressions got): by their SymPy text, duplicates
/// dropped. Reports print them in this order.
pub(crate) fn in_stable_order(conditions: Vec<Condition>) -> Vec<Condition> {
    let key = |c: &Condition| {
        let (tag, e) = match c {
            Condition::AbsAtMostOne(e) => (0, e),
            Condition::NonNegative(e) => (1, e),
            Condition::NonZero(e) => (2, e),
            Condition::Zero(e) => (3, e),
            _ => (4, &Expr::zero()),
        };
        (tag, cas::print::to_sympy(*e))
    };
    let mut keyed: Vec<_> = conditions.into_iter().map(|c| (key(&c), c)).collect();
    keyed.sort_by(|a, b| a.0.cmp(&b.0));
    keyed.dedup_by(|a, b| a.0 == b.0);
    keyed.into_iter().map(|(_, c)| c).collect()
}

/// A partial exact solution.
#[derive(Clone, Debug, Default)]
pub(crate) struct Partial {
    pub(crate) values: HashMap<Symbol, Expr>,
    pub(crate) conditions: Vec<Condition>,
}

/// At most this many exact branches are listed: beyond, the equilibria are searched for
/// numerically (a chain of n links hanging or standing has 2ⁿ; 4096 is twelve links).
const MAX_BRANCHES: usize = 4096;

/// Solves `equations = 0` for `unknowns` exactly, block by block: equations that share no
/// unknown are solved apart and their branches combined, so that the work grows with the
/// number of equilibria and not with its power. `None` when a block cannot be solved exactly
/// or there are more than [`MAX_BRANCHES`] branches.
pub(crate) fn solve_in_blocks(equations: &[Expr], unknowns: &[Symbol]) -> Option<Vec<Partial>> {
    let mut combined = vec![Partial::default()];
    for (block_equations, block_unknowns) in blocks(equations, unknowns) {
        let mut budget = MAX_BRANCHES;
        let branches = solve_exactly(&block_equations, &block_unknowns, &mut budget)?;
        if combined.len().saturating_mul(branches.len()) > MAX_BRANCHES {
            return None;
        }
        combined = combined
            .iter()
            .flat_map(|a| {
                branches.iter().map(move |b| {
                    // Later blocks' conditions first: the order one solve over all the
                    // equations gives (the conditions of the deepest step come first).
                    let mut p = b.clone();
                    p.values.extend(a.values.iter().map(|(k, v)| (*k, *v)));
                    p.conditions.extend(a.conditions.iter().copied());
                    p
                })
            })
            .collect();
    }
    Some(combined)
}

/// The equations grouped into blocks that share no unknown (connected components of the
/// graph joining each unknown to the equations it occurs in), each with its unknowns.
/// Equations free of every unknown belong to no block (the numeric check of each equilibrium
/// decides whether they hold); unknowns in no equation form no block either.
fn blocks(equations: &[Expr], unknowns: &[Symbol]) -> Vec<(Vec<Expr>, Vec<Symbol>)> {
    let mut parent: Vec<usize> = (0..unknowns.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let involved: Vec<Vec<usize>> = equations
        .iter()
        .map(|e| {
            (0..unknowns.len())
                .filter(|k| !e.diff(unknowns[*k]).is_zero())
                .collect()
        })
        .collect();
    for vars in &involved {
        for w in vars.windows(2) {
            let (a, b) = (root(&mut parent, w[0]), root(&mut parent, w[1]));
            parent[a] = b;
        }
    }
    let mut groups: Vec<(usize, Vec<Expr>, Vec<Symbol>)> = Vec::new();
    for (e, vars) in equations.iter().zip(&involved) {
        let Some(first) = vars.first() else {
            continue;
        };
        let r = root(&mut parent, *first);
        match groups.iter_mut().find(|g| g.0 == r) {
            Some(g) => g.1.push(*e),
            None => groups.push((r, vec![*e], Vec::new())),
        }
    }
    for (k, u) in unknowns.iter().enumerate() {
        let r = root(&mut parent, k);
        if let Some(g) = groups.iter_mut().find(|g| g.0 == r) {
            g.2.push(*u);
        }
    }
    groups.into_iter().map(|(_, e, u)| (e, u)).collect()
}

/// Solves `equations = 0` for `unknowns` exactly: all branches, or `None` (also when more
/// branches than `budget` would be listed).
fn solve_exactly(
    equations: &[Expr],
    unknowns: &[Symbol],
    budget: &mut usize,
) -> Option<Vec<Partial>> {
    let live: Vec<Expr> = equations.iter().copied().filter(|e| !e.is_zero()).collect();
    if unknowns.is_empty() {
        // Leftover equations free of the unknowns hold or not for given numbers; the numeric
        // check of every equilibrium decides.
        return Some(vec![Partial::default()]);
    }
    let involved = |e: Expr| -> Vec<Symbol> {
        unknowns
            .iter()
            .copied()
            .filter(|q| !e.diff(*q).is_zero())
            .collect()
    };
    // One equation in one unknown.
    for (i, e) in live.iter().enumerate() {
        let vars = involved(*e);
        if vars.len() != 1 {
            continue;
        }
        let x = vars[0];
        let Solved::Exact(solutions) = solve_for(*e, x) else {
            continue;
        };
        let rest_unknowns: Vec<Symbol> = unknowns.iter().copied().filter(|u| *u != x).collect();
        let mut branches = Vec::new();
        for s in solutions {
            let var = Expr::from_symbol(x);
            let pairs = substitution(var, s.value);
            let others: Vec<Expr> = live
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, e)| e.subs(&pairs).normal())
                .collect();
            for mut b in solve_exactly(&others, &rest_unknowns, budget)? {
                *budget = budget.checked_sub(1)?;
                let value = s.value.subs(
                    &b.values
                        .iter()
                        .map(|(k, v)| (Expr::from_symbol(*k), *v))
                        .collect::<Vec<_>>(),
                );
                b.values.insert(x, value);
                b.conditions.extend(s.conditions.iter().copied());
                branches.push(b);
            }
        }
        return Some(branches);
    }
    // No equation in one unknown: eliminate an unknown between two equations, when one's
    // dependence on it is the other's times a factor free of the unknowns (a two-link arm
    // with the second angle relative to the first), and solve the triangular system.
    if let Some(reduced) = eliminate_one(&live, unknowns) {
        return solve_exactly(&reduced, unknowns, budget);
    }
    // A linear system in all the unknowns.
    let atoms: Vec<Expr> = unknowns.iter().map(|u| Expr::from_symbol(*u)).collect();
    let linear: Vec<Expr> = live
        .iter()
        .copied()
        .filter(|e| !involved(*e).is_empty())
        .collect();
    if linear.len() == unknowns.len() {
        let mut rows = Vec::new();
        let mut rhs = Vec::new();
        for e in &linear {
            let (c, r) = e.affine_coefficients(&atoms)?;
            if c.iter().chain([&r]).any(|k| !involved(*k).is_empty()) {
                return None;
            }
            rows.push(c);
            rhs.push(-r);
        }
        let a = Matrix::from_rows(rows)?;
        let x = a.solve(&Matrix::column(rhs)).ok()?;
        let mut p = Partial::default();
        for (k, u) in unknowns.iter().enumerate() {
            p.values.insert(*u, x.get(k, 0)?.normal());
        }
        return Some(vec![p]);
    }
    None
}

/// The most unknowns [`eliminate_one`] works on.
const MAX_ELIMINATION_UNKNOWNS: usize = 6;

/// The longest equation (terms of its normal form's numerator) [`eliminate_one`] works on.
const MAX_ELIMINATION_TERMS: usize = 200;

/// One step of Gaussian elimination on nonlinear equations: `e_i − c e_j` with
/// `c = (∂e_i/∂x)/(∂e_j/∂x)` free of every unknown, so that the difference no longer holds
/// `x`. The system with `e_i` replaced is equivalent (an invertible combination of its
/// equations) and involves fewer unknowns, so repeating it ends. `None` when no pair allows it.
fn eliminate_one(equations: &[Expr], unknowns: &[Symbol]) -> Option<Vec<Expr>> {
    // Each try divides two derivatives: on many unknowns or long equations the pairs cost
    // more than the numeric search they would save.
    let long = equations
        .iter()
        .any(|e| e.term_count() > MAX_ELIMINATION_TERMS);
    if unknowns.len() > MAX_ELIMINATION_UNKNOWNS || long {
        return None;
    }
    let involved =
        |e: Expr| -> usize { unknowns.iter().filter(|q| !e.diff(**q).is_zero()).count() };
    let free_of_unknowns = |e: Expr| unknowns.iter().all(|q| e.diff(*q).is_zero());
    for (i, ei) in equations.iter().enumerate() {
        for (j, ej) in equations.iter().enumerate() {
            if i == j || involved(*ej) > involved(*ei) {
                continue;
            }
            for x in unknowns {
                let (di, dj) = (ei.diff(*x), ej.diff(*x));
                if di.is_zero() || dj.is_zero() {
                    continue;
                }
                let c = (di / dj).normal();
                if !free_of_unknowns(c) {
                    continue;
                }
                let combined = (*ei - c * *ej).normal();
                if involved(combined) < involved(*ei) {
                    let mut out = equations.to_vec();
                    out[i] = combined;
                    return Some(out);
                }
            }
        }
    }
    None
}

/// The substitution of `q = value` that also rewrites `sin q`, `cos q`, `tan q` in terms the
/// normal form can simplify (`cos(acos r) = r`, `sin(acos r) = √(1 − r²)`…).
fn substitution(q: Expr, value: Expr) -> Vec<(Expr, Expr)> {
    let (s, c) = (value.sin(), value.cos());
    vec![(q.sin(), s), (q.cos(), c), (q.tan(), s / c), (q, value)]
}

/// An evaluation environment from values by name (`None` for an unknown name).
pub fn environment(values: &Values) -> impl Fn(Symbol) -> Option<f64> + '_ {
    move |s: Symbol| values.get(s.name()).copied()
}

/// Evaluates `e` with coordinates `q = x` and the given values.
pub(crate) fn eval_at(e: Expr, rest: &RestEquations, x: &[f64], values: &Values) -> Option<f64> {
    let env = |s: Symbol| {
        rest.symbols
            .iter()
            .position(|q| *q == s)
            .map(|i| x[i])
            .or_else(|| values.get(s.name()).copied())
    };
    e.eval(&env).ok().filter(|v| v.is_finite())
}

/// Every symbol other than the coordinates must have a value; returns the first missing one.
pub fn check_values(rest: &RestEquations, values: &Values) -> Result<(), EquilibriumError> {
    for e in rest.residuals.iter().chain(rest.jacobian.iter().flatten()) {
        let multiplier = |s: Symbol| {
            rest.constraints
                .as_ref()
                .is_some_and(|k| k.multipliers.iter().any(|m| m.as_symbol() == Some(s)))
        };
        let env = |s: Symbol| {
            if rest.symbols.contains(&s) || multiplier(s) {
                Some(0.123_456_7)
            } else {
                values.get(s.name()).copied()
            }
        };
        if let Err(cas::EvalError::Unbound(name)) = e.eval(&env) {
            return Err(EquilibriumError::MissingValue { name });
        }
    }
    Ok(())
}

/// Wraps the periodic coordinates into (−π, π].
pub(crate) fn wrap(rest: &RestEquations, x: &mut [f64]) {
    for (v, p) in x.iter_mut().zip(&rest.periodic) {
        if *p {
            *v = numeric::roots::wrap_angle(*v);
        }
    }
}

/// Whether `x` satisfies the rest equations to rounding.
pub(crate) fn is_rest_state(rest: &RestEquations, x: &[f64], values: &Values) -> bool {
    rest.residuals.iter().enumerate().all(|(i, r)| {
        let Some(v) = eval_at(*r, rest, x, values) else {
            return false;
        };
        // Scale by the size of the Jacobian row, so the test is independent of units.
        let scale: f64 = rest.jacobian[i]
            .iter()
            .zip(x)
            .filter_map(|(j, xi)| eval_at(*j, rest, x, values).map(|d| d.abs() * (1.0 + xi.abs())))
            .sum();
        v.abs() <= 1e-8 * (1.0 + scale)
    })
}

/// All equilibria for the given values of parameters and inputs. `bounds` gives the range of
/// each non-angle coordinate (angles always span (−π, π]).
pub fn find_equilibria(
    rest: &RestEquations,
    values: &Values,
    bounds: &[(f64, f64)],
) -> Result<EquilibriumSet, EquilibriumError> {
    check_values(rest, values)?;
    let bounds = search_box(rest, bounds);
    let (mut found, method) = if let Some(kept) = &rest.constraints {
        let env = environment(values);
        let degenerate = kept.degenerate_when.iter().any(|e| {
            e.eval(&env)
                .map_or(true, |v| v.abs() <= 1e-12 * (1.0 + max_value(values)))
        });
        match rest.exact.as_ref().filter(|_| !degenerate) {
            Some(branches) => (
                crate::kkt::exact_kkt_equilibria(rest, kept, branches, values),
                Method::Exact,
            ),
            None => (
                kkt_equilibria(rest, kept, values, &bounds),
                Method::MultistartNewton,
            ),
        }
    } else if let Some(branches) = &rest.exact {
        (exact_equilibria(rest, branches, values), Method::Exact)
    } else if let Some(roots) = rest
        .polynomial
        .as_ref()
        .and_then(|p| polynomial_equilibria(rest, p, values, &bounds))
    {
        (roots, Method::Polynomial)
    } else {
        numeric_equilibria(rest, values, &bounds)
    };
    // −0.0 prints as "-0": fold it into 0.
    for e in &mut found {
        for v in &mut e.values {
            *v += 0.0;
        }
    }
    found.sort_by(|a, b| {
        a.values
            .iter()
            .zip(&b.values)
            .map(|(x, y)| x.total_cmp(y))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    Ok(EquilibriumSet {
        equilibria: found,
        method,
        bounds,
        repeated: Vec::new(),
    })
}

/// The largest magnitude among the values (the scale of a degenerate-case test).
fn max_value(values: &Values) -> f64 {
    values.values().fold(0.0_f64, |m, v| m.max(v.abs()))
}

/// The search box: angles over a turn, other coordinates over their given range (a missing or
/// reversed range falls back on the default −10..10).
fn search_box(rest: &RestEquations, bounds: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let pi = std::f64::consts::PI;
    rest.periodic
        .iter()
        .enumerate()
        .map(|(i, p)| match bounds.get(i) {
            _ if *p => (-pi, pi),
            Some((a, b)) if a <= b && a.is_finite() && b.is_finite() => (*a, *b),
            _ => (-10.0, 10.0),
        })
        .collect()
}

/// The exact branches that exist for these values, evaluated, checked and without repeats.
fn exact_equilibria(
    rest: &RestEquations,
    branches: &[Branch],
    values: &Values,
) -> Vec<Equilibrium> {
    let env = environment(values);
    let mut found: Vec<Equilibrium> = Vec::new();
    for b in branches {
        if b.conditions.iter().any(|c| c.holds(&env) != Some(true)) {
            continue;
        }
        let Some(mut x) = b
            .values
            .iter()
            .map(|v| v.eval(&env).ok().filter(|v| v.is_finite()))
            .collect::<Option<Vec<f64>>>()
        else {
            continue;
        };
        wrap(rest, &mut x);
        add_if_new(
            &mut found,
            rest,
            values,
            Equilibrium {
                values: x,
                exact: Some(b.values.clone()),
                conditions: b.conditions.clone(),
                multipliers: Vec::new(),
                exact_multipliers: None,
            },
        );
    }
    found
}

/// A numeric search over the coordinates that occur (free ones stay at 0), with the
/// equations that involve them; the others are checked at every root found.
fn numeric_equilibria(
    rest: &RestEquations,
    values: &Values,
    bounds: &[(f64, f64)],
) -> (Vec<Equilibrium>, Method) {
    let n = rest.symbols.len();
    let active: Vec<usize> = (0..n).filter(|i| !rest.free[*i]).collect();
    let rows: Vec<usize> = (0..n)
        .filter(|i| active.iter().any(|j| !rest.jacobian[*i][*j].is_zero()))
        .collect();
    let full = |y: &[f64]| -> Vec<f64> {
        let mut x = vec![0.0; n];
        for (k, i) in active.iter().enumerate() {
            x[*i] = y[k];
        }
        x
    };
    let residuals: Vec<Expr> = rows.iter().map(|i| rest.residuals[*i]).collect();
    let jacobian: Vec<Expr> = rows
        .iter()
        .flat_map(|i| active.iter().map(move |k| rest.jacobian[*i][*k]))
        .collect();
    let known: Vec<(Symbol, f64)> = values
        .iter()
        .filter_map(|(name, v)| Some((Expr::symbol(name).as_symbol()?, *v)))
        .collect();
    let compile = |exprs: &[Expr]| CompiledExprs::new(exprs, &rest.symbols, &known, &|_| None);
    let (residual_tape, jacobian_tape) = (compile(&residuals), compile(&jacobian));
    let by_trees = |exprs: &[Expr], y: &[f64]| -> Option<Vec<f64>> {
        let x = full(y);
        exprs
            .iter()
            .map(|e| eval_at(*e, rest, &x, values))
            .collect()
    };
    // The search evaluates these thousands of times: on compiled tapes where they compile.
    let f = |y: &[f64]| match &residual_tape {
        Some(tape) => tape.eval(&full(y)),
        None => by_trees(&residuals, y),
    };
    let j = |y: &[f64]| match &jacobian_tape {
        Some(tape) => tape.eval(&full(y)),
        None => by_trees(&jacobian, y),
    };
    let search = numeric::roots::Search::new(
        active.iter().map(|i| bounds[*i]).collect(),
        active.iter().map(|i| rest.periodic[*i]).collect(),
    );
    let roots = if rows.len() == active.len() {
        numeric::roots::find_roots(&f, &j, &search)
    } else {
        Vec::new()
    };
    let found = roots
        .into_iter()
        .map(|y| full(&y))
        .filter(|x| is_rest_state(rest, x, values))
        .map(|x| Equilibrium {
            values: x,
            exact: None,
            conditions: Vec::new(),
            multipliers: Vec::new(),
            exact_multipliers: None,
        })
        .collect();
    let method = if active.len() == 1 {
        Method::Scan
    } else {
        Method::MultistartNewton
    };
    (found, method)
}

/// Whether two points are the same equilibrium (angles modulo 2π).
/// Keeps `candidate` when it is a rest state and not one already found.
fn add_if_new(
    found: &mut Vec<Equilibrium>,
    rest: &RestEquations,
    values: &Values,
    candidate: Equilibrium,
) {
    let repeated = found
        .iter()
        .any(|e| same_point(&e.values, &candidate.values, &rest.periodic));
    if !repeated && is_rest_state(rest, &candidate.values, values) {
        found.push(candidate);
    }
}

pub(crate) fn same_point(a: &[f64], b: &[f64], periodic: &[bool]) -> bool {
    a.iter().zip(b).zip(periodic).all(|((x, y), p)| {
        let d = if *p {
            numeric::roots::wrap_angle(x - y)
        } else {
            x - y
        };
        d.abs() < 1e-9 * (1.0 + x.abs().max(y.abs()))
    })
}

/// The equilibria from the polynomial form; `None` when the polynomial vanishes identically
/// for these numbers (then the caller scans).
fn polynomial_equilibria(
    rest: &RestEquations,
    p: &RestPolynomial,
    values: &Values,
    bounds: &[(f64, f64)],
) -> Option<Vec<Equilibrium>> {
    let env = environment(values);
    let c: Vec<f64> = p
        .coefficients
        .iter()
        .map(|c| c.eval(&env).ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()?;
    let roots = real_roots(&c)?;
    let i = p.coordinate;
    let n = rest.symbols.len();
    let mut candidates: Vec<f64> = roots
        .into_iter()
        .map(|u| if p.half_angle { 2.0 * u.atan() } else { u })
        .collect();
    if p.half_angle {
        candidates.push(std::f64::consts::PI);
    }
    let point = |v: f64| {
        let mut x = vec![0.0; n];
        x[i] = v;
        x
    };
    let residual = |y: &[f64]| -> Option<Vec<f64>> {
        rest.residuals
            .iter()
            .map(|r| eval_at(*r, rest, &point(y[0]), values))
            .collect()
    };
    let row = rest
        .residuals
        .iter()
        .position(|r| rest.symbols.get(i).is_some_and(|x| !r.diff(*x).is_zero()))?;
    let f = |y: &[f64]| residual(y).map(|r| vec![r[row]]);
    let j = |y: &[f64]| eval_at(rest.jacobian[row][i], rest, &point(y[0]), values).map(|d| vec![d]);
    let mut found: Vec<Equilibrium> = Vec::new();
    for v in candidates {
        // Polish (a double root from the companion matrix is good to √ε only).
        let v = numeric::roots::newton(&f, &j, &[v], 1e-14).map_or(v, |r| r[0]);
        let mut x = point(v);
        wrap(rest, &mut x);
        if !p.half_angle && (x[i] < bounds[i].0 || x[i] > bounds[i].1) {
            continue;
        }
        add_if_new(
            &mut found,
            rest,
            values,
            Equilibrium {
                values: x,
                exact: None,
                conditions: Vec::new(),
                multipliers: Vec::new(),
                exact_multipliers: None,
            },
        );
    }
    Some(found)
}
