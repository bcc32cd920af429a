//! Motion on Kane's route: the reduced equations `M_r u̇ = f_r` as a first-order system for
//! an integrator, evaluated numerically at each state (no symbolic equations of motion).
//!
//! | symbol | meaning | shape |
//! |---|---|---|
//! | `q_F` | the coordinates that no holonomic constraint fixes (integrated) | n − h |
//! | `q_H` | the coordinates a holonomic constraint fixes: `Φ(q_F, q_H, t) = 0` by Newton | h |
//! | `u` | the independent speeds (rates of some coordinates) | p |
//! | `q̇ = T u + s` | every rate from the speeds (the constraints' rows solved) | n |
//! | `y = (q_F, u)`, `ẏ = (q̇_F, M_r⁻¹ f_r)` | the integrated state and its rate | n − h + p |
//!
//! The split into speeds and dependent rates is chosen once, at the initial configuration
//! ([`KaneSystem::eom_split`]), and kept for the run, so that the state keeps its meaning; a
//! state where the kept rows no longer fix the dependent rates is a [`KaneError::Singular`].
//! The velocity constraints hold exactly at every evaluation (the dependent rates are solved
//! from them), and the holonomic ones to Newton's tolerance, so nothing drifts off them.

use super::dynamics::{KaneSystem, SpeedSplit};
use super::linear::solve;
use super::KaneError;

/// Kane's reduced equations of one system, with values, as `ẏ = F(t, y)`.
///
/// Invariant: `free`, `holonomic` partition the coordinates; `holonomic_rows[k]` is the
/// holonomic constraint row that fixes `holonomic[k]`; `configuration` satisfies the
/// holonomic constraints at the last state evaluated (Newton's next start).
#[derive(Clone, Debug)]
pub struct KaneMotion {
    system: KaneSystem,
    values: Vec<f64>,
    split: SpeedSplit,
    holonomic: Vec<usize>,
    holonomic_rows: Vec<usize>,
    free: Vec<usize>,
    configuration: Vec<f64>,
}

/// Relative size of a given rate's mismatch above which it breaks the constraints.
const RATE_TOLERANCE: f64 = 1e-8;

impl KaneMotion {
    /// Chooses the speeds at `configuration` and moves its holonomically fixed coordinates
    /// onto the constraints at time `t`. `values` are in [`KaneSystem::value_names`]' order.
    ///
    /// # Errors
    /// No speed is free, or the holonomic constraints have no solution near `configuration`.
    pub fn new(
        system: KaneSystem,
        values: Vec<f64>,
        configuration: &[f64],
        t: f64,
    ) -> Result<KaneMotion, KaneError> {
        let split = system.eom_split(configuration, &values)?;
        let (mut holonomic, mut holonomic_rows) = (Vec::new(), Vec::new());
        for (r, c) in split.rows.iter().zip(&split.dependent) {
            if *r < system.holonomic {
                holonomic.push(*c);
                holonomic_rows.push(*r);
            }
        }
        let free = (0..configuration.len())
            .filter(|j| !holonomic.contains(j))
            .collect();
        let mut q = configuration.to_vec();
        system.newton(&mut q, &holonomic, &holonomic_rows, t, &values)?;
        Ok(KaneMotion {
            system,
            values,
            split,
            holonomic,
            holonomic_rows,
            free,
            configuration: q,
        })
    }

    /// The length of the integrated state `y = (q_F, u)`.
    #[must_use]
    pub fn dimension(&self) -> usize {
        self.free.len() + self.split.independent.len()
    }

    /// The speeds and dependent rates.
    #[must_use]
    pub fn split(&self) -> &SpeedSplit {
        &self.split
    }

    /// The coordinates in the state (those no holonomic constraint fixes), in order.
    #[must_use]
    pub fn free(&self) -> &[usize] {
        &self.free
    }

    /// The coordinates the holonomic constraints fix, found by Newton's method.
    #[must_use]
    pub fn holonomic(&self) -> &[usize] {
        &self.holonomic
    }

    /// The compiled system.
    #[must_use]
    pub fn system(&self) -> &KaneSystem {
        &self.system
    }

    /// The configuration on the constraints (after [`KaneMotion::new`], the initial one).
    #[must_use]
    pub fn configuration(&self) -> &[f64] {
        &self.configuration
    }

    /// The initial state `y₀` at the configuration of [`KaneMotion::new`]: the speeds that
    /// give the rates given (`Some`) exactly and the others as small as the constraints allow
    /// (least squares with the given ones as conditions).
    ///
    /// # Errors
    /// [`KaneError::RatesBreakConstraints`] when the given rates contradict the constraints,
    /// [`KaneError::Singular`] when the kept rows do not fix the dependent rates here.
    pub fn initial_state(&self, rates: &[Option<f64>], t: f64) -> Result<Vec<f64>, KaneError> {
        let q = &self.configuration;
        let (columns, bias) = self.rate_map(q, t)?;
        let p = columns.len();
        let given: Vec<(usize, f64)> = rates
            .iter()
            .enumerate()
            .filter_map(|(j, r)| r.map(|v| (j, v)))
            .collect();
        let row = |j: usize| -> Vec<f64> { columns.iter().map(|c| c[j]).collect() };
        let kept = independent_rows(&given.iter().map(|(j, _)| row(*j)).collect::<Vec<_>>());
        let k = kept.len();
        // The conditions' KKT system: min Σ_U (T_j u + s_j)² subject to T_G u + s_G = r_G.
        let mut a = vec![vec![0.0; p + k]; p + k];
        let mut rhs = vec![0.0; p + k];
        for j in (0..q.len()).filter(|j| rates[*j].is_none()) {
            let t_j = row(j);
            for (x, tx) in t_j.iter().enumerate() {
                for (y, ty) in t_j.iter().enumerate() {
                    a[x][y] += tx * ty;
                }
                rhs[x] -= tx * bias[j];
            }
        }
        for (c, g) in kept.iter().enumerate() {
            let (j, v) = given[*g];
            for (x, tx) in row(j).iter().enumerate() {
                a[p + c][x] = *tx;
                a[x][p + c] = *tx;
            }
            rhs[p + c] = v - bias[j];
        }
        let x = solve(a, vec![rhs]).ok_or(KaneError::Singular("the initial rates' conditions"))?;
        let u = x[0][..p].to_vec();
        let worst = given.iter().fold(0.0_f64, |m, (j, v)| {
            let rate = bias[*j] + row(*j).iter().zip(&u).map(|(t, s)| t * s).sum::<f64>();
            m.max((rate - v).abs() / (1.0 + v.abs()))
        });
        if worst > RATE_TOLERANCE {
            return Err(KaneError::RatesBreakConstraints(worst));
        }
        let mut y: Vec<f64> = self.free.iter().map(|j| q[*j]).collect();
        y.extend(u);
        Ok(y)
    }

