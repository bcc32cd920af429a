//! The independent numeric route: a generated model's frames as plain rotation matrices and
//! its points as sums of their unit vectors, evaluated with dual numbers. Velocities are the
//! directional derivatives of positions along `(q̇, 1)` in `(q, t)`, angular velocities come
//! from `ω× = Ṙ Rᵀ`, and `T`, `V`, the dissipation `D` and the power `P` of the forces and
//! couples follow. Lagrange's equations `M q̈ = f` are then formed from exact derivatives of
//! `L = T − V` (hyper-dual numbers):
//! `M_jk = ∂²L/∂q̇_j∂q̇_k`, `f_j = ∂L/∂q_j − Σ_k ∂²L/∂q̇_j∂q_k q̇_k − ∂²L/∂q̇_j∂t + Q_j`,
//! `Q_j = ∂(P − D)/∂q̇_j` (forces and couples here do not depend on the rates).

use super::dual::{hyper, Dual, Scalar};
use super::model::{Env, Load, Mass, Model, Term};

type Vec3<S> = [S; 3];
type Mat3<S> = [[S; 3]; 3];

fn rotation<S: Scalar>(angle: S, axis: usize) -> Mat3<S> {
    let (c, s, o, z) = (angle.cos(), angle.sin(), S::c(1.0), S::c(0.0));
    match axis {
        0 => [[o, z, z], [z, c, -s], [z, s, c]],
        1 => [[c, z, s], [z, o, z], [-s, z, c]],
        _ => [[c, -s, z], [s, c, z], [z, z, o]],
    }
}

