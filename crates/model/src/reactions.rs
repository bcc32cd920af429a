//! The reactions a model asks for, as the mechanics' [`ReactionRequest`]s: each reaction at a
//! point is the model lowered again with its bodies released (extra displacement coordinates,
//! the constraint dropped), each constraint written as an equation is the model lowered
//! without it.

use cas::Expr as Cx;
use mechanics::{ReactionRequest, Release as MRelease, ReleaseKind, Vector};

use crate::ast::ReleaseWord;
use crate::lower::{lower, lower_parts, lower_with, LowerError, Shift};
use crate::model::{
    Axis, ConstraintId, ConstraintKind, ExprKind, Model, PointId, Projection, ReactionTarget,
    ReleaseMember,
};
use crate::span::Span;

/// The displacement coordinates of reaction `name`: `name__x`, `name__y`, `name__z` (or
/// `name__n` along a direction). The double underscore keeps them apart from model names.
fn displacement_name(name: &str, axis: &str) -> String {
    format!("{name}__{axis}")
}

/// The unit vector along `n`: `n` itself when `n·n` is identically 1.
fn unit(n: Vector) -> Vector {
    let n2 = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).normal();
    if n2.equals(Cx::one()) {
        n
    } else {
        let length = n2.sqrt();
        n.map(|x| (x / length).normal())
    }
}

struct Spec<'a> {
    name: &'a str,
    /// The statement that asks for the reaction.
    span: Span,
    kind: ReleaseKind,
    point: PointId,
    members: Vec<ReleaseMember>,
    direction: Option<Vector>,
    dropped: Option<ConstraintId>,
    /// A rolling contact's normal, to split its force (the release is in every direction).
    normal: Option<Vector>,
}

fn release(model: &Model, spec: Spec<'_>) -> Result<MRelease, LowerError> {
    let inertial: [Vector; 3] = [
        [Cx::one(), Cx::zero(), Cx::zero()],
        [Cx::zero(), Cx::one(), Cx::zero()],
        [Cx::zero(), Cx::zero(), Cx::one()],
    ];
    let displacements: Vec<(String, Vector)> = match spec.direction {
        Some(n) => vec![(displacement_name(spec.name, "n"), unit(n))],
        None => ["x", "y", "z"]
            .iter()
            .zip(inertial)
            .map(|(axis, d)| (displacement_name(spec.name, axis), d))
            .collect(),
    };
    let mut displacement: Vector = [Cx::zero(), Cx::zero(), Cx::zero()];
    for (u, d) in &displacements {
        for (k, x) in d.iter().enumerate() {
            displacement[k] += Cx::coordinate(u) * *x;
        }
    }
    let point = point_position(model, spec.point)?;
    unreleased_load(model, &spec, &point)?;
    // A clamp also turns the members about the point by a small rotation ψ: its reaction
    // couple. A hinge and a rolling contact are turned too, to check that the motion needs no
    // couple there (if it does, other supports act on the members, or the joint transmits one).
    let turned = matches!(
        spec.kind,
        ReleaseKind::Clamp | ReleaseKind::Hinge | ReleaseKind::Rolling
    );
    let rotations: Vec<(String, Vector)> = if turned {
        ["rx", "ry", "rz"]
            .iter()
            .zip(inertial)
            .map(|(axis, d)| (displacement_name(spec.name, axis), d))
            .collect()
    } else {
        Vec::new()
    };
    let rotation = (!rotations.is_empty()).then(|| {
        let psi: Vector = [0, 1, 2].map(|k| Cx::coordinate(&rotations[k].0));
        (psi, point)
    });
    let mut shift = Shift {
        displacement: Some(displacement.map(Cx::normal)),
        coordinates: displacements
            .iter()
            .chain(&rotations)
            .map(|(u, _)| u.clone())
            .collect(),
        dropped: spec.dropped,
        rotation,
        ..Shift::default()
    };
    let mut particles = Vec::new();
    let mut bodies = Vec::new();
    let mut members = Vec::new();
    for member in &spec.members {
        match *member {
            ReleaseMember::Particle(index) => {
                if let Some(p) = model.particles().get(index) {
                    shift.points.push(p.point);
                    shift.particles.push(index);
                    particles.push(index);
                    members.push(model.point(p.point).name.name.clone());
                }
            }
            ReleaseMember::Body(id) => {
                let b = model.body(id);
                shift.points.push(b.centre);
                shift.bodies.push(id);
                bodies.push(id.index());
                members.push(b.name.name.clone());
            }
        }
    }
    shift
        .points
        .extend(attached_points(model, &spec.members, spec.point)?);
    let system = lower_with(model, shift)?;
    Ok(MRelease {
        name: spec.name.to_string(),
        kind: spec.kind,
        point: (model.point(spec.point).name.name.clone(), point),
        members,
        system,
        displacements,
        rotations,
        normal: spec.normal.map(unit),
        particles,
        bodies,
    })
}

