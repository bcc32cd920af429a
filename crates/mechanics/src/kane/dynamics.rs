//! Kane's equations at a state: partial velocities, generalized active and inertia forces, and
//! the reduction to the independent speeds.

use cas::Expr;

use super::linear::{solve, transpose_times};
use super::program::{Program, Variables};
use super::scalar::{Dual, Scalar};
use super::KaneError;
use crate::system::{ConstraintForm, Load, System};

/// Outputs of the geometry program per body: mass, centre (3), rotation (9), inertia (9).
pub(super) const BODY: usize = 22;
/// Outputs per particle: mass, position (3).
pub(super) const PARTICLE: usize = 4;

/// Where a load's numbers are among the geometry program's outputs.
#[derive(Clone, Debug)]
pub(super) enum LoadSlot {
    /// Force (3) then point (3) at this offset.
    Force(usize),
    /// Moment (3) at this offset, on this body.
    Couple(usize, usize),
    /// A generalized force at this offset, on this coordinate.
    Generalized(usize, usize),
    /// A potential energy at this offset.
    Potential(usize),
}

/// A system compiled for Kane's method: its geometry and constraints as programs over the
/// coordinates, rates, time and named values.
#[derive(Clone, Debug)]
pub struct KaneSystem {
    pub(super) coordinates: Vec<String>,
    pub(super) values: Vec<String>,
    pub(super) vars: Variables,
    pub(super) geometry: Program,
    pub(super) holonomic_only: Program,
    pub(super) rates: Program,
    pub(super) bodies: usize,
    pub(super) particles: usize,
    pub(super) gravity: usize,
    pub(super) loads: Vec<LoadSlot>,
    pub(super) holonomic: usize,
    pub(super) holonomic_at: usize,
    pub(super) velocity: usize,
    pub(super) dissipations: usize,
}

/// Which rates are the independent speeds, and which constraint rows fix the others.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SpeedSplit {
    /// Coordinates whose rates are the speeds `u`, in order.
    pub independent: Vec<usize>,
    /// Coordinates whose rates follow from the constraints.
    pub dependent: Vec<usize>,
    /// The constraint rows kept (holonomic rows first, then velocity rows), one per dependent
    /// rate; the others are combinations of them.
    pub rows: Vec<usize>,
}

/// The reduced equations at one state.
#[derive(Clone, Debug)]
pub struct Reduced<T> {
    /// `M_r = Tᵀ M T`.
    pub mass: Vec<Vec<T>>,
    /// `f_r`.
    pub forcing: Vec<T>,
    /// All the rates `q̇ = T u + s`.
    pub rates: Vec<T>,
    /// `T`: the rates per unit of each speed (n×p).
    pub speed_matrix: Vec<Vec<T>>,
    /// The accelerations the constraints need when `u̇ = 0`: `q̈ = T u̇ + bias`.
    pub bias: Vec<T>,
}

impl<T: Scalar> Reduced<T> {
    /// The accelerations of all coordinates, `q̈ = T M_r⁻¹ f_r + bias`.
    ///
    /// # Errors
    /// [`KaneError::Singular`] when `M_r` is.
    pub fn accelerations(&self) -> Result<Vec<T>, KaneError> {
        let ud = solve(self.mass.clone(), vec![self.forcing.clone()])
            .ok_or(KaneError::Singular("the reduced mass matrix"))?;
        Ok(self
            .speed_matrix
            .iter()
            .zip(&self.bias)
            .map(|(row, b)| row.iter().zip(&ud[0]).fold(*b, |acc, (t, u)| acc + *t * *u))
            .collect())
    }
}

/// The geometry's values and their derivatives in each coordinate's direction.
pub(super) struct Partials<T> {
    pub(super) value: Vec<T>,
    pub(super) by_coordinate: Vec<Vec<T>>,
}

