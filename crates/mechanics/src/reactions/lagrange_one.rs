//! Lagrange's equations of the first kind: a release's reaction from the released system's
//! residuals (compared with Newton–Euler), a constraint's generalized reaction from its
//! multipliers, and the force that drives a driven coordinate.

use cas::{Expr, Symbol};

use super::compare::{compare, worst};
use super::motion::{at_rest, residuals, Motion};
use super::newton_euler::{dot, moment_equation, moved_by, newton_euler};
use super::{Agreement, Method, Reaction, ReactionError, Release, ReleaseKind};
use crate::equations::Equations;
use crate::system::{ConstraintForm, System, Vector};

/// Checks that no constraint of the released system moves with the displacements.
pub(super) fn check_disentangled(release: &Release) -> Result<(), ReactionError> {
    let symbols: Vec<Symbol> = release
        .displacements
        .iter()
        .chain(&release.rotations)
        .flat_map(|(u, _)| [Expr::coordinate(u), Expr::rate(u, 1)])
        .filter_map(Expr::as_symbol)
        .collect();
    for c in release.system.constraints() {
        for form in &c.equations {
            let e = match form {
                ConstraintForm::Holonomic(e) | ConstraintForm::Velocity(e) => *e,
            };
            if symbols.iter().any(|s| !e.diff(*s).is_zero()) {
                return Err(ReactionError::Entangled {
                    reaction: release.name.clone(),
                    other: c.name.clone(),
                });
            }
        }
    }
    Ok(())
}

pub(super) fn release_reaction(
    original: &System,
    release: &Release,
    motion: &Motion,
) -> Result<Reaction, ReactionError> {
    check_disentangled(release)?;
    let extra: Vec<(String, Vector)> = release
        .displacements
        .iter()
        .chain(&release.rotations)
        .cloned()
        .collect();
    let zero = at_rest(&extra);
    let residuals = residuals(&release.name, &release.system, motion, &zero, &|q| {
        extra.iter().any(|(u, _)| u == q)
    })?;
    let residual_of = |name: &String| {
        residuals
            .iter()
            .find(|r| r.coordinate == *name)
            .map_or_else(Expr::zero, |r| r.on_motion)
    };
    let released_equations = residuals
        .iter()
        .map(|r| (r.coordinate.clone(), r.at_rest))
        .collect();
    let lagrange: Vec<Expr> = release
        .displacements
        .iter()
        .map(|(u, _)| residual_of(u))
        .collect();
    let turning: Vec<Expr> = release
        .rotations
        .iter()
        .map(|(psi, _)| residual_of(psi))
        .collect();
    let mut newton = newton_euler(original, release, motion, &zero);
    newton.extend(moment_equation(original, release, motion, &zero));
    let agreement = lagrange
        .iter()
        .chain(&turning)
        .zip(&newton)
        .map(|(a, b)| compare(*a, *b))
        .fold(Agreement::Exact, worst);
    let (couple, unbalanced_couple) = couples(release, &turning);
    let mut force: Vector = [Expr::zero(), Expr::zero(), Expr::zero()];
    for (r, (_, d)) in lagrange.iter().zip(&release.displacements) {
        for (k, x) in d.iter().enumerate() {
            force[k] += *r * *x;
        }
    }
    let force = force.map(Expr::normal);
    let along = match (release.kind.is_unilateral(), release.displacements.first()) {
        (true, Some((_, d))) => lagrange.first().map(|n| (*n, *d)),
        _ => release.normal.map(|n| (dot(&force, &n).normal(), n)),
    };
    let friction = release.normal.and_then(|n| {
        let (value, _) = along?;
        Some([0, 1, 2].map(|k| (force[k] - value * n[k]).normal()))
    });
    let agreement = if agreement == Agreement::Disagree && moves_others(release) {
        Agreement::Unattributed
    } else {
        agreement
    };
    let methods = if matches!(agreement, Agreement::Disagree | Agreement::Unattributed) {
        vec![Method::LagrangeI]
    } else {
        vec![Method::LagrangeI, Method::NewtonEuler]
    };
    Ok(Reaction {
        name: release.name.clone(),
        kind: Some(release.kind),
        point: Some(release.point.clone()),
        members: release.members.clone(),
        force: Some(force),
        couple,
        unbalanced_couple,
        friction,
        along,
        generalized: Vec::new(),
        multipliers: Vec::new(),
        driving: false,
        methods,
        agreement,
        released_equations,
    })
}