/// The points fixed to the members (constant body-frame components relative to a member body's
/// centre, or at a member particle) other than the reaction's point and the points of the
/// bodies and particles that are not released: they move with the members, and so do the
/// forces and springs attached there.
fn attached_points(
    model: &Model,
    members: &[ReleaseMember],
    at: PointId,
) -> Result<Vec<PointId>, LowerError> {
    let (_, (points, frames)) = lower_parts(model, Shift::default())?;
    let position = |id: PointId| points.get(id.index()).copied().flatten();
    let mut others: Vec<PointId> = vec![at];
    for (index, p) in model.particles().iter().enumerate() {
        if !members.contains(&ReleaseMember::Particle(index)) {
            others.push(p.point);
        }
    }
    for (index, b) in model.bodies().iter().enumerate() {
        let id = crate::model::BodyId(index as u32);
        if !members.contains(&ReleaseMember::Body(id)) {
            others.push(b.centre);
        }
    }
    // Each member as (its reference position, its rotation when it is a body).
    let mut anchors: Vec<(Vector, Option<mechanics::Rotation>)> = Vec::new();
    for member in members {
        match *member {
            ReleaseMember::Particle(index) => {
                if let Some(r) = model.particles().get(index).and_then(|p| position(p.point)) {
                    anchors.push((r, None));
                }
            }
            ReleaseMember::Body(id) => {
                let b = model.body(id);
                let rotation = frames.get(b.frame.index()).copied().flatten();
                if let (Some(r), Some(rotation)) = (position(b.centre), rotation) {
                    anchors.push((r, Some(rotation)));
                }
            }
        }
    }
    let fixed = |r: &Vector| {
        anchors.iter().any(|(anchor, rotation)| {
            let d: Vector = [0, 1, 2].map(|k| r[k] - anchor[k]);
            match rotation {
                None => d.iter().all(|x| x.normal().is_zero()),
                Some(rot) => (0..3).all(|i| {
                    let component: Cx = (0..3).map(|k| rot[k][i] * d[k]).sum();
                    component.normal().dt().is_zero()
                }),
            }
        })
    };
    Ok((1..model.points().len())
        .map(|i| PointId(i as u32))
        .filter(|id| !others.contains(id))
        .filter(|id| position(*id).is_some_and(|r| fixed(&r)))
        .collect())
}