impl KaneSystem {
    /// Compiles `system`; `values` names every parameter and input that has a value (their
    /// numbers are given at each evaluation, so one compilation serves a sweep).
    ///
    /// # Errors
    /// A symbol without a value, an acceleration in an expression, an unknown function.
    pub fn new(system: &System, values: &[String]) -> Result<KaneSystem, KaneError> {
        let coordinates = system.coordinates().to_vec();
        let vars = Variables::new(&coordinates, values);
        let mut out: Vec<Expr> = Vec::new();
        for b in system.bodies() {
            out.push(b.mass);
            out.extend(b.centre);
            out.extend(b.rotation.iter().flatten());
            out.extend(b.inertia.iter().flatten());
        }
        for p in system.particles() {
            out.push(p.mass);
            out.extend(p.position);
        }
        let gravity = out.len();
        out.extend(system.gravity());
        let mut loads = Vec::new();
        let mut dissipation = Vec::new();
        for load in system.loads() {
            match load {
                Load::Force { force, point } => {
                    loads.push(LoadSlot::Force(out.len()));
                    out.extend(*force);
                    out.extend(*point);
                }
                Load::Couple { moment, body } => {
                    loads.push(LoadSlot::Couple(out.len(), *body));
                    out.extend(*moment);
                }
                Load::GeneralizedForce { force, coordinate } => {
                    loads.push(LoadSlot::Generalized(out.len(), *coordinate));
                    out.push(*force);
                }
                Load::Potential(v) => {
                    loads.push(LoadSlot::Potential(out.len()));
                    out.push(*v);
                }
                Load::Dissipation(d) => dissipation.push(*d),
                _ => {}
            }
        }
        let (mut holonomic, mut velocity) = (Vec::new(), Vec::new());
        for c in system.constraints() {
            for e in &c.equations {
                match e {
                    ConstraintForm::Holonomic(f) => holonomic.push(*f),
                    ConstraintForm::Velocity(f) => velocity.push(*f),
                }
            }
        }
        let holonomic_at = out.len();
        out.extend(holonomic.iter().copied());
        let mut rate_out = velocity.clone();
        rate_out.extend(dissipation.iter().copied());
        Ok(KaneSystem {
            geometry: Program::new(&vars, &out)?,
            holonomic_only: Program::new(&vars, &holonomic)?,
            rates: Program::new(&vars, &rate_out)?,
            coordinates,
            values: values.to_vec(),
            vars,
            bodies: system.bodies().len(),
            particles: system.particles().len(),
            gravity,
            loads,
            holonomic: holonomic.len(),
            holonomic_at,
            velocity: velocity.len(),
            dissipations: dissipation.len(),
        })
    }

    /// The coordinates' names.
    pub fn coordinates(&self) -> &[String] {
        &self.coordinates
    }

    /// The names of the values, in the order [`KaneSystem::reduced`] takes them.
    pub fn value_names(&self) -> &[String] {
        &self.values
    }

    /// The number of operations of the compiled geometry (the shared graph's size).
    pub fn size(&self) -> usize {
        self.geometry.len() + self.rates.len()
    }

    /// How many holonomic constraint equations there are.
    pub fn holonomic_count(&self) -> usize {
        self.holonomic
    }

    fn variables<T: Scalar>(&self, q: &[T], qd: &[T], t: T, values: &[T]) -> Vec<T> {
        let mut v = Vec::with_capacity(self.vars.len());
        v.extend_from_slice(q);
        v.extend_from_slice(qd);
        v.push(t);
        v.extend_from_slice(values);
        v
    }

    /// The holonomic constraints' values `f(q, t)`.
    pub fn holonomic_values<T: Scalar>(&self, q: &[T], t: T, values: &[T]) -> Vec<T> {
        let zero = vec![T::constant(0.0); q.len()];
        self.holonomic_only
            .eval(&self.variables(q, &zero, t, values))
    }

    /// The holonomic constraints' Jacobian `∂f/∂q` at a configuration (rows: equations).
    pub fn holonomic_jacobian(&self, q: &[f64], t: f64, values: &[f64]) -> Vec<Vec<f64>> {
        let mut rows = vec![vec![0.0; q.len()]; self.holonomic];
        for j in 0..q.len() {
            let dq = seeded(q, j);
            let d = self.holonomic_values(&dq, Dual::constant(t), &lift(values));
            for (row, x) in rows.iter_mut().zip(d) {
                row[j] = x.eps;
            }
        }
        rows
    }

    /// The geometry and its derivative along each coordinate.
    fn partials<T: Scalar>(&self, q: &[T], qd: &[T], t: T, values: &[T]) -> Partials<T> {
        let n = q.len();
        let rates = lift(qd);
        let vals = lift(values);
        let mut by_coordinate = Vec::with_capacity(n);
        let mut value = Vec::new();
        for j in 0..n {
            let out = self.geometry.eval(&self.variables(
                &seeded(q, j),
                &rates,
                Dual::constant_of(t),
                &vals,
            ));
            if j == 0 {
                value = out.iter().map(|x| x.re).collect();
            }
            by_coordinate.push(out.into_iter().map(|x| x.eps).collect());
        }
        if n == 0 {
            value = self.geometry.eval(&self.variables(q, qd, t, values));
        }
        Partials {
            value,
            by_coordinate,
        }
    }