/// The couple at the point from the rotations' residuals: the reaction couple of a clamp, or
/// for a hinge or a rolling contact the couple the motion needs although the joint transmits
/// none (when it is not zero).
fn couples(release: &Release, turning: &[Expr]) -> (Option<Vector>, Option<Vector>) {
    let turned = (!release.rotations.is_empty()).then(|| {
        let mut couple: Vector = [Expr::zero(), Expr::zero(), Expr::zero()];
        for (c, (_, axis)) in turning.iter().zip(&release.rotations) {
            for (k, x) in axis.iter().enumerate() {
                couple[k] += *c * *x;
            }
        }
        couple.map(Expr::normal)
    });
    if release.kind == ReleaseKind::Clamp {
        (turned, None)
    } else {
        let needed = turned.filter(|c| {
            c.iter()
                .any(|x| compare(*x, Expr::zero()) == Agreement::Disagree)
        });
        (None, needed)
    }
}

pub(super) fn constraint_reaction(
    name: &str,
    without: &System,
    equations: &Equations,
    motion: &Motion,
) -> Result<Reaction, ReactionError> {
    let rows: Vec<usize> = equations
        .constraint_names()
        .iter()
        .enumerate()
        .filter(|(_, n)| *n == name)
        .map(|(k, _)| k)
        .collect();
    let (generalized, multipliers) = if rows.is_empty() {
        // Eliminated by integration: the residuals of the system without it are its
        // generalized reaction on every coordinate, the eliminated one included.
        let generalized = residuals(name, without, motion, &[], &|_| true)?
            .into_iter()
            .map(|r| (r.coordinate, r.on_motion))
            .collect();
        (generalized, Vec::new())
    } else {
        let multipliers: Vec<Expr> = rows.iter().map(|&k| motion.multipliers[k]).collect();
        let generalized = equations
            .coordinates()
            .iter()
            .enumerate()
            .map(|(j, q)| {
                let r: Expr = rows
                    .iter()
                    .map(|&k| -(equations.constraint_matrix()[k][j] * motion.multipliers[k]))
                    .sum();
                (q.clone(), r.normal())
            })
            .collect();
        (generalized, multipliers)
    };
    Ok(Reaction {
        name: name.to_string(),
        kind: None,
        point: None,
        members: Vec::new(),
        force: None,
        couple: None,
        unbalanced_couple: None,
        friction: None,
        along: None,
        generalized,
        multipliers,
        driving: false,
        methods: vec![Method::LagrangeI],
        agreement: Agreement::Single,
        released_equations: Vec::new(),
    })
}

pub(super) fn driving_force(
    name: &str,
    without: &System,
    prescribed: Expr,
    motion: &Motion,
) -> Result<Reaction, ReactionError> {
    let rate = prescribed.dt();
    let driven = [
        (Expr::coordinate(name), prescribed),
        (Expr::rate(name, 1), rate),
        (Expr::rate(name, 2), rate.dt()),
    ];
    let generalized = residuals(name, without, motion, &driven, &|q| q == name)?
        .into_iter()
        .map(|r| (r.coordinate, r.on_motion))
        .collect();
    Ok(Reaction {
        name: name.to_string(),
        kind: None,
        point: None,
        members: Vec::new(),
        force: None,
        couple: None,
        unbalanced_couple: None,
        friction: None,
        along: None,
        generalized,
        multipliers: Vec::new(),
        driving: true,
        methods: vec![Method::LagrangeI],
        agreement: Agreement::Single,
        released_equations: Vec::new(),
    })
}

/// Whether the release displaces a particle or body that is not one of its members (one
/// at the same point, or one hanging from a member): Lagrange I counts its inertia and
/// weight, the members' momentum balance does not.
fn moves_others(release: &Release) -> bool {
    let moves = moved_by(release);
    let particles = release
        .system
        .particles()
        .iter()
        .enumerate()
        .any(|(i, p)| !release.particles.contains(&i) && moves(&p.position));
    let bodies = release
        .system
        .bodies()
        .iter()
        .enumerate()
        .any(|(i, b)| !release.bodies.contains(&i) && moves(&b.centre));
    particles || bodies
}
