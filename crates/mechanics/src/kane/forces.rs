//! The generalized mass matrix and forces per coordinate (before the reduction to speeds):
//! `M_jk = Σ m J_j·J_k + Ω_j·I Ω_k` and `E_j = F_j + F*_j` at `q̈ = 0`, where `J_j = ∂r/∂q_j`
//! and `Ω_j` are the partial velocities and partial angular velocities.

use super::dynamics::{KaneSystem, LoadSlot, Partials, BODY, PARTICLE};
use super::scalar::{Dual, Scalar};

type V3<T> = [T; 3];

fn dot<T: Scalar>(a: &V3<T>, b: &V3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross<T: Scalar>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn v3<T: Copy>(x: &[T], at: usize) -> V3<T> {
    [x[at], x[at + 1], x[at + 2]]
}

fn mat<T: Copy>(x: &[T], at: usize) -> [[T; 3]; 3] {
    [v3(x, at), v3(x, at + 3), v3(x, at + 6)]
}

/// `vee((d Rᵀ − R dᵀ)/2)`: the angular vector of the rotation rate `d` of `r`.
fn angular<T: Scalar>(d: &[[T; 3]; 3], r: &[[T; 3]; 3]) -> V3<T> {
    let w = |i: usize, j: usize| (0..3).fold(T::constant(0.0), |acc, k| acc + d[i][k] * r[j][k]);
    let half = T::constant(0.5);
    [
        (w(2, 1) - w(1, 2)) * half,
        (w(0, 2) - w(2, 0)) * half,
        (w(1, 0) - w(0, 1)) * half,
    ]
}

/// `R I Rᵀ x`: the inertia in inertial axes applied to `x`.
fn inertia_times<T: Scalar>(r: &[[T; 3]; 3], inertia: &[[T; 3]; 3], x: &V3<T>) -> V3<T> {
    let body: V3<T> = [0, 1, 2].map(|i| (0..3).fold(T::constant(0.0), |a, k| a + r[k][i] * x[k]));
    let turned: V3<T> =
        [0, 1, 2].map(|i| (0..3).fold(T::constant(0.0), |a, k| a + inertia[i][k] * body[k]));
    [0, 1, 2].map(|i| (0..3).fold(T::constant(0.0), |a, k| a + r[i][k] * turned[k]))
}

impl KaneSystem {
    /// Body `b`'s partial angular velocity along coordinate `j`.
    fn omega_partial<T: Scalar>(&self, geo: &Partials<T>, b: usize, j: usize) -> V3<T> {
        let o = b * BODY + 4;
        angular(&mat(&geo.by_coordinate[j], o), &mat(&geo.value, o))
    }

    /// The generalized mass matrix `M` (n×n).
    pub(super) fn mass_matrix<T: Scalar>(&self, geo: &Partials<T>) -> Vec<Vec<T>> {
        let n = geo.by_coordinate.len();
        let zero = T::constant(0.0);
        let mut m = vec![vec![zero; n]; n];
        for b in 0..self.bodies {
            let o = b * BODY;
            let (mass, r, inertia) = (
                geo.value[o],
                mat(&geo.value, o + 4),
                mat(&geo.value, o + 13),
            );
            let jv: Vec<V3<T>> = (0..n).map(|j| v3(&geo.by_coordinate[j], o + 1)).collect();
            let om: Vec<V3<T>> = (0..n).map(|j| self.omega_partial(geo, b, j)).collect();
            let iom: Vec<V3<T>> = om.iter().map(|w| inertia_times(&r, &inertia, w)).collect();
            for j in 0..n {
                for k in 0..n {
                    m[j][k] = m[j][k] + mass * dot(&jv[j], &jv[k]) + dot(&om[j], &iom[k]);
                }
            }
        }
        for p in 0..self.particles {
            let o = self.bodies * BODY + p * PARTICLE;
            let mass = geo.value[o];
            let jv: Vec<V3<T>> = (0..n).map(|j| v3(&geo.by_coordinate[j], o + 1)).collect();
            for j in 0..n {
                for k in 0..n {
                    m[j][k] = m[j][k] + mass * dot(&jv[j], &jv[k]);
                }
            }
        }
        m
    }

    /// `E_j = F_j + F*_j` with the accelerations of the jet (`q̈ = 0`), less the damping
    /// `∂D/∂q̇_j` given per coordinate.
    pub(super) fn forces<T: Scalar>(
        &self,
        geo: &Partials<T>,
        jet: &[Dual<Dual<T>>],
        damping: &[T],
    ) -> Vec<T> {
        let n = geo.by_coordinate.len();
        let g = v3(&geo.value, self.gravity);
        let mut e: Vec<T> = damping.iter().map(|d| -*d).collect();
        for b in 0..self.bodies {
            let o = b * BODY;
            let (mass, r, inertia) = (
                geo.value[o],
                mat(&geo.value, o + 4),
                mat(&geo.value, o + 13),
            );
            let acc: V3<T> = [0, 1, 2].map(|i| jet[o + 1 + i].eps.eps);
            let rd = [0, 1, 2].map(|i| [0, 1, 2].map(|k| jet[o + 4 + 3 * i + k].re.eps));
            let rdd = [0, 1, 2].map(|i| [0, 1, 2].map(|k| jet[o + 4 + 3 * i + k].eps.eps));
            let (w, alpha) = (angular(&rd, &r), angular(&rdd, &r));
            let iw = inertia_times(&r, &inertia, &w);
            let ia = inertia_times(&r, &inertia, &alpha);
            let gyro = cross(&w, &iw);
            let moment: V3<T> = [0, 1, 2].map(|i| ia[i] + gyro[i]);
            let net: V3<T> = [0, 1, 2].map(|i| mass * (g[i] - acc[i]));
            for (j, ej) in e.iter_mut().enumerate() {
                let jv = v3(&geo.by_coordinate[j], o + 1);
                let om = self.omega_partial(geo, b, j);
                *ej = *ej + dot(&net, &jv) - dot(&moment, &om);
            }
        }
        for p in 0..self.particles {
            let o = self.bodies * BODY + p * PARTICLE;
            let mass = geo.value[o];
            let net: V3<T> = [0, 1, 2].map(|i| mass * (g[i] - jet[o + 1 + i].eps.eps));
            for (j, ej) in e.iter_mut().enumerate() {
                *ej = *ej + dot(&net, &v3(&geo.by_coordinate[j], o + 1));
            }
        }
        for (j, ej) in e.iter_mut().enumerate().take(n) {
            *ej = *ej + self.load_force(geo, j);
        }
        e
    }

    /// The loads' generalized force on coordinate `j`.
    fn load_force<T: Scalar>(&self, geo: &Partials<T>, j: usize) -> T {
        let d = &geo.by_coordinate[j];
        self.loads.iter().fold(T::constant(0.0), |acc, load| {
            acc + match load {
                LoadSlot::Force(o) => dot(&v3(&geo.value, *o), &v3(d, o + 3)),
                LoadSlot::Couple(o, b) => dot(&v3(&geo.value, *o), &self.omega_partial(geo, *b, j)),
                LoadSlot::Generalized(o, c) if *c == j => geo.value[*o],
                LoadSlot::Generalized(..) => T::constant(0.0),
                LoadSlot::Potential(o) => -d[*o],
            }
        })
    }
}

impl KaneSystem {
    /// The energy `T + V` at `(q, q̇, t)`: the bodies' and particles' kinetic energy
    /// `½ m v·v + ½ ω·(R I Rᵀ) ω`, gravity's potential `−m g·r` and the loads' potentials.
    /// Forces that have no potential do work on it, so it is conserved only without them.
    pub fn energy(&self, q: &[f64], qd: &[f64], t: f64, values: &[f64]) -> f64 {
        let (jet, _) = self.jet(q, qd, t, values);
        let value: Vec<f64> = jet.iter().map(|x| x.re.re).collect();
        let rate: Vec<f64> = jet.iter().map(|x| x.re.eps).collect();
        let g = v3(&value, self.gravity);
        let mut energy = 0.0;
        for b in 0..self.bodies {
            let o = b * BODY;
            let (mass, r, inertia) = (value[o], mat(&value, o + 4), mat(&value, o + 13));
            let v = v3(&rate, o + 1);
            let w = angular(&mat(&rate, o + 4), &r);
            let iw = inertia_times(&r, &inertia, &w);
            energy +=
                0.5 * mass * dot(&v, &v) + 0.5 * dot(&w, &iw) - mass * dot(&g, &v3(&value, o + 1));
        }
        for p in 0..self.particles {
            let o = self.bodies * BODY + p * PARTICLE;
            let v = v3(&rate, o + 1);
            energy += value[o] * (0.5 * dot(&v, &v) - dot(&g, &v3(&value, o + 1)));
        }
        for load in &self.loads {
            if let LoadSlot::Potential(o) = load {
                energy += value[*o];
            }
        }
        energy
    }
}
