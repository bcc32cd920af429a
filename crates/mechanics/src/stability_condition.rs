//! Stability stated in the parameters, as a course states it, at an equilibrium (or steady
//! motion) whose location is known in closed form: the symbolic `M0`, `G` (the skew part of
//! `C0`) and `K0` there, and the condition they give.
//!
//! | system at the point | criterion | the condition |
//! |---|---|---|
//! | one coordinate, conservative | Lagrange–Dirichlet | `K0 > 0` (iff, to first order) |
//! | n coordinates, conservative, `G = 0` | Sylvester on `K0` | every leading minor `Δ_k > 0` |
//! | steady motion, one coordinate not spinning | Routh | `∂²V_R/∂q² > 0` at fixed momenta |
//! | steady motion, n coordinates not spinning | Routh + Sylvester | leading minors of `∂²V_R` |
//! | two coordinates, gyroscopic `M0 q̈ + G q̇ + K0 q = 0` | roots of `det(M0 λ² + G λ + K0)` | see below |
//!
//! With two coordinates and `G = [[0, γ], [−γ, 0]]`, `det(M0 λ² + G λ + K0) = a₄ λ⁴ + a₂ λ² + a₀`
//! with `a₄ = det M0`, `a₂ = M₁₁K₂₂ + M₂₂K₁₁ − 2 M₁₂K₁₂ + γ²`, `a₀ = det K0`. The roots are
//! purely imaginary and distinct (the motion stays bounded to first order; gyroscopic
//! stabilisation when `K0` is not positive definite) iff, with `a₄ > 0`, `a₀ > 0`, `a₂ > 0`
//! and `a₂² − 4 a₄ a₀ > 0`. For the sleeping top this is Maxwell's `C² ω₃² > 4 A m g ℓ`.
//!
//! Where the condition's boundary (a leading minor, or the last condition, vanishing) makes
//! every rest equation vanish identically, the equilibria there are not isolated: a whole
//! family (the bead on a parabola spinning at `Ω² = 2 a g` rests at every `r`). That case is
//! reported as such ([`Boundary::family`]).

use cas::{solve_for, Expr, Solved, Symbol};

use crate::equilibria::RestEquations;
use crate::linearize::{substitute, LinearModel};
use crate::parameter_signs::{read_all, symbols, Inequality};

/// The criterion a [`StabilityCondition`] comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ConditionCriterion {
    /// One coordinate: the sign of `K0` (Lagrange–Dirichlet; the opposite sign is unstable).
    Sign,
    /// Sylvester's criterion on `K0`: its leading principal minors positive.
    Sylvester,
    /// Routh: the reduced potential's Hessian at fixed momenta, over the coordinates that do
    /// not spin (necessary and sufficient to first order for one such coordinate).
    Routh,
    /// Two coordinates coupled gyroscopically: the characteristic polynomial's roots purely
    /// imaginary and distinct.
    Gyroscopic,
    /// A steady motion of a conservative (nonholonomic) system: its characteristic
    /// polynomial, the family's zero roots divided out, even in `λ`, with every root in `λ²`
    /// real, negative and distinct (`mechanics::kane`'s steady condition).
    EvenCharacteristic,
    /// A steady motion: the characteristic polynomial, the family's zero roots divided out,
    /// with every root to the left of the imaginary axis (Routh–Hurwitz).
    RouthHurwitz,
}

impl ConditionCriterion {
    /// The sentence that names the criterion in reports.
    #[must_use]
    pub fn sentence(self) -> &'static str {
        match self {
            ConditionCriterion::Sign => "Lagrange–Dirichlet on the sign of K0",
            ConditionCriterion::Sylvester => {
                "Sylvester's criterion: the leading principal minors of K0 positive"
            }
            ConditionCriterion::Routh => {
                "Routh: the Hessian of the reduced potential at fixed momenta positive definite"
            }
            ConditionCriterion::Gyroscopic => {
                "the roots λ of det(M0 λ² + G λ + K0) = 0 purely imaginary and distinct"
            }
            ConditionCriterion::EvenCharacteristic => {
                "the roots λ of the characteristic polynomial, the family's zero roots divided \
                 out, purely imaginary and distinct"
            }
            ConditionCriterion::RouthHurwitz => {
                "Routh–Hurwitz on the characteristic polynomial, the family's zero roots \
                 divided out"
            }
        }
    }
}