/// Refuses a release whose members are moved, other than by moving the reaction's point, by a
/// coordinate that also moves a body or particle not released (a pulley under a rope built
/// into the coordinates: `φ` turns the pulley and lowers the masses). The released members
/// then exchange a force with those through the coordinate (the rope's pull), which the
/// release does not see: it only moves the members. Moving with the point is harmless: a
/// link hinged at the point carries the bodies beyond it, and that is the force asked for.
fn unreleased_load(model: &Model, spec: &Spec<'_>, at: &Vector) -> Result<(), LowerError> {
    let (_, (points, frames)) = lower_parts(model, Shift::default())?;
    let position = |id: PointId| points.get(id.index()).copied().flatten();
    let rotation = |frame: crate::model::FrameId| frames.get(frame.index()).copied().flatten();
    // Each body or particle as (name, released, position, rotation).
    let mut items: Vec<(String, bool, Option<Vector>, Option<mechanics::Rotation>)> = Vec::new();
    for (index, p) in model.particles().iter().enumerate() {
        let released = spec.members.contains(&ReleaseMember::Particle(index));
        let name = model.point(p.point).name.name.clone();
        items.push((name, released, position(p.point), None));
    }
    for (index, b) in model.bodies().iter().enumerate() {
        let released = spec
            .members
            .contains(&ReleaseMember::Body(crate::model::BodyId(index as u32)));
        items.push((
            b.name.name.clone(),
            released,
            position(b.centre),
            rotation(b.frame),
        ));
    }
    for coordinate in model.coordinates().iter().filter(|c| c.driven.is_none()) {
        let Some(q) = Cx::coordinate(&coordinate.name.name).as_symbol() else {
            continue;
        };
        let moves = |v: &Vector| v.iter().any(|x| !x.diff(q).normal().is_zero());
        let turns = |r: &Option<mechanics::Rotation>| {
            r.is_some_and(|r| r.iter().flatten().any(|x| !x.diff(q).normal().is_zero()))
        };
        let members_move = items.iter().filter(|item| item.1).any(|item| {
            let relative = item.2.map(|r| [0, 1, 2].map(|k| r[k] - at[k]));
            relative.is_some_and(|d| moves(&d)) || turns(&item.3)
        });
        if !members_move {
            continue;
        }
        let others: Vec<String> = items
            .iter()
            .filter(|item| !item.1 && (item.2.is_some_and(|r| moves(&r)) || turns(&item.3)))
            .map(|item| item.0.clone())
            .collect();
        if !others.is_empty() {
            return Err(LowerError::UnreleasedLoad {
                span: spec.span,
                reaction: spec.name.to_owned(),
                members: items.iter().filter(|i| i.1).map(|i| i.0.clone()).collect(),
                coordinate: coordinate.name.name.clone(),
                others,
            });
        }
    }
    Ok(())
}

/// A point's position, read off the lowering of a probe force at it.
fn point_position(model: &Model, point: PointId) -> Result<Vector, LowerError> {
    let at = crate::model::Expr {
        kind: crate::model::ExprKind::Point(point),
        span: model.point(point).name.span,
        ty: crate::diagnostic::Type::Vector,
    };
    probe_vector(model, &at)
}

/// Every reaction the model asks for (`reactions …` of constraints, then `reaction NAME: …`),
/// ready for [`mechanics::reactions`]. A driven coordinate's driving force is not a reaction
/// handled here and is skipped.
///
/// # Errors
/// A [`LowerError`] when the model (or a released copy of it) cannot be lowered.
pub fn reaction_requests(model: &Model) -> Result<Vec<ReactionRequest>, LowerError> {
    let mut requests = Vec::new();
    for target in model.reactions() {
        let id = match target {
            ReactionTarget::Constraint(id) => id,
            ReactionTarget::Driven(id) => {
                let coordinate = model.coordinate(*id);
                let Some(motion) = &coordinate.driven else {
                    continue;
                };
                let without = lower_with(
                    model,
                    Shift {
                        freed: Some(*id),
                        ..Shift::default()
                    },
                )?;
                requests.push(ReactionRequest::Driven {
                    name: coordinate.name.name.clone(),
                    without,
                    motion: probe_scalar(model, motion)?,
                });
                continue;
            }
        };
        let constraint = model.constraint(*id);
        let name = constraint
            .name
            .as_ref()
            .map_or_else(|| "constraint".to_string(), |n| n.name.clone());
        match &constraint.kind {
            ConstraintKind::Rolling { body, contact } => {
                requests.push(ReactionRequest::Release(release(
                    model,
                    Spec {
                        name: &name,
                        span: constraint.span,
                        kind: ReleaseKind::Rolling,
                        point: *contact,
                        members: vec![ReleaseMember::Body(*body)],
                        direction: None,
                        dropped: Some(*id),
                        normal: None,
                    },
                )?));
            }
            _ => {
                let without = lower_with(
                    model,
                    Shift {
                        dropped: Some(*id),
                        ..Shift::default()
                    },
                )?;
                requests.push(ReactionRequest::Constraint { name, without });
            }
        }
    }
    for r in model.releases() {
        let direction = match &r.direction {
            Some(d) => {
                let n = probe_vector(model, d)?;
                let n2 = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).normal();
                if n2.is_zero() {
                    return Err(LowerError::ZeroDirection { span: d.span });
                }
                Some(n)
            }
            None => None,
        };
        let kind = match r.word {
            ReleaseWord::Hinge => ReleaseKind::Hinge,
            ReleaseWord::Contact => ReleaseKind::Contact,
            ReleaseWord::Rope => ReleaseKind::Rope,
            ReleaseWord::Clamp => ReleaseKind::Clamp,
            ReleaseWord::Rolling => ReleaseKind::Rolling,
        };
        // A rolling contact is released in every direction; its normal only splits the force.
        let (direction, normal) = if kind == ReleaseKind::Rolling {
            (None, direction)
        } else {
            (direction, None)
        };
        requests.push(ReactionRequest::Release(release(
            model,
            Spec {
                name: &r.name.name,
                span: r.name.span,
                kind,
                point: r.point,
                members: r.members.clone(),
                direction,
                dropped: r.constraint,
                normal,
            },
        )?));
    }
    Ok(requests)
}