    /// `T`'s columns (the rates per unit of each speed) and `s` (the rates at `u = 0`).
    fn rate_map(&self, q: &[f64], t: f64) -> Result<(Vec<Vec<f64>>, Vec<f64>), KaneError> {
        let (a, b) = self.system.constraint_rows(q, t, &self.values);
        let p = self.split.independent.len();
        let bias = self
            .system
            .rates_from_speeds(&self.split, &a, &b, &vec![0.0; p])?;
        let zero_b = vec![0.0; b.len()];
        let columns = (0..p)
            .map(|k| {
                let unit: Vec<f64> = (0..p).map(|i| if i == k { 1.0 } else { 0.0 }).collect();
                self.system
                    .rates_from_speeds(&self.split, &a, &zero_b, &unit)
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok((columns, bias))
    }

    /// Every coordinate and every rate at `(t, y)`: the fixed coordinates by Newton's method
    /// from the last configuration, the rates from the speeds.
    ///
    /// # Errors
    /// As [`KaneMotion::derivative`].
    pub fn full_state(&mut self, t: f64, y: &[f64]) -> Result<(Vec<f64>, Vec<f64>), KaneError> {
        let q = self.settle(t, y)?;
        let (a, b) = self.system.constraint_rows(&q, t, &self.values);
        let u = &y[self.free.len()..];
        let qd = self.system.rates_from_speeds(&self.split, &a, &b, u)?;
        Ok((q, qd))
    }

    /// `ẏ = (q̇_F, M_r⁻¹ f_r)` at `(t, y)`, written into `dy`.
    ///
    /// # Errors
    /// [`KaneError::NoConfiguration`] when Newton's method finds no configuration on the
    /// holonomic constraints, [`KaneError::Singular`] when `M_r` or the kept constraint rows
    /// are singular here.
    pub fn derivative(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), KaneError> {
        let q = self.settle(t, y)?;
        let nf = self.free.len();
        let reduced = self
            .system
            .reduced(&self.split, &q, &y[nf..], t, &self.values)?;
        let ud = solve(reduced.mass, vec![reduced.forcing])
            .ok_or(KaneError::Singular("the reduced mass matrix"))?;
        for (slot, j) in dy.iter_mut().zip(&self.free) {
            *slot = reduced.rates[*j];
        }
        dy[nf..].copy_from_slice(&ud[0]);
        Ok(())
    }

    /// The energy `T + V` at a full state ([`KaneSystem::energy`]).
    #[must_use]
    pub fn energy(&self, q: &[f64], qd: &[f64], t: f64) -> f64 {
        self.system.energy(q, qd, t, &self.values)
    }

    /// The largest residual of the holonomic constraints `|Φ|` and of every constraint row at
    /// velocity level `|A q̇ + b|` at a full state.
    #[must_use]
    pub fn drift(&self, q: &[f64], qd: &[f64], t: f64) -> (f64, f64) {
        let phi = self.system.holonomic_values(q, t, &self.values);
        let position = phi.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let (a, b) = self.system.constraint_rows(q, t, &self.values);
        let velocity = a.iter().zip(&b).fold(0.0_f64, |m, (row, bi)| {
            let r = row.iter().zip(qd).map(|(x, v)| x * v).sum::<f64>() + bi;
            m.max(r.abs())
        });
        (position, velocity)
    }

    /// The configuration at `(t, y)`: the free coordinates from `y`, the fixed ones by
    /// Newton's method from the last configuration (kept for the next call).
    fn settle(&mut self, t: f64, y: &[f64]) -> Result<Vec<f64>, KaneError> {
        let mut q = self.configuration.clone();
        for (k, j) in self.free.iter().enumerate() {
            q[*j] = y[k];
        }
        self.system.newton(
            &mut q,
            &self.holonomic,
            &self.holonomic_rows,
            t,
            &self.values,
        )?;
        self.configuration.clone_from(&q);
        Ok(q)
    }
}

/// The indices of a maximal set of linearly independent rows (Gram–Schmidt, in order).
fn independent_rows(rows: &[Vec<f64>]) -> Vec<usize> {
    let scale = rows.iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let mut kept = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        let mut r = row.clone();
        for b in &basis {
            let d: f64 = r.iter().zip(b).map(|(x, y)| x * y).sum();
            for (x, y) in r.iter_mut().zip(b) {
                *x -= d * y;
            }
        }
        let norm = r.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm > 1e-9 * scale.max(1e-300) {
            basis.push(r.iter().map(|x| x / norm).collect());
            kept.push(i);
        }
    }
    kept
}