/// When the condition holds.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Verdict {
    /// For every positive value of the positive parameters.
    Always,
    /// For none of them.
    Never,
    /// Exactly when every inequality holds.
    When(Vec<Inequality>),
}

/// The boundary of a condition, where one of its inequalities becomes an equality.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Boundary {
    /// The inequality whose equality this is.
    pub relation: Inequality,
    /// Whether there the rest equations hold for every value of the coordinates the
    /// condition is about: a family of equilibria, not a point.
    pub family: bool,
}

/// A stability condition in the parameters at one exactly known equilibrium or steady motion.
#[derive(Clone, Debug)]
pub struct StabilityCondition {
    /// The coordinates the condition is about (those not free or spinning).
    pub coordinates: Vec<String>,
    /// `M0` at the point, over those coordinates.
    pub mass: Vec<Vec<Expr>>,
    /// `G`, the skew part of `C0` at the point (zero at rest without gyroscopic coupling).
    pub gyroscopic: Vec<Vec<Expr>>,
    /// The stiffness the criterion reads: `K0`, or the reduced potential's Hessian (Routh).
    pub stiffness: Vec<Vec<Expr>>,
    /// The criterion.
    pub criterion: ConditionCriterion,
    /// The expressions the criterion asks to be positive (minors, `a₀`, `a₂`, the discriminant).
    pub tests: Vec<Expr>,
    /// When they all are, read for positive parameters.
    pub verdict: Verdict,
    /// The boundaries of the condition.
    pub boundaries: Vec<Boundary>,
    /// The characteristic polynomial's coefficients `c₀, c₁, …` (the family's zero roots
    /// divided out) where the criterion reads them; empty otherwise.
    pub characteristic: Vec<Expr>,
}

impl StabilityCondition {
    /// The condition in words: `stable iff Ω² < 2 a g` (with `print` for expressions).
    #[must_use]
    pub fn sentence(&self, print: fn(Expr) -> String) -> String {
        let how = if self.criterion == ConditionCriterion::Routh && self.coordinates.len() > 1 {
            "stable if"
        } else if self.criterion == ConditionCriterion::EvenCharacteristic {
            "stable to first order iff"
        } else {
            "stable iff"
        };
        match &self.verdict {
            Verdict::Always => "stable for every positive value of the parameters".to_owned(),
            Verdict::Never if self.criterion == ConditionCriterion::Sign => {
                "unstable or critical for every positive value of the parameters (K0 ≤ 0)"
                    .to_owned()
            }
            Verdict::Never => {
                "the criterion is met for no positive value of the parameters".to_owned()
            }
            Verdict::When(all) => {
                let parts: Vec<String> = all.iter().map(|i| i.text(print)).collect();
                format!("{how} {}", parts.join(" and "))
            }
        }
    }

    /// What happens on each boundary, in words (`at Ω² = 2 a g every r is an equilibrium`).
    #[must_use]
    pub fn boundary_sentences(&self, print: fn(Expr) -> String) -> Vec<String> {
        self.boundaries
            .iter()
            .map(|b| {
                let (left, _, right) = b.relation.reading_order();
                let at = format!("at {} = {}", print(left), print(right));
                if b.family {
                    format!(
                        "{at} every {} is an equilibrium (a family of equilibria, not a point; \
                         degenerate)",
                        self.coordinates.join(", ")
                    )
                } else {
                    format!("{at} the linearization does not decide (a critical case)")
                }
            })
            .collect()
    }
}