/// The axes a reaction's force is projected on for the report (`reaction NAME: … in frame R`,
/// `… along n`): each a label and a unit vector in inertial components.
#[derive(Clone, Debug)]
pub struct ReactionProjection {
    /// The reaction's name.
    pub name: String,
    /// What the projection is on, for the report: `frame B`, `A − P`.
    pub onto: String,
    /// The axes: a label (`B.x`, or `along`) and the vector in inertial components — a
    /// frame's unit vectors, or the direction `along` as written (not normalised: its length
    /// is for the caller, who knows which parameters are positive).
    pub axes: Vec<(String, Vector)>,
}

/// The projections the model's `reaction` statements ask for, in their order.
///
/// # Errors
/// A [`LowerError`] when a direction cannot be lowered or is zero.
pub fn reaction_projections(model: &Model) -> Result<Vec<ReactionProjection>, LowerError> {
    let mut out = Vec::new();
    for r in model.releases() {
        let Some(projection) = &r.projection else {
            continue;
        };
        let (onto, axes) = match projection {
            Projection::Frame(frame) => {
                let name = model.frame(*frame).name.name.clone();
                let mut axes = Vec::new();
                for (axis, label) in [(Axis::X, "x"), (Axis::Y, "y"), (Axis::Z, "z")] {
                    let e = crate::model::Expr {
                        kind: ExprKind::UnitVector {
                            frame: *frame,
                            axis,
                        },
                        span: r.span,
                        ty: crate::diagnostic::Type::Vector,
                    };
                    axes.push((format!("{name}.{label}"), probe_vector(model, &e)?));
                }
                (format!("frame {name}"), axes)
            }
            Projection::Along(d) => (model.display(d).to_string(), along(model, d)?),
            Projection::AlongBody { body, direction } => (body.clone(), along(model, direction)?),
        };
        out.push(ReactionProjection {
            name: r.name.name.clone(),
            onto,
            axes,
        });
    }
    Ok(out)
}

/// The one axis of `… along d`: `d` lowered, not normalised.
fn along(model: &Model, d: &crate::model::Expr) -> Result<Vec<(String, Vector)>, LowerError> {
    let n = probe_vector(model, d)?;
    let n2 = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).normal();
    if n2.is_zero() {
        return Err(LowerError::ZeroDirection { span: d.span });
    }
    Ok(vec![("along".to_string(), n)])
}

/// A vector expression lowered, through a probe force whose vector it is.
fn probe_vector(model: &Model, direction: &crate::model::Expr) -> Result<Vector, LowerError> {
    let mut probe = model.clone();
    probe.loads.push(crate::model::LoadItem {
        load: crate::model::Load::Force {
            force: direction.clone(),
            point: direction.clone(),
        },
        span: direction.span,
    });
    let system = lower(&probe)?;
    match system.loads().last() {
        Some(mechanics::Load::Force { force, .. }) => Ok(force.map(Cx::normal)),
        _ => Err(LowerError::Shape {
            span: direction.span,
            expected: "vector",
        }),
    }
}

/// A scalar expression lowered, through a probe generalized-force-free potential.
fn probe_scalar(model: &Model, value: &crate::model::Expr) -> Result<Cx, LowerError> {
    let mut probe = model.clone();
    probe.loads.push(crate::model::LoadItem {
        load: crate::model::Load::Potential(value.clone()),
        span: value.span,
    });
    let system = lower(&probe)?;
    match system.loads().last() {
        Some(mechanics::Load::Potential(v)) => Ok(*v),
        _ => Err(LowerError::Shape {
            span: value.span,
            expected: "scalar",
        }),
    }
}