    /// The full constraint rows `A` (holonomic rows `∂f/∂q`, then velocity rows) and `b`
    /// (`∂f/∂t`, then the velocity constraints at zero rates).
    pub fn constraint_rows<T: Scalar>(&self, q: &[T], t: T, values: &[T]) -> (Vec<Vec<T>>, Vec<T>) {
        let n = q.len();
        let zero_t = T::constant(0.0);
        let mut a = vec![vec![zero_t; n]; self.holonomic + self.velocity];
        let mut b = vec![zero_t; self.holonomic + self.velocity];
        let dt = self.holonomic_values(&lift(q), Dual::new(t, T::constant(1.0)), &lift(values));
        for (k, x) in dt.iter().enumerate() {
            b[k] = x.eps;
        }
        // One column of `A` per coordinate, from the derivative along it.
        for (j, _) in q.iter().enumerate() {
            let d = self.holonomic_values(&seeded(q, j), Dual::constant_of(t), &lift(values));
            for (k, x) in d.iter().enumerate() {
                a[k][j] = x.eps;
            }
            let rates = seeded(&vec![zero_t; n], j);
            let c = self.rates.eval(&self.variables(
                &lift(q),
                &rates,
                Dual::constant_of(t),
                &lift(values),
            ));
            for (k, ck) in c.iter().take(self.velocity).enumerate() {
                a[self.holonomic + k][j] = ck.eps;
                b[self.holonomic + k] = ck.re;
            }
        }
        (a, b)
    }

    /// The rates `q̇` from the speeds `u` (the dependent ones solved from the kept rows).
    ///
    /// # Errors
    /// [`KaneError::Singular`] when the kept rows do not fix the dependent rates.
    pub fn rates_from_speeds<T: Scalar>(
        &self,
        split: &SpeedSplit,
        a: &[Vec<T>],
        b: &[T],
        u: &[T],
    ) -> Result<Vec<T>, KaneError> {
        let n = self.coordinates.len();
        let mut qd = vec![T::constant(0.0); n];
        for (k, i) in split.independent.iter().enumerate() {
            qd[*i] = u[k];
        }
        let rhs: Vec<T> = split
            .rows
            .iter()
            .map(|r| {
                let known = split
                    .independent
                    .iter()
                    .fold(b[*r], |acc, i| acc + a[*r][*i] * qd[*i]);
                -known
            })
            .collect();
        let ad: Vec<Vec<T>> = split
            .rows
            .iter()
            .map(|r| split.dependent.iter().map(|d| a[*r][*d]).collect())
            .collect();
        let x = solve(ad, vec![rhs]).ok_or(KaneError::Singular("the dependent rates' matrix"))?;
        for (k, d) in split.dependent.iter().enumerate() {
            qd[*d] = x[0][k];
        }
        Ok(qd)
    }

    /// Kane's reduced equations at `(q, u)`: `M_r u̇ = f_r`.
    ///
    /// # Errors
    /// [`KaneError::Singular`] when the split's rows do not fix the dependent rates here.
    pub fn reduced<T: Scalar>(
        &self,
        split: &SpeedSplit,
        q: &[T],
        u: &[T],
        t: T,
        values: &[T],
    ) -> Result<Reduced<T>, KaneError> {
        let n = q.len();
        let (a, b) = self.constraint_rows(q, t, values);
        let qd = self.rates_from_speeds(split, &a, &b, u)?;
        let tm = self.speed_matrix(split, &a)?;
        let geo = self.partials(q, &qd, t, values);
        let (jet, bias) = self.jet(q, &qd, t, values);
        // The acceleration that the constraints need when u̇ = 0.
        let zero_u = vec![T::constant(0.0); u.len()];
        let qdd = self.rates_from_speeds(split, &a, &bias, &zero_u)?;
        let qd_dir = self.dissipation_partials(q, &qd, t, values);
        let mass = self.mass_matrix(&geo);
        let mut forces = self.forces(&geo, &jet, &qd_dir);
        for (j, f) in forces.iter_mut().enumerate() {
            *f = (0..n).fold(*f, |acc, k| acc - mass[j][k] * qdd[k]);
        }
        let mt: Vec<Vec<T>> = transpose_times(&tm, &mass);
        let mass_r = (0..u.len())
            .map(|i| {
                (0..u.len())
                    .map(|k| (0..n).fold(T::constant(0.0), |acc, j| acc + mt[i][j] * tm[j][k]))
                    .collect()
            })
            .collect();
        let forcing = (0..u.len())
            .map(|i| (0..n).fold(T::constant(0.0), |acc, j| acc + tm[j][i] * forces[j]))
            .collect();
        Ok(Reduced {
            mass: mass_r,
            forcing,
            rates: qd,
            speed_matrix: tm,
            bias: qdd,
        })
    }

