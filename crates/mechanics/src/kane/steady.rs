//! Steady motions of a (possibly nonholonomic) system and the linearization about them.
//!
//! A steady motion holds the *shape* coordinates (those the reduced equations depend on)
//! constant and turns the *cyclic* ones (those they do not depend on: a bicycle's position,
//! heading and wheel angles) at constant rates, which the rolling constraints tie together.
//! The linearized state is the shape coordinates not fixed by a holonomic constraint and the
//! independent speeds; its matrix is the exact derivative of `(q̇_S, M_r⁻¹ f_r)` (one dual
//! evaluation per state), the holonomically dependent coordinates following by Newton's
//! method in dual numbers.

use super::dynamics::{lift, KaneSystem, SpeedSplit};
use super::linear::solve;
use super::scalar::{Dual, Scalar};
use super::KaneError;

/// A steady motion to linearize about: a configuration (the holonomically dependent
/// coordinates are solved from it, the others kept) and the rates that are given (the others
/// follow: zero for shape coordinates, the constraints for the rest).
#[derive(Clone, Debug, PartialEq)]
pub struct SteadyMotion {
    /// The coordinates, in the system's order.
    pub configuration: Vec<f64>,
    /// The rates given, in the system's order.
    pub rates: Vec<Option<f64>>,
    /// The time (for systems that depend on it, which rarely have steady motions).
    pub time: f64,
}

/// The linearization about a steady motion.
#[derive(Clone, Debug, PartialEq)]
pub struct SteadyLinearization {
    /// Coordinates the equations do not depend on.
    pub cyclic: Vec<String>,
    /// The shape coordinates in the state.
    pub shape: Vec<String>,
    /// Coordinates fixed by the holonomic constraints.
    pub holonomic: Vec<String>,
    /// The coordinates whose rates are the independent speeds.
    pub speeds: Vec<String>,
    /// The steady configuration and rates.
    pub configuration: Vec<f64>,
    /// The steady rates.
    pub rates: Vec<f64>,
    /// The state matrix of `(δq_S, δu)`.
    pub state_matrix: Vec<Vec<f64>>,
    /// The states' names, in the matrix's order: the shape coordinates, then the speeds
    /// (`phi_d`).
    pub states: Vec<String>,
    /// The states that no other state changes and that change none (their row and column
    /// vanish): their zero eigenvalues are left out of [`SteadyLinearization::eigenvalues`].
    pub decoupled: Vec<String>,
    /// `M_r` at the steady motion (speeds × speeds).
    pub mass: Vec<Vec<f64>>,
    /// `−∂f_r/∂u` (speeds × speeds).
    pub damping: Vec<Vec<f64>>,
    /// `−∂f_r/∂q_S` (speeds × shape).
    pub stiffness: Vec<Vec<f64>>,
    /// The eigenvalues `(re, im)` of the state matrix without its decoupled states.
    pub eigenvalues: Vec<(f64, f64)>,
}

/// The roles of the coordinates at a steady motion.
pub(super) struct Roles {
    pub(super) split: SpeedSplit,
    pub(super) cyclic: Vec<bool>,
    pub(super) holonomic: Vec<usize>,
    pub(super) holonomic_rows: Vec<usize>,
    pub(super) shape: Vec<usize>,
}

impl KaneSystem {
    /// Linearizes about `motion` with the named values `values` (in
    /// [`KaneSystem::value_names`]' order).
    ///
    /// # Errors
    /// No configuration satisfying the holonomic constraints, rates not fixed or breaking the
    /// constraints, a motion that is not steady, or a singular matrix.
    pub fn linearize_steady(
        &self,
        motion: &SteadyMotion,
        values: &[f64],
    ) -> Result<SteadyLinearization, KaneError> {
        let t = motion.time;
        let roles = self.roles(&motion.configuration, t, values)?;
        let mut q = motion.configuration.clone();
        self.settle(&mut q, &roles, t, values)?;
        let qd = self.steady_rates(&q, motion, &roles, t, values)?;
        let u: Vec<f64> = roles.split.independent.iter().map(|i| qd[*i]).collect();
        let r = self.reduced(&roles.split, &q, &u, t, values)?;
        let ud = solve(r.mass.clone(), vec![r.forcing.clone()])
            .ok_or(KaneError::Singular("the reduced mass matrix"))?;
        let drift = ud[0].iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let speed = u.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        if drift > 1e-8 * speed * speed {
            return Err(KaneError::NotSteady(drift));
        }
        self.state_matrix(&roles, &q, &u, t, values, r.mass)
    }

    /// Splits the speeds twice: once to find the cyclic coordinates, then preferring them as
    /// the dependent rates (so the shape rates stay speeds).
    fn roles(&self, q0: &[f64], t: f64, values: &[f64]) -> Result<Roles, KaneError> {
        let (cyclic, prefer) = self.cyclic_and_preferred(q0, t, values)?;
        let free: Vec<bool> = cyclic.iter().map(|c| !c).collect();
        let split = self.split(q0, t, values, &prefer, &free)?;
        let (mut holonomic, mut holonomic_rows) = (Vec::new(), Vec::new());
        for (r, c) in split.rows.iter().zip(&split.dependent) {
            if *r < self.holonomic {
                holonomic.push(*c);
                holonomic_rows.push(*r);
            }
        }
        let shape = (0..q0.len())
            .filter(|j| !cyclic[*j] && !holonomic.contains(j))
            .collect();
        Ok(Roles {
            split,
            cyclic,
            holonomic,
            holonomic_rows,
            shape,
        })
    }

