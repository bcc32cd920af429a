//! The stability of a steady motion stated in the parameters: Kane's reduced equations as
//! expressions ([`KaneSystem::symbolic`]), linearized symbolically about the steady motion,
//! their characteristic polynomial with the parameters as symbols, the family's zero roots
//! divided out, and the criterion read with the parameters' signs
//! ([`crate::stability_condition`]).
//!
//! With the state `x = (δq_S, δu)` (shape coordinates, independent speeds) and the reduced
//! equations `q̇_S = r_S(q, u)`, `M_r u̇ = f_r(q, u)`, where `f_r = 0` at the steady motion,
//!
//! ```text
//! P(λ) = det [ λ I − ∂r_S/∂q_S      −∂r_S/∂u   ]  = det M_r · det(λ I − A)
//!            [ −∂f_r/∂q_S      λ M_r − ∂f_r/∂u ]
//! ```
//!
//! The family of neighbouring steady motions gives `λ^k`, `k` its dimension (the numeric
//! [`SteadySpectrum`]'s). What is left, `Q(λ)`, decides:
//!
//! | `Q` | criterion | tests (each `> 0`) |
//! |---|---|---|
//! | even (`λ → −λ` symmetric: conservative), degree 2 | roots `λ²` real, negative | `c₀/c₂` |
//! | even, degree 4 | roots `λ²` real, negative, distinct | `c₂/c₄`, `c₀/c₄`, `(c₂² − 4 c₄ c₀)/c₄²` |
//! | degree ≤ 4 otherwise | Routh–Hurwitz (asymptotic) | `cₖ/c_d`, and `a₁a₂ − a₀a₃`, … |

use cas::{Expr, Matrix, Symbol};

use super::dynamics::KaneSystem;
use super::steady::SteadyLinearization;
use super::verdict::SteadySpectrum;
use super::KaneError;
use crate::stability_condition::{verdict_of, ConditionCriterion, StabilityCondition};

/// The largest state (shape coordinates and speeds) whose characteristic polynomial is
/// formed symbolically.
const MAX_STATES: usize = 6;

/// `x` as an exact number where it is one with a small denominator (`0`, `½`, `−4`), a
/// float otherwise: the steady configuration the numeric linearization settled on.
#[must_use]
pub fn exact_value(x: f64) -> Expr {
    super::symbolic::exact_number(x)
}

/// A steady motion given exactly: the configuration and the rates the model gives.
#[derive(Clone, Debug)]
pub struct ExactSteadyMotion {
    /// Each coordinate's value (exact numbers or expressions in the parameters).
    pub configuration: Vec<Expr>,
    /// Each coordinate's rate where the motion gives it.
    pub rates: Vec<Option<Expr>>,
}

