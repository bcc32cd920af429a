//! Newton–Euler: the momentum (and, for a clamp, angular momentum) equation of the released
//! bodies on the constrained motion, independent of the released Lagrangian.

use cas::{Expr, Symbol};

use super::motion::Motion;
use super::Release;
use crate::equations::angular_velocity;
use crate::system::{Load, System, Vector};

pub(super) fn dot(a: &Vector, b: &Vector) -> Expr {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Whether a point moves with the release's redundant displacements (loads at such points act
/// on the released bodies).
pub(super) fn moved_by(release: &Release) -> impl Fn(&Vector) -> bool {
    let symbols: Vec<Symbol> = release
        .displacements
        .iter()
        .filter_map(|(u, _)| Expr::coordinate(u).as_symbol())
        .collect();
    move |e: &Vector| {
        e.iter()
            .any(|x| symbols.iter().any(|s| !x.diff(*s).is_zero()))
    }
}

/// Newton–Euler: `R·d_i` from the momentum equation of the released bodies.
pub(super) fn newton_euler(
    original: &System,
    release: &Release,
    motion: &Motion,
    zero: &[(Expr, Expr)],
) -> Vec<Expr> {
    let mut momentum_rate: Vector = [Expr::zero(), Expr::zero(), Expr::zero()];
    let mut weight: Vector = momentum_rate;
    let mut mass = Expr::zero();
    let mut add = |m: Expr, r: &Vector| {
        for (k, x) in r.iter().enumerate() {
            momentum_rate[k] += m * x.dt().dt();
        }
        mass += m;
    };
    for &i in &release.particles {
        if let Some(p) = original.particles().get(i) {
            add(p.mass, &p.position);
        }
    }
    for &i in &release.bodies {
        if let Some(b) = original.bodies().get(i) {
            add(b.mass, &b.centre);
        }
    }
    let moves = moved_by(release);
    let mut applied: Vector = [Expr::zero(), Expr::zero(), Expr::zero()];
    let mut potential = Expr::zero();
    let mut dissipation = Expr::zero();
    for (k, x) in release.system.gravity().iter().enumerate() {
        weight[k] += mass * *x;
    }
    for load in release.system.loads() {
        match load {
            Load::Force { force, point } if moves(point) => {
                for (k, x) in force.iter().enumerate() {
                    applied[k] += *x;
                }
            }
            Load::Potential(v) => potential += *v,
            Load::Dissipation(d) => dissipation += *d,
            _ => {}
        }
    }
    release
        .displacements
        .iter()
        .map(|(u, d)| {
            let newton: Vector = [0, 1, 2].map(|k| momentum_rate[k] - weight[k] - applied[k]);
            let r = released_balance(&newton, d, u, potential, dissipation).subs(zero);
            motion.on_motion(r)
        })
        .collect()
}

fn cross(a: &Vector, b: &Vector) -> Vector {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn minus(a: &Vector, b: &Vector) -> Vector {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Newton–Euler for a clamp: the couple `C·e_i` from the angular momentum equation of the
/// released bodies about the point `P`, `Σ (r − P) × m a + Σ Ḣ_G = Σ (r − P) × F + Σ C_applied +
/// C` (the reaction force at `P` has no moment about it), springs and dampers through
/// `∂V/∂ψ_i`, `∂D/∂ψ̇_i`.
pub(super) fn moment_equation(
    original: &System,
    release: &Release,
    motion: &Motion,
    zero: &[(Expr, Expr)],
) -> Vec<Expr> {
    if release.rotations.is_empty() {
        return Vec::new();
    }
    let pivot = release.point.1;
    let mut inertial: Vector = [Expr::zero(), Expr::zero(), Expr::zero()];
    let mut gravity_moment: Vector = inertial;
    let mut spin: Vector = inertial;
    let gravity: Vector = release.system.gravity();
    let mut add = |m: Expr, r: &Vector| {
        let arm = minus(r, &pivot);
        let a: Vector = r.map(|x| x.dt().dt());
        let ma: Vector = a.map(|x| m * x);
        let mg: Vector = gravity.map(|x| m * x);
        let (t, w) = (cross(&arm, &ma), cross(&arm, &mg));
        for k in 0..3 {
            inertial[k] += t[k];
            gravity_moment[k] += w[k];
        }
    };
    for &i in &release.particles {
        if let Some(p) = original.particles().get(i) {
            add(p.mass, &p.position);
        }
    }
    for &i in &release.bodies {
        if let Some(b) = original.bodies().get(i) {
            add(b.mass, &b.centre);
            // H_G = R I Rᵀ ω, differentiated in time.
            let r = &b.rotation;
            let w = angular_velocity(r);
            let wb: Vec<Expr> = (0..3)
                .map(|i| (0..3).map(|k| r[k][i] * w[k]).sum())
                .collect();
            let hb: Vec<Expr> = (0..3)
                .map(|i| (0..3).map(|j| b.inertia[i][j] * wb[j]).sum())
                .collect();
            for (k, total) in spin.iter_mut().enumerate() {
                let h: Expr = (0..3).map(|i| r[k][i] * hb[i]).sum();
                *total += h.normal().dt();
            }
        }
    }
    for (total, s) in inertial.iter_mut().zip(spin) {
        *total += s;
    }
    let moves = moved_by(release);
    let mut applied: Vector = [Expr::zero(), Expr::zero(), Expr::zero()];
    let mut potential = Expr::zero();
    let mut dissipation = Expr::zero();
    for load in release.system.loads() {
        match load {
            Load::Force { force, point } if moves(point) => {
                let at: Vector = point.map(|x| x.subs(zero));
                let m = cross(&minus(&at, &pivot), force);
                for k in 0..3 {
                    applied[k] += m[k];
                }
            }
            Load::Couple { moment, body } if release.bodies.contains(body) => {
                for k in 0..3 {
                    applied[k] += moment[k];
                }
            }
            Load::Potential(v) => potential += *v,
            Load::Dissipation(d) => dissipation += *d,
            _ => {}
        }
    }
    release
        .rotations
        .iter()
        .map(|(psi, axis)| {
            let euler: Vector = [0, 1, 2].map(|k| inertial[k] - gravity_moment[k] - applied[k]);
            motion.on_motion(released_balance(&euler, axis, psi, potential, dissipation).subs(zero))
        })
        .collect()
}

/// A momentum (or angular-momentum) balance of the released bodies along the direction of a
/// released coordinate, with the forces that enter through the potential and the Rayleigh
/// function of that coordinate: what the reaction must supply.
pub(super) fn released_balance(
    balance: &Vector,
    direction: &Vector,
    coordinate: &str,
    potential: Expr,
    dissipation: Expr,
) -> Expr {
    let gradient = Expr::coordinate(coordinate)
        .as_symbol()
        .map_or_else(Expr::zero, |s| potential.diff(s));
    let drag = Expr::rate(coordinate, 1)
        .as_symbol()
        .map_or_else(Expr::zero, |s| dissipation.diff(s));
    dot(balance, direction) + gradient + drag
}