/// The stability condition at the equilibrium `exact` (one value per coordinate), with the
/// parameters for which `positive` holds taken positive. `None` where no criterion above
/// applies: constraints kept by multipliers, non-conservative or damped systems, gyroscopic
/// coupling of more than two coordinates, or a point where `M0` is singular.
#[must_use]
pub fn stability_condition(
    model: &LinearModel,
    rest: &RestEquations,
    exact: &[Expr],
    positive: &dyn Fn(Symbol) -> bool,
) -> Option<StabilityCondition> {
    if rest.constraints.is_some() || exact.len() != rest.symbols.len() {
        return None;
    }
    let spinning = |i: usize| rest.spinning.contains(&rest.coordinates[i]);
    let bound: Vec<usize> = (0..exact.len())
        .filter(|i| !rest.free[*i] && !spinning(*i))
        .collect();
    // Determinants by cofactors grow as n!: beyond a few coordinates the condition would be
    // too long to read anyway.
    if bound.is_empty() || bound.len() > MAX_COORDINATES {
        return None;
    }
    let pick = |m: &[Vec<Expr>]| -> Vec<Vec<Expr>> {
        let at = substitute(m, rest, exact);
        bound
            .iter()
            .map(|i| bound.iter().map(|j| at[*i][*j]).collect())
            .collect()
    };
    // At a pole of the coordinates (`M0` singular) the linearization in them says nothing;
    // crate users decide there in a regular chart.
    if determinant(&substitute(&model.mass, rest, exact)).is_zero() {
        return None;
    }
    let mass = pick(&model.mass);
    let damping = pick(&model.damping);
    let (symmetric, gyroscopic) = parts(&damping);
    if !all_zero(&symmetric) {
        return None;
    }
    let (criterion, stiffness, tests) = match &model.routh {
        Some(routh) => {
            let reduced = routh_hessian(routh, rest, exact, &bound);
            (
                ConditionCriterion::Routh,
                reduced.clone(),
                leading_minors(&reduced),
            )
        }
        None => {
            let stiffness = pick(&model.stiffness);
            if !same(&stiffness, &pick(&model.hessian)) {
                return None;
            }
            at_rest(&mass, &gyroscopic, stiffness)?
        }
    };
    let verdict = match read_all(&tests, positive) {
        None => Verdict::Never,
        Some(v) if v.is_empty() => Verdict::Always,
        Some(v) => Verdict::When(v),
    };
    let names: Vec<String> = bound.iter().map(|i| rest.coordinates[*i].clone()).collect();
    let boundaries = boundaries(&verdict, rest, &bound);
    Some(StabilityCondition {
        coordinates: names,
        mass,
        gyroscopic,
        stiffness,
        criterion,
        tests,
        verdict,
        boundaries,
        characteristic: Vec::new(),
    })
}

/// The most coordinates a condition is stated for.
const MAX_COORDINATES: usize = 4;

type Criterion = (ConditionCriterion, Vec<Vec<Expr>>, Vec<Expr>);

/// The criterion at rest: the sign of `K0`, Sylvester's minors, or the two-coordinate
/// gyroscopic conditions.
fn at_rest(
    mass: &[Vec<Expr>],
    gyroscopic: &[Vec<Expr>],
    stiffness: Vec<Vec<Expr>>,
) -> Option<Criterion> {
    if !all_zero(gyroscopic) {
        let tests = gyroscopic_conditions(mass, gyroscopic, &stiffness)?;
        return Some((ConditionCriterion::Gyroscopic, stiffness, tests));
    }
    let tests = leading_minors(&stiffness);
    let criterion = if stiffness.len() == 1 {
        ConditionCriterion::Sign
    } else {
        ConditionCriterion::Sylvester
    };
    Some((criterion, stiffness, tests))
}

/// `a₀`, `a₂` and `a₂² − 4 a₄ a₀` of `det(M λ² + G λ + K)` for two coordinates (module doc).
fn gyroscopic_conditions(m: &[Vec<Expr>], g: &[Vec<Expr>], k: &[Vec<Expr>]) -> Option<Vec<Expr>> {
    if m.len() != 2 {
        return None;
    }
    let gamma = g[0][1];
    let a4 = determinant(m);
    let a2 =
        (m[0][0] * k[1][1] + m[1][1] * k[0][0] - 2 * m[0][1] * k[0][1] + gamma.powi(2)).normal();
    let a0 = determinant(k);
    let discriminant = (a2.powi(2) - 4 * a4 * a0).normal();
    // Dividing by `a₄ = det M0 > 0` keeps the signs.
    Some(vec![a0, a2, discriminant])
}

