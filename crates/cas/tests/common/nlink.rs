//! The planar n-link pendulum (point masses on massless rods, absolute angles from the
//! downward vertical), built with the symbolic core alone: the workload of the core's
//! benchmark and the closed form that checks it.
//!
//! ```text
//!   ─┬─ pivot
//!     \ l1, θ1
//!      ● m1
//!      |  l2, θ2
//!      ● m2 …
//! ```

#![allow(dead_code)] // Each including target uses part of it.

use cas::Expr;

/// The symbols of an n-link pendulum.
pub struct NLink {
    pub angles: Vec<Expr>,
    pub rates: Vec<Expr>,
    pub accelerations: Vec<Expr>,
    pub masses: Vec<Expr>,
    pub lengths: Vec<Expr>,
    pub gravity: Expr,
}

impl NLink {
    pub fn new(n: usize) -> NLink {
        NLink::with_prefix(n, "")
    }

    /// The same system with every name prefixed (so that repeated runs share nothing).
    pub fn with_prefix(n: usize, p: &str) -> NLink {
        NLink {
            angles: (1..=n)
                .map(|i| Expr::coordinate(&format!("{p}theta{i}")))
                .collect(),
            rates: (1..=n)
                .map(|i| Expr::rate(&format!("{p}theta{i}"), 1))
                .collect(),
            accelerations: (1..=n)
                .map(|i| Expr::rate(&format!("{p}theta{i}"), 2))
                .collect(),
            masses: (1..=n).map(|i| Expr::symbol(&format!("{p}m{i}"))).collect(),
            lengths: (1..=n).map(|i| Expr::symbol(&format!("{p}l{i}"))).collect(),
            gravity: Expr::symbol(&format!("{p}g")),
        }
    }

    /// Kinetic energy K and potential energy V.
    pub fn energies(&self) -> (Expr, Expr) {
        let half = Expr::rational(1, 2).expect("2 is not zero");
        let (mut x, mut y) = (Expr::zero(), Expr::zero());
        let mut kinetic = Vec::new();
        let mut potential = Vec::new();
        for k in 0..self.angles.len() {
            x += self.lengths[k] * self.angles[k].sin();
            y -= self.lengths[k] * self.angles[k].cos();
            let (vx, vy) = (x.dt(), y.dt());
            kinetic.push(half * self.masses[k] * (vx.powi(2) + vy.powi(2)));
            potential.push(self.masses[k] * self.gravity * y);
        }
        (
            Expr::add_all(kinetic).normal(),
            Expr::add_all(potential).normal(),
        )
    }

    /// Lagrange's equations `M θ̈ = f`: the mass matrix (rows) and the forcing, in normal form.
    pub fn equations(&self) -> (Vec<Vec<Expr>>, Vec<Expr>) {
        let (kinetic, potential) = self.energies();
        let lagrangian = (kinetic - potential).normal();
        let mut mass = Vec::new();
        let mut forcing = Vec::new();
        for i in 0..self.angles.len() {
            let momentum = lagrangian.diff(self.rates[i].as_symbol().expect("a rate is a symbol"));
            let equation = momentum.dt()
                - lagrangian.diff(self.angles[i].as_symbol().expect("an angle is a symbol"));
            let (row, rest) = equation
                .affine_coefficients(&self.accelerations)
                .expect("Lagrange's equations are affine in the accelerations");
            mass.push(row);
            forcing.push((-rest).normal());
        }
        (mass, forcing)
    }

    /// The closed form: `M_ij = μ_ij l_i l_j cos(θ_i − θ_j)`,
    /// `f_i = −Σ_j μ_ij l_i l_j sin(θ_i − θ_j) θ̇_j² − μ_ii g l_i sin θ_i`, with
    /// `μ_ij = Σ_{k ≥ max(i,j)} m_k`.
    /// [`NLink::equations`] with the intermediate results kept as working forms
    /// (`cas::NormalForm`), as the mechanics crate derives them: only `M` and `f` become trees.
    pub fn equations_on_working_forms(&self) -> (Vec<Vec<Expr>>, Vec<Expr>) {
        let (kinetic, potential) = self.energies();
        let lagrangian = (kinetic - potential).normal().normal_form();
        let mut mass = Vec::new();
        let mut forcing = Vec::new();
        for i in 0..self.angles.len() {
            let momentum = lagrangian.diff(self.rates[i].as_symbol().expect("a rate is a symbol"));
            let equation = momentum
                .dt()
                .sub(&lagrangian.diff(self.angles[i].as_symbol().expect("an angle is a symbol")));
            let (row, rest) = equation
                .affine_coefficients(&self.accelerations)
                .expect("Lagrange's equations are affine in the accelerations");
            mass.push(row.iter().map(cas::NormalForm::to_expr).collect());
            forcing.push(rest.neg().to_expr());
        }
        (mass, forcing)
    }

    pub fn closed_form(&self) -> (Vec<Vec<Expr>>, Vec<Expr>) {
        let n = self.angles.len();
        let mu = |i: usize, j: usize| Expr::add_all(self.masses[i.max(j)..].iter().copied());
        let mass = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        mu(i, j)
                            * self.lengths[i]
                            * self.lengths[j]
                            * (self.angles[i] - self.angles[j]).cos()
                    })
                    .collect()
            })
            .collect();
        let forcing = (0..n)
            .map(|i| {
                let coupling: Expr = (0..n)
                    .map(|j| {
                        mu(i, j)
                            * self.lengths[i]
                            * self.lengths[j]
                            * (self.angles[i] - self.angles[j]).sin()
                            * self.rates[j].powi(2)
                    })
                    .sum();
                -coupling - mu(i, i) * self.gravity * self.lengths[i] * self.angles[i].sin()
            })
            .collect();
        (mass, forcing)
    }
}
