//! Each generalized coordinate marked as a textbook does. A coordinate is an *angle* of a
//! segment of the drawing (a link, a rod, a disk's radius line) when turning the coordinate
//! turns that segment at unit rate about a pivot that stays put: it is drawn as an arc from
//! the segment's direction at zero (a dashed reference line) to its direction now. It is a
//! *displacement* of a point when moving the coordinate by Δ moves the point by Δ·u along
//! one fixed direction: it is drawn as an arrow from where the point is at zero. Both are
//! read off the model by differentiating its geometry, whatever the coordinate is called.

use model::{Axis, ExprKind};

use crate::build::{translates, Context, Shape};
use crate::sample::{add, cross, dot, norm, rotate, scale, sub, unit};
use crate::scene::{ArcKind, ArrowKind, Item, P3};
use crate::DrawError;

/// How a coordinate is shown.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Mark {
    /// An angle about `pivot`, turning about `normal`; `radius` of its arc.
    Angle { pivot: P3, normal: P3, radius: f64 },
    /// A displacement of a point from `origin` along the unit vector `along`.
    Displacement { origin: P3, at: P3, along: P3 },
}

/// The marks' items, and the mark of each coordinate (by index) that has one.
pub(crate) struct Marks {
    pub items: Vec<Item>,
    pub marks: Vec<(usize, Mark)>,
}

/// A segment that may turn with a coordinate: its pivot, unit direction, length, and the
/// derivatives of both with respect to the coordinate.
struct Segment {
    pivot: P3,
    direction: P3,
    length: f64,
    pivot_rate: P3,
    direction_rate: P3,
}

/// Marks every free coordinate that some element of the drawing shows; returns the names of
/// the others.
///
/// # Errors
/// A value the geometry needs is missing.
pub(crate) fn coordinates(context: &Context<'_, '_>) -> Result<(Marks, Vec<String>), DrawError> {
    let model = context.sampler.model;
    let mut marks = Marks {
        items: Vec::new(),
        marks: Vec::new(),
    };
    let mut unmarked = Vec::new();
    for (k, coordinate) in model.coordinates().iter().enumerate() {
        if context.rates[k].is_none() {
            continue;
        }
        let name = crate::names::symbol(&coordinate.name.name);
        let q = context.sampler.at.coordinates[k];
        let segments = segments(context, k);
        let fixed = segments.iter().find(|s| turns(s) && still(s));
        let moving = segments.iter().find(|s| turns(s));
        // A spatial system's angle without a fixed pivot is clearer as its frame's rotation;
        // a planar one's at the moving end of what it turns (a ladder's foot).
        let rotation = match (fixed, context.plane) {
            (None, None) => frame_rotation(context, k)?,
            _ => None,
        };
        let mark = if let Some(s) = fixed.or(if rotation.is_some() { None } else { moving }) {
            Some(angle(context, s, q, &name, &mut marks.items))
        } else if let Some((n, zero)) = rotation {
            Some(frame_angle(context, n, zero, q, &name, &mut marks.items))
        } else if let Some((i, u)) = displaced(context, k)? {
            Some(displacement(context, i, u, q, &name, &mut marks.items))
        } else if let Some((n, zero)) = frame_rotation(context, k)? {
            Some(frame_angle(context, n, zero, q, &name, &mut marks.items))
        } else {
            None
        };
        match mark {
            Some(mark) => marks.marks.push((k, mark)),
            None => unmarked.push(coordinate.name.name.clone()),
        }
    }
    Ok((marks, unmarked))
}

/// Whether the segment turns at unit rate with the coordinate.
fn turns(s: &Segment) -> bool {
    (norm(s.direction_rate) - 1.0).abs() < 1e-4
}

/// Whether the segment's pivot stays put as the coordinate changes (then the arc is drawn
/// about a fixed point; a ladder's angle has none and is drawn at a moving end).
fn still(s: &Segment) -> bool {
    norm(s.pivot_rate) < 1e-6 * (1.0 + s.length)
}