/// The Hessian of Routh's reduced potential at the point, the momenta at their values there,
/// over the `bound` coordinates.
fn routh_hessian(
    routh: &crate::linearize::Routh,
    rest: &RestEquations,
    exact: &[Expr],
    bound: &[usize],
) -> Vec<Vec<Expr>> {
    let momenta: Vec<(Expr, Expr)> = routh
        .momenta
        .iter()
        .zip(&routh.momentum_values)
        .map(|(p, v)| (*p, *v))
        .collect();
    let with_momenta: Vec<Vec<Expr>> = routh
        .hessian
        .iter()
        .map(|row| row.iter().map(|h| h.subs(&momenta)).collect())
        .collect();
    let at = substitute(&with_momenta, rest, exact);
    bound
        .iter()
        .map(|i| bound.iter().map(|j| at[*i][*j]).collect())
        .collect()
}

/// The boundaries of the verdict's inequalities, each checked for a family of equilibria.
fn boundaries(verdict: &Verdict, rest: &RestEquations, bound: &[usize]) -> Vec<Boundary> {
    let Verdict::When(all) = verdict else {
        return Vec::new();
    };
    all.iter()
        .map(|relation| Boundary {
            relation: *relation,
            family: is_family(relation.difference(), rest, bound),
        })
        .collect()
}

/// Whether `boundary = 0` makes every rest equation vanish for every value of the `bound`
/// coordinates: solved for a parameter it holds to the first power, substituted.
fn is_family(boundary: Expr, rest: &RestEquations, bound: &[usize]) -> bool {
    let coordinates: Vec<Symbol> = bound.iter().map(|i| rest.symbols[*i]).collect();
    for s in symbols(boundary) {
        if rest.symbols.contains(&s)
            || boundary
                .coeff(Expr::from_symbol(s), 2)
                .is_none_or(|c| !c.is_zero())
        {
            continue;
        }
        let Solved::Exact(solutions) = solve_for(boundary, s) else {
            continue;
        };
        let [solution] = solutions.as_slice() else {
            continue;
        };
        let pair = [(Expr::from_symbol(s), solution.value)];
        let vanish = rest.residuals.iter().all(|r| r.subs(&pair).is_zero());
        let involved = rest
            .residuals
            .iter()
            .any(|r| coordinates.iter().any(|q| !r.diff(*q).is_zero()));
        return vanish && involved;
    }
    false
}

/// The leading principal minors `Δ₁, …, Δₙ`.
fn leading_minors(m: &[Vec<Expr>]) -> Vec<Expr> {
    (1..=m.len())
        .map(|k| {
            let block: Vec<Vec<Expr>> = m[..k].iter().map(|row| row[..k].to_vec()).collect();
            determinant(&block)
        })
        .collect()
}

/// The determinant by cofactors along the first row (the matrices here are small).
fn determinant(m: &[Vec<Expr>]) -> Expr {
    match m.len() {
        0 => Expr::one(),
        1 => m[0][0].normal(),
        n => {
            let terms = (0..n).map(|j| {
                let minor: Vec<Vec<Expr>> = m[1..]
                    .iter()
                    .map(|row| {
                        row.iter()
                            .enumerate()
                            .filter(|(c, _)| *c != j)
                            .map(|(_, e)| *e)
                            .collect()
                    })
                    .collect();
                let sign = if j % 2 == 0 { 1 } else { -1 };
                sign * m[0][j] * determinant(&minor)
            });
            Expr::add_all(terms).normal()
        }
    }
}

/// The symmetric and skew parts of a square matrix.
fn parts(m: &[Vec<Expr>]) -> (Vec<Vec<Expr>>, Vec<Vec<Expr>>) {
    let n = m.len();
    let half = |sign: i64| -> Vec<Vec<Expr>> {
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| ((m[i][j] + sign * m[j][i]) / 2).normal())
                    .collect()
            })
            .collect()
    };
    (half(1), half(-1))
}

