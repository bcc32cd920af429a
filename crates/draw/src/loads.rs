//! Force elements and loads: springs (zigzags, or coils when torsional), dampers, applied
//! forces and couples as arrows, gravity. A spring or damper on a coordinate is drawn where
//! that coordinate is marked: a coil at an angle's pivot, a zigzag along a displacement.

use model::ast::BinaryOp;
use model::{Connection, Expr, ExprKind, Load, Model, Type};

use crate::build::Context;
use crate::marks::{Mark, Marks};
use crate::sample::{add, cross, dot, norm, rotate, scale, sub, unit, Sampler};
use crate::scene::{ArcKind, ArrowKind, Item, P3};
use crate::DrawError;

/// Springs and dampers, with the walls they are anchored to.
///
/// # Errors
/// A value the geometry needs is missing.
pub(crate) fn elements(
    context: &Context<'_, '_>,
    marks: &Marks,
    items: &mut Vec<Item>,
) -> Result<(), DrawError> {
    let model = context.sampler.model;
    for item in model.loads() {
        let (connection, spring) = match &item.load {
            Load::Spring { connection, .. } => (connection, true),
            Load::Damper { connection, .. } => (connection, false),
            _ => continue,
        };
        match connection {
            Connection::Points { from, to } => {
                let (Some(a), Some(b)) =
                    (context.sampler.vector(from)?, context.sampler.vector(to)?)
                else {
                    continue;
                };
                let offset = if spring { 0.0 } else { 0.3 * context.block };
                element(
                    context,
                    (a, fixed(context, from)),
                    (b, fixed(context, to)),
                    spring,
                    offset,
                    items,
                );
            }
            Connection::Scalar(expr) => {
                let ExprKind::Coordinate(id) = expr.kind else {
                    continue;
                };
                let Some((_, mark)) = marks.marks.iter().find(|(k, _)| *k == id.index()) else {
                    continue;
                };
                match *mark {
                    Mark::Angle {
                        pivot,
                        normal,
                        radius,
                    } if spring => items.push(Item::Coil {
                        at: pivot,
                        normal,
                        radius: 0.6 * radius,
                    }),
                    Mark::Displacement { origin, at, along } => {
                        // Anchored where the coordinate is zero (the element's rest), or two
                        // blocks further back when that is too close to draw it.
                        let anchor = if norm(sub(at, origin)) > 2.0 * context.block {
                            origin
                        } else {
                            sub(origin, scale(2.0 * context.block, along))
                        };
                        let offset = if spring { 0.0 } else { 0.3 * context.block };
                        element(context, (anchor, true), (at, false), spring, offset, items);
                    }
                    Mark::Angle { .. } => {}
                }
            }
        }
    }
    Ok(())
}

/// Whether an end of an element is a fixed point (it gets a wall).
fn fixed(context: &Context<'_, '_>, end: &Expr) -> bool {
    match end.kind {
        ExprKind::Point(id) => context.fixed[id.index()],
        _ => false,
    }
}

/// A spring or damper from `a` to `b`, ended at a block's side rather than its centre,
/// shifted sideways by `offset` (a damper beside a spring), with a wall at a fixed end.
fn element(
    context: &Context<'_, '_>,
    (a, a_fixed): (P3, bool),
    (b, b_fixed): (P3, bool),
    spring: bool,
    offset: f64,
    items: &mut Vec<Item>,
) {
    let Some(d) = unit(sub(b, a)) else { return };
    let side = unit(cross(context.plane.unwrap_or([0.0, 0.0, 1.0]), d)).unwrap_or([0.0; 3]);
    let shift = scale(offset, side);
    let trim = |p: P3, towards: P3| {
        let on_block = context
            .sliders
            .iter()
            .any(|(i, _)| norm(sub(context.here.points[*i], p)) < 1e-9 * (1.0 + context.size));
        if on_block {
            add(p, scale(0.5 * context.block, towards))
        } else {
            p
        }
    };
    let a2 = add(trim(a, d), shift);
    let b2 = add(trim(b, scale(-1.0, d)), shift);
    for (end, fixed, into) in [(a2, a_fixed, d), (b2, b_fixed, scale(-1.0, d))] {
        if fixed {
            items.push(Item::Wall {
                at: end,
                normal: into,
            });
        }
    }
    items.push(if spring {
        Item::Spring { a: a2, b: b2 }
    } else {
        Item::Damper { a: a2, b: b2 }
    });
}