impl KaneSystem {
    /// The stability condition of the steady motion `motion` in the parameters (module doc),
    /// `None` where the route does not apply: holonomically dependent coordinates, a state
    /// over six states, steady speeds the given rates do not fix, a family whose zero roots
    /// are not those of the numeric linearization `lin`, or a polynomial beyond the table.
    ///
    /// # Errors
    /// As [`KaneSystem::symbolic`]: the geometry or the equations over the size or work
    /// limits (the Whipple bicycle's).
    pub fn steady_condition(
        &self,
        motion: &ExactSteadyMotion,
        values: &[f64],
        (lin, spectrum): (&SteadyLinearization, &SteadySpectrum),
        positive: &dyn Fn(Symbol) -> bool,
    ) -> Result<Option<StabilityCondition>, KaneError> {
        if !lin.holonomic.is_empty() || lin.states.len() > MAX_STATES {
            return Ok(None);
        }
        let sample: Vec<f64> = (0..self.coordinates.len())
            .map(|k| 0.31 + 0.137 * ((k * 7 + 3) % 11) as f64)
            .collect();
        // The speeds as the numeric linearization chose them, at the steady configuration
        // with the cyclic coordinates' rates preferred as dependent (the contact point's
        // `ẋ`, `ẏ`): chosen at the generic sample instead, the pivots follow the sizes there
        // and may make a heading rate dependent, which ties the equations to the heading.
        let dependent: Vec<bool> = self
            .coordinates
            .iter()
            .map(|c| lin.cyclic.contains(c) && !lin.speeds.contains(c))
            .collect();
        let all = vec![true; dependent.len()];
        let split = self.split(&lin.configuration, 0.0, values, &dependent, &all)?;
        let eq = self.symbolic_with(split, &sample, values)?;
        let shape: Vec<usize> = lin
            .shape
            .iter()
            .filter_map(|s| self.coordinates.iter().position(|c| c == s))
            .collect();
        let speeds: Vec<Symbol> = eq
            .split
            .independent
            .iter()
            .filter_map(|j| Expr::rate(&self.coordinates[*j], 1).as_symbol())
            .collect();
        let coordinates: Vec<Symbol> = self
            .coordinates
            .iter()
            .filter_map(|c| Expr::coordinate(c).as_symbol())
            .collect();
        if speeds.len() != eq.split.independent.len() || coordinates.len() != sample.len() {
            return Ok(None);
        }
        let at_q: Vec<(Expr, Expr)> = coordinates
            .iter()
            .zip(&motion.configuration)
            .map(|(q, v)| (Expr::from_symbol(*q), *v))
            .collect();
        let Some(at_u) = steady_speeds(&eq.rates, &at_q, &speeds, &shape, motion) else {
            return Ok(None);
        };
        let at: Vec<(Expr, Expr)> = at_q.iter().chain(&at_u).copied().collect();
        let lambda = fresh_lambda(&self.values);
        let shape_symbols: Vec<Symbol> = shape.iter().map(|j| coordinates[*j]).collect();
        let pencil = characteristic_pencil(&eq, &shape, &shape_symbols, &speeds, &at, lambda);
        let polynomial = cas::limited(|| {
            Matrix::from_rows(pencil)
                .and_then(|m| m.determinant())
                .map(|d| coefficients(d.normal(), lambda, lin.states.len()))
        })
        .map_err(KaneError::WorkLimit)?;
        let Some(Some(all)) = polynomial else {
            return Ok(None);
        };
        let family = spectrum.family.iter().filter(|f| **f).count();
        if all.iter().take(family).any(|c| !c.is_zero())
            || all.get(family).is_none_or(|c| c.is_zero())
        {
            return Ok(None);
        }
        let mass = eq
            .mass
            .iter()
            .map(|row| row.iter().map(|e| e.subs(&at).normal()).collect())
            .collect();
        Ok(condition_of(&all[family..], lin, mass, positive))
    }
}

/// The symbol `λ` of the characteristic polynomial: `lambda`, or with an underscore added
/// until no named value has its name.
#[must_use]
pub fn fresh_lambda(names: &[String]) -> Expr {
    let mut name = String::from("lambda");
    while names.contains(&name) {
        name.push('_');
    }
    Expr::symbol(&name)
}

/// The condition read off the polynomial `rest` (the family's zero roots divided out).
fn condition_of(
    rest: &[Expr],
    lin: &SteadyLinearization,
    mass: Vec<Vec<Expr>>,
    positive: &dyn Fn(Symbol) -> bool,
) -> Option<StabilityCondition> {
    let (criterion, tests) = criterion_tests(rest)?;
    let (verdict, boundaries) = verdict_of(&tests, positive);
    Some(StabilityCondition {
        coordinates: lin.shape.clone(),
        mass,
        gyroscopic: Vec::new(),
        stiffness: Vec::new(),
        criterion,
        tests,
        verdict,
        boundaries,
        characteristic: rest.to_vec(),
    })
}

/// The steady values of the speeds: the given rates and the shape coordinates' zero rates,
/// linear in the speeds, solved exactly (`None` when they do not fix the speeds).
fn steady_speeds(
    rates: &[Expr],
    at_q: &[(Expr, Expr)],
    speeds: &[Symbol],
    shape: &[usize],
    motion: &ExactSteadyMotion,
) -> Option<Vec<(Expr, Expr)>> {
    let mut rows = Vec::new();
    let mut rhs = Vec::new();
    for (j, rate) in rates.iter().enumerate() {
        let target = match motion.rates.get(j).copied().flatten() {
            Some(given) => given,
            None if shape.contains(&j) => Expr::zero(),
            None => continue,
        };
        let at = rate.subs(at_q).normal();
        let row: Vec<Expr> = speeds.iter().map(|u| at.diff(*u)).collect();
        let zero: Vec<(Expr, Expr)> = speeds
            .iter()
            .map(|u| (Expr::from_symbol(*u), Expr::zero()))
            .collect();
        let constant = at.subs(&zero);
        if row.iter().all(|e| e.is_zero()) {
            continue;
        }
        rows.push(row);
        rhs.push((target - constant).normal());
    }
    if rows.len() != speeds.len() {
        return None;
    }
    let solution = Matrix::from_rows(rows)?.solve(&Matrix::column(rhs)).ok()?;
    speeds
        .iter()
        .enumerate()
        .map(|(k, u)| Some((Expr::from_symbol(*u), solution.get(k, 0)?.normal())))
        .collect()
}