fn all_zero(m: &[Vec<Expr>]) -> bool {
    m.iter().flatten().all(|e| e.is_zero())
}

fn same(a: &[Vec<Expr>], b: &[Vec<Expr>]) -> bool {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .all(|(x, y)| (*x - *y).is_zero())
}

/// The condition of a steady motion whose linearization in a regular chart `(u, v)` is
/// isotropic: `M = m I`, `G = γ J`, `K = k I` (a symmetric top sleeping upright, where
/// `m = A`, `γ = C ω₃`, `k = −m g ℓ`). The two-coordinate gyroscopic conditions then read
/// `γ² + 4 m k > 0` — Maxwell's `C² ω₃² > 4 A m g ℓ` — with the parameters for which
/// `positive` holds taken positive.
#[must_use]
pub fn isotropic_condition(
    [m, gamma, k]: [Expr; 3],
    positive: &dyn Fn(Symbol) -> bool,
) -> StabilityCondition {
    let zero = Expr::zero();
    let mass = vec![vec![m, zero], vec![zero, m]];
    let gyroscopic = vec![vec![zero, gamma], vec![-gamma, zero]];
    let stiffness = vec![vec![k, zero], vec![zero, k]];
    let tests = gyroscopic_conditions(&mass, &gyroscopic, &stiffness).unwrap_or_default();
    let (verdict, boundaries) = verdict_of(&tests, positive);
    StabilityCondition {
        coordinates: vec!["u".to_owned(), "v".to_owned()],
        mass,
        gyroscopic,
        stiffness,
        criterion: ConditionCriterion::Gyroscopic,
        tests,
        verdict,
        boundaries,
        characteristic: Vec::new(),
    }
}

/// The verdict of the tests (each `> 0`) read with the parameters' signs, and its
/// boundaries (none of them a family of equilibria).
pub(crate) fn verdict_of(
    tests: &[Expr],
    positive: &dyn Fn(Symbol) -> bool,
) -> (Verdict, Vec<Boundary>) {
    let verdict = match read_all(tests, positive) {
        None => Verdict::Never,
        Some(v) if v.is_empty() => Verdict::Always,
        Some(v) => Verdict::When(v),
    };
    let boundaries = match &verdict {
        Verdict::When(all) => all
            .iter()
            .map(|relation| Boundary {
                relation: *relation,
                family: false,
            })
            .collect(),
        _ => Vec::new(),
    };
    (verdict, boundaries)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_isotropic_gyroscopic_case_is_maxwells_criterion() {
        let [a, c, m, g, l, w] = ["A", "C", "M", "g", "l", "w"].map(Expr::symbol);
        let spin = w.as_symbol();
        let positive = |s: Symbol| Some(s) != spin;
        let condition = isotropic_condition([a, c * w, -(m * g * l)], &positive);
        let Verdict::When(all) = &condition.verdict else {
            panic!("{:?}", condition.verdict)
        };
        // a₀ = (m g ℓ)² > 0 always; a₂ = C² ω² − 2 A m g ℓ > 0 follows from the discriminant's.
        assert_eq!(all.len(), 1);
        assert!(all[0]
            .difference()
            .equals(c.powi(2) * w.powi(2) - 4 * a * m * g * l));
        assert_eq!(all[0].reading_order().1, ">");
        // A top hanging down (k > 0) is stable at any spin.
        let hanging = isotropic_condition([a, c * w, m * g * l], &positive);
        assert_eq!(hanging.verdict, Verdict::Always);
    }

    #[test]
    fn determinants_and_minors_of_a_small_matrix() {
        let (k1, k2) = (Expr::symbol("k1"), Expr::symbol("k2"));
        let k = vec![vec![k1 + k2, -k2], vec![-k2, k2]];
        let minors = leading_minors(&k);
        assert!(minors[0].equals(k1 + k2));
        assert!(minors[1].equals(k1 * k2));
        let positive = |_: Symbol| true;
        assert_eq!(read_all(&minors, &positive), Some(Vec::new()));
    }
}