/// Applied forces, couples and gravity.
///
/// # Errors
/// A value the geometry needs is missing.
pub(crate) fn forces(context: &Context<'_, '_>, items: &mut Vec<Item>) -> Result<(), DrawError> {
    let model = context.sampler.model;
    // A force whose inputs are zero now still has a direction: that with every input at 1.
    let unit_inputs = with_unit_inputs(model);
    let probe = match &unit_inputs {
        Some(m) => Sampler::new(m, context.sampler.at.clone()).ok(),
        None => None,
    };
    let direction = |e: &Expr| -> Result<Option<P3>, DrawError> {
        let v = context.sampler.vector(e)?.and_then(unit);
        match (v, &probe) {
            (Some(v), _) => Ok(Some(v)),
            (None, Some(p)) => Ok(p.vector(e)?.and_then(unit)),
            (None, None) => Ok(None),
        }
    };
    let length = 0.25 * context.size;
    for item in model.loads() {
        match &item.load {
            Load::Force { force, point } => {
                let (Some(p), Some(d)) = (context.sampler.vector(point)?, direction(force)?) else {
                    continue;
                };
                items.push(Item::Arrow {
                    kind: ArrowKind::Force(label(model, force)),
                    from: p,
                    to: add(p, scale(length, d)),
                });
            }
            Load::Couple { moment, body } => {
                let Some(n) = direction(moment)? else {
                    continue;
                };
                let g = context.here.points[model.body(*body).centre.index()];
                couple(context, g, n, label(model, moment), items);
            }
            Load::Gravity(g) => {
                if let Some(d) = context.sampler.vector(g)?.and_then(unit) {
                    items.push(Item::Gravity {
                        direction: d,
                        label: label(model, g),
                    });
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// A couple about `n` at `g`: three quarters of a circle, its head turning the positive way.
fn couple(context: &Context<'_, '_>, g: P3, n: P3, label: String, items: &mut Vec<Item>) {
    let seed = if dot(n, [1.0, 0.0, 0.0]).abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let Some(start) = unit(cross(n, seed)) else {
        return;
    };
    let radius = 0.12 * context.size;
    let steps = 36;
    let points = (0..=steps)
        .map(|j| {
            let turn = 1.5 * std::f64::consts::PI * j as f64 / steps as f64;
            add(g, scale(radius, rotate(start, n, turn)))
        })
        .collect();
    items.push(Item::Arc {
        kind: ArcKind::Couple(label),
        points,
    });
}

/// The model with every input at 1, when it has inputs.
fn with_unit_inputs(model: &Model) -> Option<Model> {
    let inputs: Vec<(String, f64)> = model
        .inputs()
        .iter()
        .map(|i| (i.name.name.clone(), 1.0))
        .collect();
    if inputs.is_empty() {
        return None;
    }
    model.with_overrides(&inputs).ok()
}

/// A force's label: its magnitude as written (`F` of `F*N.x`, `g` of `-g*N.y`).
fn label(model: &Model, e: &Expr) -> String {
    let text = match &e.kind {
        ExprKind::Neg(inner) => return label(model, inner),
        ExprKind::Binary {
            op: BinaryOp::Mul,
            lhs,
            rhs,
        } if lhs.ty == Type::Scalar && rhs.ty == Type::Vector => model.display(lhs).to_string(),
        ExprKind::Binary {
            op: BinaryOp::Mul,
            lhs,
            rhs,
        } if lhs.ty == Type::Vector && rhs.ty == Type::Scalar => model.display(rhs).to_string(),
        _ => model.display(e).to_string(),
    };
    crate::names::text(text.trim_start_matches('-').trim())
}