/// The matrix `[[λ I − ∂r_S/∂q_S, −∂r_S/∂u], [−∂f_r/∂q_S, λ M_r − ∂f_r/∂u]]` at the steady
/// motion `at`.
fn characteristic_pencil(
    eq: &super::KaneEquations,
    shape: &[usize],
    shape_symbols: &[Symbol],
    speeds: &[Symbol],
    at: &[(Expr, Expr)],
    lambda: Expr,
) -> Vec<Vec<Expr>> {
    let point = |e: Expr| e.subs(at).normal();
    let variables: Vec<Symbol> = shape_symbols.iter().chain(speeds).copied().collect();
    let s = shape.len();
    let mut rows = Vec::with_capacity(s + speeds.len());
    for (i, j) in shape.iter().enumerate() {
        let rate = eq.rates[*j];
        rows.push(
            variables
                .iter()
                .enumerate()
                .map(|(c, x)| {
                    let own = if c == i { lambda } else { Expr::zero() };
                    (own - point(rate.diff(*x))).normal()
                })
                .collect(),
        );
    }
    for (k, force) in eq.forcing.iter().enumerate() {
        rows.push(
            variables
                .iter()
                .enumerate()
                .map(|(c, x)| {
                    let own = if c >= s {
                        lambda * point(eq.mass[k][c - s])
                    } else {
                        Expr::zero()
                    };
                    (own - point(force.diff(*x))).normal()
                })
                .collect(),
        );
    }
    rows
}

/// The coefficients `c₀ … c_n` of `p` in `λ` (`None` when `p` is not a polynomial in it).
fn coefficients(p: Expr, lambda: Expr, n: usize) -> Option<Vec<Expr>> {
    (0..=n)
        .map(|k| {
            let exponent = u32::try_from(k).ok()?;
            p.coeff(lambda, exponent).map(Expr::normal)
        })
        .collect()
}

/// The criterion for the polynomial `c₀ + c₁ λ + …` and the expressions it asks positive
/// (module doc's table); `None` beyond it.
fn criterion_tests(c: &[Expr]) -> Option<(ConditionCriterion, Vec<Expr>)> {
    let d = c.len().checked_sub(1)?;
    let lead = c[d];
    let ratio = |k: usize| (c[k] / lead).normal();
    let even = c.iter().skip(1).step_by(2).all(|x| x.is_zero());
    if even && d > 0 {
        let tests = match d {
            2 => vec![ratio(0)],
            4 => {
                let (a4, a2, a0) = (c[4], c[2], c[0]);
                let discriminant = ((a2.powi(2) - 4 * a4 * a0) / a4.powi(2)).normal();
                vec![ratio(2), ratio(0), discriminant]
            }
            _ => return None,
        };
        return Some((ConditionCriterion::EvenCharacteristic, tests));
    }
    // Routh–Hurwitz on `λ^d + a_{d−1} λ^{d−1} + … + a₀` (monic).
    let a: Vec<Expr> = (0..=d).map(ratio).collect();
    let mut tests: Vec<Expr> = a[..d].to_vec();
    match d {
        1 | 2 => {}
        3 => tests.push((a[2] * a[1] - a[0]).normal()),
        4 => tests.push((a[3] * a[2] * a[1] - a[1].powi(2) - a[3].powi(2) * a[0]).normal()),
        _ => return None,
    }
    Some((ConditionCriterion::RouthHurwitz, tests))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_even_quadratic_asks_its_constant_and_leading_coefficients_to_agree() {
        let (k, m) = (Expr::symbol("k"), Expr::symbol("m"));
        let (criterion, tests) = criterion_tests(&[k, Expr::zero(), m]).unwrap();
        assert_eq!(criterion, ConditionCriterion::EvenCharacteristic);
        assert!(tests[0].equals(k / m));
    }

    #[test]
    fn a_cubic_takes_routh_hurwitz() {
        let a: Vec<Expr> = ["a0", "a1", "a2"].map(Expr::symbol).to_vec();
        let c = vec![a[0], a[1], a[2], Expr::one()];
        let (criterion, tests) = criterion_tests(&c).unwrap();
        assert_eq!(criterion, ConditionCriterion::RouthHurwitz);
        assert_eq!(tests.len(), 4);
        assert!(tests[3].equals(a[2] * a[1] - a[0]));
    }
}