fn matmul<S: Scalar>(a: &Mat3<S>, b: &Mat3<S>) -> Mat3<S> {
    let mut r = [[S::c(0.0); 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    r
}

fn dot<S: Scalar>(a: &Vec3<S>, b: &Vec3<S>) -> S {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Frames (columns: the frame's unit vectors in `N`) and points (positions in `N`).
struct Geometry<S> {
    frames: Vec<Mat3<S>>,
    points: Vec<Vec3<S>>,
}

fn vector<S: Scalar>(terms: &[Term], frames: &[Mat3<S>], env: &Env<'_, S>) -> Vec3<S> {
    let mut v = [S::c(0.0); 3];
    for term in terms {
        let c = term.coefficient.eval(env);
        let r = &frames[term.frame];
        for (k, x) in v.iter_mut().enumerate() {
            *x = *x + c * r[k][term.axis.index()];
        }
    }
    v
}

fn geometry<S: Scalar>(m: &Model, env: &Env<'_, S>) -> Geometry<S> {
    let (o, z) = (S::c(1.0), S::c(0.0));
    let mut frames: Vec<Mat3<S>> = Vec::with_capacity(m.frames.len());
    for (i, f) in m.frames.iter().enumerate() {
        let mut r = if i == 0 {
            [[o, z, z], [z, o, z], [z, z, o]]
        } else {
            frames[f.parent]
        };
        for (angle, axis) in &f.rotations {
            r = matmul(&r, &rotation(angle.eval(env), axis.index()));
        }
        frames.push(r);
    }
    let mut points: Vec<Vec3<S>> = Vec::with_capacity(m.points.len());
    for p in &m.points {
        let base = p.base.map_or([z, z, z], |b| points[b]);
        let v = vector(&p.terms, &frames, env);
        points.push([base[0] + v[0], base[1] + v[1], base[2] + v[2]]);
    }
    Geometry { frames, points }
}

/// `T`, `V`, `D` and `P` at `(q, q̇, t)`.
pub struct Energies<S> {
    pub kinetic: S,
    pub potential: S,
    pub dissipation: S,
    pub power: S,
}

/// The inertial angular velocity of a frame given with its rate `R + Ṙ ε`.
fn omega<S: Scalar>(r: &Mat3<Dual<S>>) -> Vec3<S> {
    // W = Ṙ Rᵀ is skew: ω = (W₃₂, W₁₃, W₂₁).
    let w = |i: usize, j: usize| (0..3).fold(S::c(0.0), |a, k| a + r[i][k].d * r[j][k].v);
    [w(2, 1), w(0, 2), w(1, 0)]
}

fn value<S: Scalar>(v: &Vec3<Dual<S>>) -> Vec3<S> {
    v.map(|x| x.v)
}

fn rate<S: Scalar>(v: &Vec3<Dual<S>>) -> Vec3<S> {
    v.map(|x| x.d)
}

fn point<S: Scalar>(g: &Geometry<Dual<S>>, p: Option<usize>) -> Vec3<Dual<S>> {
    p.map_or([Dual::c(0.0); 3], |p| g.points[p])
}

/// The energies of `m` at `(q, q̇, t)`.
pub fn energies<S: Scalar>(m: &Model, params: &[f64], q: &[S], qd: &[S], t: S) -> Energies<S> {
    let lifted: Vec<Dual<S>> = q.iter().zip(qd).map(|(x, v)| Dual::new(*x, *v)).collect();
    let env = Env {
        params,
        q: &lifted,
        t: Dual::new(t, S::c(1.0)),
        driven: &m.driven,
    };
    let g = geometry(m, &env);
    let mut e = Energies {
        kinetic: S::c(0.0),
        potential: S::c(0.0),
        dissipation: S::c(0.0),
        power: S::c(0.0),
    };
    let half = S::c(0.5);
    let gravity: Vec3<S> = m
        .loads
        .iter()
        .find_map(|l| match l {
            Load::Gravity(terms) => Some(value(&vector(terms, &g.frames, &env))),
            _ => None,
        })
        .unwrap_or([S::c(0.0); 3]);
    for mass in &m.masses {
        let (point, mass_value) = match mass {
            Mass::Particle { point, mass } => (*point, mass.eval(&env).v),
            Mass::Body { point, mass, .. } => (*point, mass.eval(&env).v),
        };
        let r = g.points[point];
        let v = rate(&r);
        e.kinetic = e.kinetic + half * mass_value * dot(&v, &v);
        e.potential = e.potential - mass_value * dot(&gravity, &value(&r));
        if let Mass::Body { frame, inertia, .. } = mass {
            let rot = &g.frames[*frame];
            let w = omega(rot);
            // ω in the body's axes: Rᵀ ω.
            let wb: Vec3<S> =
                [0, 1, 2].map(|i| (0..3).fold(S::c(0.0), |a, k| a + rot[k][i].v * w[k]));
            for i in 0..3 {
                for j in 0..3 {
                    e.kinetic = e.kinetic + half * wb[i] * S::c(inertia[i][j]) * wb[j];
                }
            }
        }
    }
    for load in &m.loads {
        load_energies(m, load, &g, &env, &mut e);
    }
    e
}

fn load_energies<S: Scalar>(
    m: &Model,
    load: &Load,
    g: &Geometry<Dual<S>>,
    env: &Env<'_, Dual<S>>,
    e: &mut Energies<S>,
) {
    let half = S::c(0.5);
    let between = |from: Option<usize>, to: usize| {
        let (a, b) = (point(g, from), point(g, Some(to)));
        [0, 1, 2].map(|k| b[k] - a[k])
    };
    match load {
        Load::Gravity(_) => {}
        Load::Spring { k, from, to, rest } => {
            let d = value(&between(*from, *to));
            let k = k.eval(env).v;
            let stretch = match rest {
                Some(r) => dot(&d, &d).sqrt() - r.eval(env).v,
                None => dot(&d, &d).sqrt(),
            };
            e.potential = e.potential + half * k * stretch * stretch;
        }
        Load::Torsion { k, on, rest } => {
            let s = on.eval(env).v - rest.as_ref().map_or(S::c(0.0), |r| r.eval(env).v);
            e.potential = e.potential + half * k.eval(env).v * s * s;
        }
        Load::Damper { c, from, to } => {
            let d = between(*from, *to);
            let (x, v) = (value(&d), rate(&d));
            let along = dot(&x, &v) / dot(&x, &x).sqrt();
            e.dissipation = e.dissipation + half * c.eval(env).v * along * along;
        }
        Load::DamperOn { c, on } => {
            let v = on.eval(env).d;
            e.dissipation = e.dissipation + half * c.eval(env).v * v * v;
        }
        Load::Force { terms, at } => {
            let f = value(&vector(terms, &g.frames, env));
            e.power = e.power + dot(&f, &rate(&g.points[*at]));
        }
        Load::Couple { terms, body } => {
            let Mass::Body { frame, .. } = &m.masses[*body] else {
                return;
            };
            let c = value(&vector(terms, &g.frames, env));
            e.power = e.power + dot(&c, &omega(&g.frames[*frame]));
        }
    }
}

/// Lagrange's equations at a state, from the numeric route.
pub struct Numeric {
    pub mass: Vec<Vec<f64>>,
    pub forcing: Vec<f64>,
    /// `p_j = ∂L/∂q̇_j`.
    pub momenta: Vec<f64>,
    /// `T + V`.
    pub energy: f64,
    /// `Σ q̇_j p_j − L`.
    pub jacobi: f64,
}

/// `M`, `f`, the momenta and the energies of `m` at `(q, q̇, t)`.
pub fn equations(m: &Model, params: &[f64], q: &[f64], qd: &[f64], t: f64) -> Numeric {
    let n = q.len();
    let mut mass = vec![vec![0.0; n]; n];
    let mut forcing = vec![0.0; n];
    let mut momenta = vec![0.0; n];
    for j in 0..n {
        // Outer ε along q̇_j; inner ε along z = q_0…q_{n−1}, q̇_0…q̇_{n−1}, t.
        for z in 0..=2 * n {
            let unit = |i: usize| if i == z { 1.0 } else { 0.0 };
            let qh: Vec<_> = (0..n).map(|i| hyper(q[i], 0.0, unit(i))).collect();
            let qdh: Vec<_> = (0..n)
                .map(|i| hyper(qd[i], if i == j { 1.0 } else { 0.0 }, unit(n + i)))
                .collect();
            let th = hyper(t, 0.0, unit(2 * n));
            let e = energies(m, params, &qh, &qdh, th);
            let lagrangian = e.kinetic - e.potential;
            let mixed = lagrangian.d.d;
            if z == 0 {
                momenta[j] = lagrangian.d.v;
                forcing[j] += (e.power - e.dissipation).d.v;
            }
            if z == j {
                forcing[j] += lagrangian.v.d;
            }
            if z < n {
                forcing[j] -= mixed * qd[z];
            } else if z < 2 * n {
                mass[j][z - n] = mixed;
            } else {
                forcing[j] -= mixed;
            }
        }
    }
    let e = energies(m, params, q, qd, t);
    let lagrangian = e.kinetic - e.potential;
    let jacobi = qd.iter().zip(&momenta).map(|(v, p)| v * p).sum::<f64>() - lagrangian;
    Numeric {
        mass,
        forcing,
        momenta,
        energy: e.kinetic + e.potential,
        jacobi,
    }
}

/// `x` with `a x = b` (Gaussian elimination, partial pivoting); `None` when singular.
pub fn solve(a: &[Vec<f64>], b: &[f64]) -> Option<Vec<f64>> {
    let n = b.len();
    let mut m: Vec<Vec<f64>> = a
        .iter()
        .zip(b)
        .map(|(r, x)| [r.clone(), vec![*x]].concat())
        .collect();
    for col in 0..n {
        let pivot = (col..n).max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))?;
        if m[pivot][col] == 0.0 {
            return None;
        }
        m.swap(col, pivot);
        let pivot_row = m[col].clone();
        for row in m.iter_mut().skip(col + 1) {
            let factor = row[col] / pivot_row[col];
            for (x, p) in row.iter_mut().zip(&pivot_row).skip(col) {
                *x -= factor * p;
            }
        }
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n).map(|k| m[i][k] * x[k]).sum();
        x[i] = (m[i][n] - s) / m[i][i];
    }
    Some(x)
}

/// `‖A‖∞ ‖A⁻¹‖∞`, infinite when singular.
pub fn condition(a: &[Vec<f64>]) -> f64 {
    let n = a.len();
    let norm = |rows: &[Vec<f64>]| {
        rows.iter()
            .map(|r| r.iter().map(|x| x.abs()).sum::<f64>())
            .fold(0.0, f64::max)
    };
    let mut inverse = vec![vec![0.0; n]; n];
    for k in 0..n {
        let e: Vec<f64> = (0..n).map(|i| if i == k { 1.0 } else { 0.0 }).collect();
        let Some(col) = solve(a, &e) else {
            return f64::INFINITY;
        };
        for (row, x) in inverse.iter_mut().zip(col) {
            row[k] = x;
        }
    }
    norm(a) * norm(&inverse)
}