    /// The cyclic coordinates, and the coordinates to prefer as the dependent rates: the
    /// cyclic ones. They are judged under the split of the largest pivots, unless a split that
    /// avoids one of its dependent rates leaves more coordinates cyclic: the largest pivot
    /// depends on the units (a rolling disk's spin enters its contact's velocity as `R φ̇`,
    /// larger than `ẋ`'s `1` once `R > 1`), and a spin rate taken as dependent ties the
    /// reduced equations to the heading. Then only that split's cyclic dependent rates are
    /// preferred, so that the sizes cannot choose the spin again.
    pub(super) fn cyclic_and_preferred(
        &self,
        q0: &[f64],
        t: f64,
        values: &[f64],
    ) -> Result<(Vec<bool>, Vec<bool>), KaneError> {
        let n = q0.len();
        let all = vec![true; n];
        let first = self.split(q0, t, values, &vec![false; n], &all)?;
        let cyclic = self.cyclic(&first, q0, t, values)?;
        let count = |c: &[bool]| c.iter().filter(|x| **x).count();
        let mut better: Option<(SpeedSplit, Vec<bool>)> = None;
        for &avoided in &first.dependent {
            let others: Vec<bool> = (0..n).map(|j| j != avoided).collect();
            let Ok(other) = self.split(q0, t, values, &others, &all) else {
                continue;
            };
            let Ok(other_cyclic) = self.cyclic(&other, q0, t, values) else {
                continue;
            };
            let best = better.as_ref().map_or(count(&cyclic), |(_, c)| count(c));
            if count(&other_cyclic) > best {
                better = Some((other, other_cyclic));
            }
        }
        Ok(match better {
            None => (cyclic.clone(), cyclic),
            Some((split, cyclic)) => {
                let prefer = (0..n)
                    .map(|j| cyclic[j] && split.dependent.contains(&j))
                    .collect();
                (cyclic, prefer)
            }
        })
    }

    /// Which coordinates the reduced equations `M_r`, `f_r` do not depend on: exact
    /// derivatives at a generic state near `q0` (every coordinate moved, every speed nonzero)
    /// below rounding. (The rates of cyclic coordinates may depend on them: a bicycle's
    /// `ẋ = v cos ψ`.)
    pub(super) fn cyclic(
        &self,
        split: &SpeedSplit,
        q0: &[f64],
        t: f64,
        values: &[f64],
    ) -> Result<Vec<bool>, KaneError> {
        let n = q0.len();
        let holonomic: Vec<usize> = split
            .rows
            .iter()
            .zip(&split.dependent)
            .filter(|(r, _)| **r < self.holonomic)
            .map(|(_, c)| *c)
            .collect();
        let rows: Vec<usize> = split
            .rows
            .iter()
            .copied()
            .filter(|r| *r < self.holonomic)
            .collect();
        let mut q: Vec<f64> = q0
            .iter()
            .enumerate()
            .map(|(k, x)| x + 0.05 * (1.0 + (k % 3) as f64))
            .collect();
        self.newton(&mut q, &holonomic, &rows, t, values)?;
        let u: Vec<f64> = (0..split.independent.len())
            .map(|k| 0.7 + 0.3 * k as f64)
            .collect();
        let mut cyclic = vec![false; n];
        for (j, flag) in cyclic.iter_mut().enumerate() {
            let dq = super::dynamics::seeded(&q, j);
            let r = self.reduced(split, &dq, &lift(&u), Dual::constant_of(t), &lift(values))?;
            let all = r.mass.iter().flatten().chain(&r.forcing);
            let (size, change) = all.fold((1.0_f64, 0.0_f64), |(s, c), x| {
                (s.max(x.re.abs()), c.max(x.eps.abs()))
            });
            *flag = change <= 1e-9 * size;
        }
        Ok(cyclic)
    }

    /// Moves the holonomically dependent coordinates of `q` onto the constraints.
    pub(super) fn settle<T: Scalar>(
        &self,
        q: &mut [T],
        roles: &Roles,
        t: f64,
        values: &[f64],
    ) -> Result<(), KaneError> {
        self.newton(q, &roles.holonomic, &roles.holonomic_rows, t, values)
    }

    /// Newton's method on the holonomic rows `rows` for the coordinates `unknown`; the
    /// Jacobian is taken at the values, which is exact at the solution, so the derivatives
    /// that `T` carries come out exact after the last steps.
    pub(super) fn newton<T: Scalar>(
        &self,
        q: &mut [T],
        unknown: &[usize],
        rows: &[usize],
        t: f64,
        values: &[f64],
    ) -> Result<(), KaneError> {
        if unknown.is_empty() {
            return Ok(());
        }
        let tv: Vec<T> = values.iter().map(|v| T::constant(*v)).collect();
        let mut settled = 0;
        let mut residual = f64::INFINITY;
        for _ in 0..60 {
            let f = self.holonomic_values(q, T::constant(t), &tv);
            residual = rows.iter().fold(0.0_f64, |m, r| m.max(f[*r].value().abs()));
            if residual <= 1e-13 {
                settled += 1;
                if settled > 2 {
                    return Ok(());
                }
            }
            let real: Vec<f64> = q.iter().map(|x| x.value()).collect();
            let jac = self.holonomic_jacobian(&real, t, values);
            let a: Vec<Vec<T>> = rows
                .iter()
                .map(|r| unknown.iter().map(|c| T::constant(jac[*r][*c])).collect())
                .collect();
            let rhs: Vec<T> = rows.iter().map(|r| f[*r]).collect();
            let step = solve(a, vec![rhs])
                .ok_or(KaneError::Singular("the holonomic constraints' Jacobian"))?;
            for (k, c) in unknown.iter().enumerate() {
                q[*c] = q[*c] - step[0][k];
            }
        }
        Err(KaneError::NoConfiguration(residual))
    }
}