/// The segments of the drawing, links first, then rods, then disks' and blocks' axes.
fn segments(context: &Context<'_, '_>, k: usize) -> Vec<Segment> {
    let Some(rates) = &context.rates[k] else {
        return Vec::new();
    };
    let here = &context.here;
    let mut segments = Vec::new();
    for &(a, b) in &context.links {
        let r = sub(here.points[b], here.points[a]);
        let (length, Some(d)) = (norm(r), unit(r)) else {
            continue;
        };
        let v = sub(rates.points[b], rates.points[a]);
        segments.push(Segment {
            pivot: here.points[a],
            direction: d,
            length,
            pivot_rate: rates.points[a],
            direction_rate: scale(1.0 / length, sub(v, scale(dot(v, d), d))),
        });
    }
    let model = context.sampler.model;
    for (b, shape) in context.shapes.iter().enumerate() {
        let body = &model.bodies()[b];
        let (f, c) = (body.frame.index(), body.centre.index());
        let axes = here.frames[f];
        let axis_rates = rates.frames[f];
        match shape {
            Shape::Rod { a, b: e, points } => {
                let Some(d) = unit(sub(*e, *a)) else { continue };
                let axis =
                    (0..3).max_by(|&i, &j| dot(axes[i], d).abs().total_cmp(&dot(axes[j], d).abs()));
                let Some(axis) = axis else { continue };
                let sign = dot(axes[axis], d).signum();
                let length = norm(sub(*e, *a));
                // Pivot: a point of the rod that stays put; the rod points away from it.
                for &p in points {
                    let pivot = here.points[p];
                    let (to_a, to_e) = (norm(sub(*a, pivot)), norm(sub(*e, pivot)));
                    let direction = if to_e >= to_a { d } else { scale(-1.0, d) };
                    let s = if to_e >= to_a { sign } else { -sign };
                    segments.push(Segment {
                        pivot,
                        direction,
                        length: to_a.max(to_e).max(0.5 * length),
                        pivot_rate: rates.points[p],
                        direction_rate: scale(s, axis_rates[axis]),
                    });
                }
            }
            Shape::Disk {
                radius,
                axis,
                shaft,
                ..
            } => {
                if let Some(p) = *shaft {
                    let r = sub(here.points[c], here.points[p]);
                    if let (length, Some(d)) = (norm(r), unit(r)) {
                        let v = sub(rates.points[c], rates.points[p]);
                        segments.push(Segment {
                            pivot: here.points[p],
                            direction: d,
                            length,
                            pivot_rate: rates.points[p],
                            direction_rate: scale(1.0 / length, sub(v, scale(dot(v, d), d))),
                        });
                    }
                }
                segments.push(Segment {
                    pivot: here.points[c],
                    direction: axes[*axis],
                    length: *radius,
                    pivot_rate: rates.points[c],
                    direction_rate: axis_rates[*axis],
                });
            }
            Shape::Block { size, .. } => segments.push(Segment {
                pivot: here.points[c],
                direction: axes[0],
                length: *size,
                pivot_rate: rates.points[c],
                direction_rate: axis_rates[0],
            }),
        }
    }
    segments
}

fn angle(
    context: &Context<'_, '_>,
    s: &Segment,
    q: f64,
    name: &str,
    items: &mut Vec<Item>,
) -> Mark {
    let normal = unit(cross(s.direction, s.direction_rate)).unwrap_or([0.0, 0.0, 1.0]);
    // An angle of several turns is shown by its part within one turn, with its sign.
    let q = q % std::f64::consts::TAU;
    let zero = rotate(s.direction, normal, -q);
    let radius = (0.4 * s.length).clamp(0.05 * context.size, 0.25 * context.size);
    items.push(Item::Reference {
        a: s.pivot,
        b: add(s.pivot, scale(1.3 * radius.max(0.6 * s.length), zero)),
    });
    // A fixed number of points, so that the frames of an animation share their markup.
    let steps = 24;
    let points = (0..=steps)
        .map(|j| {
            let turn = q * j as f64 / steps as f64;
            add(s.pivot, scale(radius, rotate(zero, normal, turn)))
        })
        .collect();
    items.push(Item::Arc {
        kind: ArcKind::Coordinate(name.to_owned()),
        points,
    });
    Mark::Angle {
        pivot: s.pivot,
        normal,
        radius,
    }
}

/// The point coordinate `k` displaces along a fixed line: a particle if one is, else a body's
/// centre, else any named point; the one that fewest other coordinates move.
fn displaced(context: &Context<'_, '_>, k: usize) -> Result<Option<(usize, P3)>, DrawError> {
    let model = context.sampler.model;
    let Some(rates) = &context.rates[k] else {
        return Ok(None);
    };
    let particles = model.particles().iter().map(|p| p.point.index());
    let centres = model.bodies().iter().map(|b| b.centre.index());
    let order: Vec<usize> = particles
        .chain(centres)
        .chain(0..context.here.points.len())
        .collect();
    let mut best: Option<(usize, usize, P3)> = None;
    for (rank, &i) in order.iter().enumerate() {
        let u = rates.points[i];
        if norm(u) < 1e-6 || !translates(context, i, k, u)? {
            continue;
        }
        let others = context
            .rates
            .iter()
            .enumerate()
            .filter(|(j, r)| *j != k && r.as_ref().is_some_and(|r| norm(r.points[i]) > 1e-6))
            .count();
        if best.is_none_or(|(o, _, _)| others < o) {
            best = Some((others, rank, u));
        }
    }
    Ok(best.map(|(_, rank, u)| (order[rank], u)))
}