    /// The residuals `E_j − Q_j = (M q̈ − f)_j` of Lagrange's equations of every coordinate
    /// at `(q, q̇, q̈, t)`, without the constraints' terms: what the rows of a released
    /// system's displacements read on a given motion (reactions evaluated numerically,
    /// `reactions::numeric`).
    pub(crate) fn lagrange_residuals(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        t: f64,
        values: &[f64],
    ) -> Vec<f64> {
        let geo = self.partials(q, qd, t, values);
        let (jet, _) = self.jet(q, qd, t, values);
        let damping = self.dissipation_partials(q, qd, t, values);
        let mass = self.mass_matrix(&geo);
        let forces = self.forces(&geo, &jet, &damping);
        mass.iter()
            .zip(forces)
            .map(|(row, f)| row.iter().zip(qdd).map(|(m, a)| m * a).sum::<f64>() - f)
            .collect()
    }

    /// `T` (n×p): the rates per unit of each speed, with no constraint bias.
    fn speed_matrix<T: Scalar>(
        &self,
        split: &SpeedSplit,
        a: &[Vec<T>],
    ) -> Result<Vec<Vec<T>>, KaneError> {
        let n = self.coordinates.len();
        let p = split.independent.len();
        let zero_b = vec![T::constant(0.0); a.len()];
        let mut tm = vec![vec![T::constant(0.0); p]; n];
        for k in 0..p {
            let mut e = vec![T::constant(0.0); p];
            e[k] = T::constant(1.0);
            let col = self.rates_from_speeds(split, a, &zero_b, &e)?;
            for j in 0..n {
                tm[j][k] = col[j];
            }
        }
        Ok(tm)
    }

    /// The geometry as a Taylor series to second order in time at `q̈ = 0`
    /// (`x + ẋ ε₁ + ẋ ε₂ + ẍ ε₁ε₂`), and the constraint rows' bias `Ȧ q̇ + ḃ`.
    pub(super) fn jet<T: Scalar>(
        &self,
        q: &[T],
        qd: &[T],
        t: T,
        values: &[T],
    ) -> (Vec<Dual<Dual<T>>>, Vec<T>) {
        let z = T::constant(0.0);
        let one = T::constant(1.0);
        let tq: Vec<Dual<Dual<T>>> = q
            .iter()
            .zip(qd)
            .map(|(x, v)| Dual::new(Dual::new(*x, *v), Dual::new(*v, z)))
            .collect();
        let trate: Vec<Dual<Dual<T>>> = qd
            .iter()
            .map(|v| Dual::constant_of(Dual::constant_of(*v)))
            .collect();
        let tt = Dual::new(Dual::new(t, one), Dual::new(one, z));
        let tv: Vec<Dual<Dual<T>>> = values
            .iter()
            .map(|v| Dual::constant_of(Dual::constant_of(*v)))
            .collect();
        let jet = self.geometry.eval(&self.variables(&tq, &trate, tt, &tv));
        let mut bias = Vec::with_capacity(self.holonomic + self.velocity);
        for k in 0..self.holonomic {
            bias.push(jet[self.holonomic_at + k].eps.eps);
        }
        let dq: Vec<Dual<T>> = q.iter().zip(qd).map(|(x, v)| Dual::new(*x, *v)).collect();
        let c = self
            .rates
            .eval(&self.variables(&dq, &lift(qd), Dual::new(t, one), &lift(values)));
        bias.extend(c.iter().take(self.velocity).map(|x| x.eps));
        (jet, bias)
    }

    /// `∂D/∂q̇_j` of each dissipation function, summed, per coordinate.
    fn dissipation_partials<T: Scalar>(&self, q: &[T], qd: &[T], t: T, values: &[T]) -> Vec<T> {
        let n = q.len();
        let mut out = vec![T::constant(0.0); n];
        if self.dissipations == 0 {
            return out;
        }
        for (j, slot) in out.iter_mut().enumerate() {
            let c = self.rates.eval(&self.variables(
                &lift(q),
                &seeded(qd, j),
                Dual::constant_of(t),
                &lift(values),
            ));
            *slot = c[self.velocity..]
                .iter()
                .fold(T::constant(0.0), |acc, x| acc + x.eps);
        }
        out
    }
}

/// `x` as duals with no derivative.
pub(super) fn lift<T: Scalar>(x: &[T]) -> Vec<Dual<T>> {
    x.iter().map(|v| Dual::constant_of(*v)).collect()
}

/// `x` as duals with unit derivative in slot `j`.
pub(super) fn seeded<T: Scalar>(x: &[T], j: usize) -> Vec<Dual<T>> {
    x.iter()
        .enumerate()
        .map(|(k, v)| Dual::new(*v, T::constant(if k == j { 1.0 } else { 0.0 })))
        .collect()
}
