//! The rates of a steady motion, and the state matrix about it.

use super::dynamics::{lift, seeded, KaneSystem};
use super::linear::solve;
use super::scalar::Dual;
use super::steady::{Roles, SteadyLinearization, SteadyMotion};
use super::KaneError;

impl KaneSystem {
    /// All rates at the steady configuration `q`: the given ones, zero for the shape
    /// coordinates, and the rest from the constraints `A q̇ + b = 0` (least squares over all
    /// rows, which must then hold exactly).
    pub(super) fn steady_rates(
        &self,
        q: &[f64],
        motion: &SteadyMotion,
        roles: &Roles,
        t: f64,
        values: &[f64],
    ) -> Result<Vec<f64>, KaneError> {
        let n = q.len();
        let mut qd = vec![0.0; n];
        let mut unknown = Vec::new();
        for (j, rate) in qd.iter_mut().enumerate() {
            match motion.rates.get(j).copied().flatten() {
                Some(v) if roles.cyclic[j] || v == 0.0 => *rate = v,
                Some(_) => return Err(KaneError::MovingShape(self.coordinates[j].clone())),
                None if roles.cyclic[j] || roles.holonomic.contains(&j) => unknown.push(j),
                None => {}
            }
        }
        let (a, b) = self.constraint_rows(q, t, values);
        let rhs: Vec<f64> = a
            .iter()
            .zip(&b)
            .map(|(row, bk)| -(bk + (0..n).map(|j| row[j] * qd[j]).sum::<f64>()))
            .collect();
        let normal: Vec<Vec<f64>> = unknown
            .iter()
            .map(|i| {
                unknown
                    .iter()
                    .map(|k| a.iter().map(|row| row[*i] * row[*k]).sum())
                    .collect()
            })
            .collect();
        let projected: Vec<f64> = unknown
            .iter()
            .map(|i| a.iter().zip(&rhs).map(|(row, r)| row[*i] * r).sum())
            .collect();
        let names = || {
            unknown
                .iter()
                .map(|j| format!("`{}`", self.coordinates[*j]))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let x = solve(normal, vec![projected]).ok_or_else(|| KaneError::RatesNotFixed(names()))?;
        for (k, j) in unknown.iter().enumerate() {
            qd[*j] = x[0][k];
        }
        let scale = qd.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        let residual = a
            .iter()
            .zip(&b)
            .map(|(row, bk)| (bk + (0..n).map(|j| row[j] * qd[j]).sum::<f64>()).abs())
            .fold(0.0_f64, f64::max);
        if residual > 1e-9 * scale {
            return Err(KaneError::RatesBreakConstraints(residual));
        }
        Ok(qd)
    }

    /// The state matrix of `(δq_S, δu)`, one dual evaluation per state, with `M_r`, `−∂f_r/∂u`
    /// and `−∂f_r/∂q_S`.
    pub(super) fn state_matrix(
        &self,
        roles: &Roles,
        q: &[f64],
        u: &[f64],
        t: f64,
        values: &[f64],
        mass: Vec<Vec<f64>>,
    ) -> Result<SteadyLinearization, KaneError> {
        let (s, p) = (roles.shape.len(), u.len());
        let mut columns = Vec::with_capacity(s + p);
        let mut stiffness = vec![vec![0.0; s]; p];
        let mut damping = vec![vec![0.0; p]; p];
        for d in 0..s + p {
            let mut dq = lift(q);
            if d < s {
                dq = seeded(q, roles.shape[d]);
            }
            self.settle(&mut dq, roles, t, values)?;
            let du = if d < s { lift(u) } else { seeded(u, d - s) };
            let r = self.reduced(&roles.split, &dq, &du, Dual::constant_of(t), &lift(values))?;
            let ud = solve(r.mass, vec![r.forcing.clone()])
                .ok_or(KaneError::Singular("the reduced mass matrix"))?;
            let mut col: Vec<f64> = roles.shape.iter().map(|j| r.rates[*j].eps).collect();
            col.extend(ud[0].iter().map(|x| x.eps));
            columns.push(col);
            for (i, f) in r.forcing.iter().enumerate() {
                if d < s {
                    stiffness[i][d] = -f.eps;
                } else {
                    damping[i][d - s] = -f.eps;
                }
            }
        }
        let state_matrix: Vec<Vec<f64>> = (0..s + p)
            .map(|i| columns.iter().map(|c| c[i]).collect())
            .collect();
        let coupled = coupled_states(&state_matrix);
        let kept: Vec<Vec<f64>> = coupled
            .iter()
            .map(|i| coupled.iter().map(|j| state_matrix[*i][*j]).collect())
            .collect();
        let eigenvalues = numeric::eigen::eigenvalues(&kept)
            .map_err(|_| KaneError::Singular("the state matrix's eigenproblem"))?;
        let mut states: Vec<String> = roles
            .shape
            .iter()
            .map(|j| self.coordinates[*j].clone())
            .collect();
        states.extend(
            roles
                .split
                .independent
                .iter()
                .map(|j| format!("{}_d", self.coordinates[*j])),
        );
        let decoupled = (0..s + p)
            .filter(|k| !coupled.contains(k))
            .map(|k| states[k].clone())
            .collect();
        let names = |idx: &[usize]| idx.iter().map(|j| self.coordinates[*j].clone()).collect();
        let cyclic: Vec<usize> = (0..q.len()).filter(|j| roles.cyclic[*j]).collect();
        let mut qd = vec![0.0; q.len()];
        let (a, b) = self.constraint_rows(q, t, values);
        if let Ok(rates) = self.rates_from_speeds(&roles.split, &a, &b, u) {
            qd = rates;
        }
        Ok(SteadyLinearization {
            cyclic: names(&cyclic),
            shape: names(&roles.shape),
            holonomic: names(&roles.holonomic),
            speeds: names(&roles.split.independent),
            configuration: q.to_vec(),
            rates: qd,
            state_matrix,
            states,
            decoupled,
            mass,
            damping,
            stiffness,
            eigenvalues,
        })
    }
}

/// The states that are coupled to others: a state whose row and column are zero (a conserved
/// speed, such as a bicycle's forward speed at first order) adds an exact zero eigenvalue,
/// which would hide a real eigenvalue passing through zero; it is left out of the eigenvalues.
fn coupled_states(a: &[Vec<f64>]) -> Vec<usize> {
    let scale = a.iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
    let tiny = 1e-12 * scale;
    (0..a.len())
        .filter(|k| {
            let row = a[*k].iter().any(|x| x.abs() > tiny);
            let column = a.iter().any(|r| r[*k].abs() > tiny);
            row || column
        })
        .collect()
}