fn displacement(
    context: &Context<'_, '_>,
    i: usize,
    u: P3,
    q: f64,
    name: &str,
    items: &mut Vec<Item>,
) -> Mark {
    let at = context.here.points[i];
    let origin = sub(at, scale(q, u));
    let along = unit(u).unwrap_or([1.0, 0.0, 0.0]);
    let up = scale(-1.0, context.down);
    // Above a horizontal motion; beside a vertical one, on the outer side of the system (the
    // left mass's arrow on its left), so that it does not run over the rest.
    let side = unit(sub(up, scale(dot(up, along), along)))
        .or_else(|| {
            let across = unit(cross(context.plane.unwrap_or([0.0, 0.0, 1.0]), along))?;
            let points = &context.here.points;
            let centre = scale(
                1.0 / points.len().max(1) as f64,
                points.iter().fold([0.0; 3], |a, p| add(a, *p)),
            );
            let outward = dot(across, sub(at, centre));
            Some(if outward < 0.0 {
                scale(-1.0, across)
            } else {
                across
            })
        })
        .unwrap_or([0.0, 1.0, 0.0]);
    let offset = scale(1.1 * context.block, side);
    let tail = add(origin, offset);
    let travel = norm(sub(at, origin));
    let head = if travel < 0.4 * context.block {
        // At its zero the coordinate is shown by its positive sense.
        add(tail, scale(1.5 * context.block, along))
    } else {
        add(at, offset)
    };
    items.push(Item::Reference {
        a: origin,
        b: add(origin, scale(1.3, offset)),
    });
    items.push(Item::Reference {
        a: add(at, scale(0.5 * context.block, side)),
        b: add(at, scale(1.3, offset)),
    });
    items.push(Item::Arrow {
        kind: ArrowKind::Coordinate(name.to_owned()),
        from: tail,
        to: head,
    });
    Mark::Displacement { origin, at, along }
}

/// A coordinate that is the angle of an elementary rotation in a frame's chain
/// (`frame T = N rotated theta about z`): the rotation's axis, and the axis it turns from.
fn frame_rotation(context: &Context<'_, '_>, k: usize) -> Result<Option<(P3, P3)>, DrawError> {
    let model = context.sampler.model;
    for frame in model.frames() {
        let Some((parent, rotations)) = &frame.rotation else {
            continue;
        };
        let mut axes = context.here.frames[parent.index()];
        for rotation in rotations {
            let index = match rotation.axis {
                Axis::X => 0,
                Axis::Y => 1,
                Axis::Z => 2,
            };
            let n = axes[index];
            if names_coordinate(&rotation.angle, k) {
                // The axis a textbook measures from: x about z and y, z about x.
                let from = [2, 0, 0][index];
                return Ok(Some((n, axes[from])));
            }
            let angle = context.sampler.scalar(&rotation.angle)?.unwrap_or(0.0);
            axes = axes.map(|a| rotate(a, n, angle));
        }
    }
    Ok(None)
}

/// Whether `expr` is coordinate `k` or its negative.
fn names_coordinate(expr: &model::Expr, k: usize) -> bool {
    match &expr.kind {
        ExprKind::Coordinate(id) => id.index() == k,
        ExprKind::Neg(inner) => names_coordinate(inner, k),
        _ => false,
    }
}

/// The angle of a frame's rotation, at the origin: an arc about `n` from the axis `zero` it
/// turns from to where that axis is now, both drawn dashed.
fn frame_angle(
    context: &Context<'_, '_>,
    n: P3,
    zero: P3,
    q: f64,
    name: &str,
    items: &mut Vec<Item>,
) -> Mark {
    let q = q % std::f64::consts::TAU;
    let pivot = [0.0; 3];
    let radius = 0.3 * context.size;
    let now = rotate(zero, n, q);
    for d in [zero, now] {
        items.push(Item::Reference {
            a: pivot,
            b: scale(1.5 * radius, d),
        });
    }
    let steps = 24;
    let points = (0..=steps)
        .map(|j| scale(radius, rotate(zero, n, q * j as f64 / steps as f64)))
        .collect();
    items.push(Item::Arc {
        kind: ArcKind::Coordinate(name.to_owned()),
        points,
    });
    Mark::Angle {
        pivot,
        normal: n,
        radius,
    }
}
