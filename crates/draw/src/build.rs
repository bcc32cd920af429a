//! The model at a configuration → a [`Scene`]: what is fixed, what each body looks like,
//! which points are joined by rigid links, which masses slide. Everything is decided from the
//! model's own geometry by evaluating it at the configuration and at nearby ones (a link is a
//! pair of points whose distance never changes; a body's points are those that keep their
//! body-frame coordinates); nothing depends on the names a model happens to use.

use model::ast::{BinaryOp, ReleaseWord};
use model::{ConstraintKind, ExprKind, Load};

use crate::sample::{add, cross, dot, norm, scale, sub, unit, Sampler, Snapshot};
use crate::scene::{Item, Scene, P3};
use crate::DrawError;

/// How far coordinates are moved to tell what is fixed or rigid.
const SHAKE: f64 = 0.5;
/// Step of the central differences.
const STEP: f64 = 1e-4;

/// What the builder knows about the system once it has looked at it.
pub(crate) struct Context<'s, 'm> {
    pub sampler: &'s Sampler<'m>,
    pub here: Snapshot,
    /// Per point: it does not move with any coordinate or with time.
    pub fixed: Vec<bool>,
    /// The system's extent (metres).
    pub size: f64,
    /// The side of a block (a cart, a sliding mass).
    pub block: f64,
    /// Lengths below this are zero.
    pub eps: f64,
    /// The unit vector towards the ground on the page.
    pub down: P3,
    /// The normal of the plane of a planar system.
    pub plane: Option<P3>,
    /// Per coordinate: the derivatives of every point and frame (`None` for driven ones).
    pub rates: Vec<Option<Snapshot>>,
    /// The shapes of the bodies, by body index.
    pub shapes: Vec<Shape>,
    /// Rigid links between named points (point indices), base first.
    pub links: Vec<(usize, usize)>,
    /// Particles drawn as blocks: point index and the unit vector they slide along.
    pub sliders: Vec<(usize, P3)>,
}

/// How a body is drawn.
#[derive(Clone, Debug)]
pub(crate) enum Shape {
    /// A slender rod from `a` to `b`; `points` are the named points the body carries.
    Rod { a: P3, b: P3, points: Vec<usize> },
    /// A disk of `radius` about the body's centre, normal `normal`, with an optional shaft to
    /// a point on its axis; `axis` is the body axis its radius line follows.
    Disk {
        normal: P3,
        radius: f64,
        marker: P3,
        shaft: Option<usize>,
        axis: usize,
    },
    /// A block (a plate with no axis of symmetry).
    Block { along: P3, size: f64 },
}

/// Builds the scene of `sampler`'s model at its configuration; `size`, when given, is the
/// system's extent that symbols scale with (an animation keeps its first frame's).
///
/// # Errors
/// A value the geometry needs is missing.
pub(crate) fn scene(
    sampler: &Sampler<'_>,
    size: Option<f64>,
) -> Result<(Scene, Option<P3>), DrawError> {
    let context = look(sampler, size)?;
    let mut items = Vec::new();
    if context.plane.is_none() {
        axes(&context, &mut items);
    }
    structure(&context, &mut items);
    let (marks, unmarked) = crate::marks::coordinates(&context)?;
    crate::loads::elements(&context, &marks, &mut items)?;
    items.extend(marks.items);
    crate::loads::forces(&context, &mut items)?;
    labels(&context, &mut items);
    let scene = Scene {
        items,
        size: context.size,
        unmarked,
    };
    Ok((scene, context.plane))
}

/// The inertial frame's axes at the origin, for a spatial system.
fn axes(context: &Context<'_, '_>, items: &mut Vec<Item>) {
    let model = context.sampler.model;
    let frame = model
        .inertial_frame()
        .map(|f| model.frame(f).name.name.clone());
    for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
        let mut to = [0.0; 3];
        to[k] = 0.45 * context.size;
        let name = match &frame {
            Some(f) => format!("{f}.{axis}"),
            None => axis.to_owned(),
        };
        items.push(Item::Arrow {
            kind: crate::scene::ArrowKind::Axis(name),
            from: [0.0; 3],
            to,
        });
    }
}

fn look<'s, 'm>(
    sampler: &'s Sampler<'m>,
    given_size: Option<f64>,
) -> Result<Context<'s, 'm>, DrawError> {
    let model = sampler.model;
    let here = sampler.here()?;
    let shaken = [sampler.shaken(SHAKE)?, sampler.shaken(-0.8 * SHAKE)?];
    let size = extent(&here.points, &shaken);
    let eps = 1e-9 * size.max(1.0);
    let fixed = (0..here.points.len())
        .map(|i| {
            shaken
                .iter()
                .all(|s| norm(sub(s.points[i], here.points[i])) < eps)
        })
        .collect();
    let plane = plane_of(&here, &shaken, eps);
    let gravity = gravity(sampler)?;
    let down = gravity.unwrap_or(match plane {
        Some(n) if n[2].abs() < 0.5 => [0.0, 0.0, -1.0],
        Some(_) => [0.0, -1.0, 0.0],
        None => [0.0, 0.0, -1.0],
    });
    let mut rates = Vec::new();
    for (k, c) in model.coordinates().iter().enumerate() {
        rates.push(match c.driven {
            Some(_) => None,
            None => Some(derivative(
                &sampler.moved(k, STEP)?,
                &sampler.moved(k, -STEP)?,
            )),
        });
    }
    let mut context = Context {
        sampler,
        here,
        fixed,
        size,
        block: 0.12 * size,
        eps,
        down,
        plane,
        rates,
        shapes: Vec::new(),
        links: Vec::new(),
        sliders: Vec::new(),
    };
    context.shapes = shapes(&context, &shaken)?;
    context.size = given_size.unwrap_or_else(|| context.size.max(rims(&context)));
    context.block = 0.12 * context.size;
    context.links = links(&context, &shaken);
    context.sliders = sliders(&context)?;
    context.block = block(&context);
    Ok(context)
}

/// The diagonal of the box around every point, here and moved (1 when they all coincide).
fn extent(here: &[P3], shaken: &[Snapshot]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in here
        .iter()
        .chain(shaken.iter().flat_map(|s| s.points.iter()))
    {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let d = norm(sub(hi, lo));
    if d.is_finite() && d > 1e-9 {
        d
    } else {
        1.0
    }
}

/// The diagonal of the box around the points and the disks' rims.
fn rims(context: &Context<'_, '_>) -> f64 {
    let model = context.sampler.model;
    let mut extra = Vec::new();
    for (b, shape) in context.shapes.iter().enumerate() {
        if let Shape::Disk { radius, .. } = shape {
            let g = context.here.points[model.bodies()[b].centre.index()];
            for k in 0..3 {
                let mut d = [0.0; 3];
                d[k] = *radius;
                extra.extend([add(g, d), sub(g, d)]);
            }
        }
    }
    extra.extend(context.here.points.iter().copied());
    extent(&extra, &[])
}

/// A block's side: an eighth of the system, less where sliding masses sit close together.
fn block(context: &Context<'_, '_>) -> f64 {
    let mut side = 0.12 * context.size;
    for (k, (i, _)) in context.sliders.iter().enumerate() {
        for (j, _) in &context.sliders[k + 1..] {
            let d = norm(sub(context.here.points[*i], context.here.points[*j]));
            if d > 1e3 * context.eps {
                side = side.min(0.8 * d);
            }
        }
    }
    side
}

/// The normal of the coordinate plane every point stays in, if there is one.
fn plane_of(here: &Snapshot, shaken: &[Snapshot], eps: f64) -> Option<P3> {
    let flat = |k: usize| {
        here.points
            .iter()
            .chain(shaken.iter().flat_map(|s| s.points.iter()))
            .all(|p| p[k].abs() < 1e3 * eps)
    };
    [2, 1, 0].into_iter().find(|&k| flat(k)).map(|k| {
        let mut n = [0.0; 3];
        n[k] = 1.0;
        n
    })
}

fn gravity(sampler: &Sampler<'_>) -> Result<Option<P3>, DrawError> {
    for item in sampler.model.loads() {
        if let Load::Gravity(g) = &item.load {
            if let Some(v) = sampler.vector(g)? {
                return Ok(unit(v));
            }
        }
    }
    Ok(None)
}

fn derivative(plus: &Snapshot, minus: &Snapshot) -> Snapshot {
    let d = |a: P3, b: P3| scale(0.5 / STEP, sub(a, b));
    Snapshot {
        points: plus
            .points
            .iter()
            .zip(&minus.points)
            .map(|(a, b)| d(*a, *b))
            .collect(),
        frames: plus
            .frames
            .iter()
            .zip(&minus.frames)
            .map(|(a, b)| [d(a[0], b[0]), d(a[1], b[1]), d(a[2], b[2])])
            .collect(),
    }
}

/// The moments of inertia of body `b` about its centre, in body axes, and its mass.
fn moments(sampler: &Sampler<'_>, here: &Snapshot, b: usize) -> Result<([f64; 3], f64), DrawError> {
    let body = &sampler.model.bodies()[b];
    let mass = sampler.scalar(&body.mass)?.unwrap_or(0.0);
    let mut i = [0.0; 3];
    for (k, slot) in i.iter_mut().enumerate() {
        if let Some(e) = &body.inertia.components[k] {
            *slot = sampler.scalar(e)?.unwrap_or(0.0);
        }
    }
    if body.inertia.about != body.centre {
        // Parallel axes: I_G = I_P − m (|r|² − r_k²) on the diagonal, r = G − P in body axes.
        let axes = here.frames[body.frame.index()];
        let r = sub(
            here.points[body.centre.index()],
            here.points[body.inertia.about.index()],
        );
        let local = axes.map(|a| dot(a, r));
        let r2 = dot(r, r);
        for k in 0..3 {
            i[k] -= mass * (r2 - local[k] * local[k]);
        }
    }
    Ok((i.map(|x| x.max(0.0)), mass))
}

/// The points that keep their coordinates in body `b`'s frame (it carries them).
fn carried(
    context_here: &Snapshot,
    shaken: &[Snapshot],
    frame: usize,
    centre: usize,
    eps: f64,
) -> Vec<usize> {
    let local = |s: &Snapshot, i: usize| {
        let r = sub(s.points[i], s.points[centre]);
        s.frames[frame].map(|a| dot(a, r))
    };
    (0..context_here.points.len())
        .filter(|&i| {
            let l = local(context_here, i);
            shaken.iter().all(|s| norm(sub(local(s, i), l)) < 1e3 * eps)
        })
        .collect()
}

fn shapes(context: &Context<'_, '_>, shaken: &[Snapshot]) -> Result<Vec<Shape>, DrawError> {
    let model = context.sampler.model;
    let mut shapes = Vec::new();
    for (b, body) in model.bodies().iter().enumerate() {
        let here = &context.here;
        let centre = body.centre.index();
        let frame = body.frame.index();
        let g = here.points[centre];
        let axes = here.frames[frame];
        let points = carried(here, shaken, frame, centre, context.eps);
        let (moments, mass) = moments(context.sampler, here, b)?;
        let biggest = moments.iter().copied().fold(0.0, f64::max);
        let slender = (0..3)
            .filter(|&k| moments[k] <= 1e-9 * biggest.max(1e-300))
            .collect::<Vec<_>>();
        let far = points
            .iter()
            .copied()
            .max_by(|&i, &j| norm(sub(here.points[i], g)).total_cmp(&norm(sub(here.points[j], g))))
            .filter(|&i| norm(sub(here.points[i], g)) > context.eps);
        let line = far.and_then(|i| unit(sub(here.points[i], g)));
        let collinear = |d: P3| {
            points
                .iter()
                .all(|&i| norm(cross(sub(here.points[i], g), d)) < 1e3 * context.eps)
        };
        // A slender rod: a body axis about which it has no inertia, and its points on it.
        let rod_axis = slender.iter().copied().find(|&k| match line {
            Some(d) => dot(d, axes[k]).abs() > 1.0 - 1e-9 && collinear(d),
            None => true,
        });
        let shape = if let (Some(k), true) = (rod_axis, mass > 0.0 || far.is_some()) {
            rod(here, g, axes[k], &points, moments, mass)
        } else {
            round(context, b, &points, moments, mass)?
        };
        shapes.push(shape);
    }
    Ok(shapes)
}

fn rod(here: &Snapshot, g: P3, d: P3, points: &[usize], moments: [f64; 3], mass: f64) -> Shape {
    // A uniform rod about its centre: I = m L²/12, so its half-length is √(3 I / m).
    let i = moments.iter().copied().fold(0.0, f64::max);
    let half = if mass > 0.0 {
        (3.0 * i / mass).sqrt()
    } else {
        0.0
    };
    let along: Vec<f64> = points
        .iter()
        .map(|&p| dot(sub(here.points[p], g), d))
        .collect();
    let lo = along.iter().copied().fold(-half, f64::min);
    let hi = along.iter().copied().fold(half, f64::max);
    Shape::Rod {
        a: add(g, scale(lo, d)),
        b: add(g, scale(hi, d)),
        points: points.to_vec(),
    }
}

/// A body with an axis of symmetry (a disk, a gear, a top), or without one (a block).
fn round(
    context: &Context<'_, '_>,
    b: usize,
    points: &[usize],
    moments: [f64; 3],
    mass: f64,
) -> Result<Shape, DrawError> {
    let model = context.sampler.model;
    let body = &model.bodies()[b];
    let here = &context.here;
    let g = here.points[body.centre.index()];
    let axes = here.frames[body.frame.index()];
    let close = |a: f64, c: f64| (a - c).abs() <= 1e-6 * a.abs().max(c.abs());
    let symmetric = (0..3).find(|&k| {
        let (o1, o2) = (moments[(k + 1) % 3], moments[(k + 2) % 3]);
        close(o1, o2) && !close(moments[k], o1)
    });
    let symmetric = symmetric.or_else(|| {
        // A planar system: the axis normal to the plane.
        let n = context.plane?;
        (0..3).find(|&k| {
            dot(axes[k], n).abs() > 1.0 - 1e-9 && !close(moments[k], moments[(k + 1) % 3])
        })
    });
    let Some(k) = symmetric else {
        // No axis of symmetry: a square plate, I = m a²/6 about its normal.
        let i = moments.iter().copied().fold(0.0, f64::max);
        let size = if mass > 0.0 {
            (6.0 * i / mass).sqrt()
        } else {
            context.block
        };
        return Ok(Shape::Block {
            along: axes[0],
            size: size.min(context.size).max(0.2 * context.block),
        });
    };
    let normal = axes[k];
    let radius = radius(context, b, points, normal, moments[k], mass)?;
    let side = (k + 1) % 3;
    let shaft = points
        .iter()
        .copied()
        .filter(|&i| {
            let r = sub(here.points[i], g);
            norm(r) > context.eps && norm(cross(r, normal)) < 1e-6 * norm(r)
        })
        .max_by(|&i, &j| norm(sub(here.points[i], g)).total_cmp(&norm(sub(here.points[j], g))));
    Ok(Shape::Disk {
        normal,
        radius,
        marker: add(g, scale(radius, axes[side])),
        shaft,
        axis: side,
    })
}

/// A disk's radius: to its rolling contact, else to the farthest point it carries off its
/// axis, else that of a uniform disk with its polar moment (`I = m R² / 2`).
fn radius(
    context: &Context<'_, '_>,
    b: usize,
    points: &[usize],
    normal: P3,
    polar: f64,
    mass: f64,
) -> Result<f64, DrawError> {
    let model = context.sampler.model;
    let here = &context.here;
    let g = here.points[model.bodies()[b].centre.index()];
    for c in model.constraints() {
        if let ConstraintKind::Rolling { body, contact } = &c.kind {
            if body.index() == b {
                let r = norm(sub(here.points[contact.index()], g));
                if r > context.eps {
                    return Ok(r);
                }
            }
        }
    }
    if let Some(r) = meshing(context, b)? {
        return Ok(r);
    }
    let off_axis = |i: usize| {
        let r = sub(here.points[i], g);
        norm(sub(r, scale(dot(r, normal), normal)))
    };
    let rim = points.iter().map(|&i| off_axis(i)).fold(0.0, f64::max);
    if rim > context.eps {
        return Ok(rim);
    }
    if mass > 0.0 && polar > 0.0 {
        return Ok((2.0 * polar / mass).sqrt());
    }
    Ok(0.5 * context.block)
}

/// The coordinate body `b` turns with (the first its frame depends on), if its centre is fixed.
fn turning(context: &Context<'_, '_>, b: usize) -> Option<usize> {
    let body = &context.sampler.model.bodies()[b];
    if !context.fixed[body.centre.index()] {
        return None;
    }
    context.rates.iter().position(|r| {
        r.as_ref()
            .is_some_and(|r| r.frames[body.frame.index()].iter().any(|a| norm(*a) > 1e-6))
    })
}

/// The pitch radius of a gear on a fixed axle that meshes with another (`gear q1 to q2 ratio
/// r`): the radii add up to the distance between the axles, and `r = R₁ / R₂`.
fn meshing(context: &Context<'_, '_>, b: usize) -> Result<Option<f64>, DrawError> {
    let model = context.sampler.model;
    let Some(mine) = turning(context, b) else {
        return Ok(None);
    };
    for c in model.constraints() {
        let ConstraintKind::Gear {
            driver,
            driven,
            ratio,
        } = &c.kind
        else {
            continue;
        };
        let (me_driver, other) = if driver.index() == mine {
            (true, driven.index())
        } else if driven.index() == mine {
            (false, driver.index())
        } else {
            continue;
        };
        let partner =
            (0..model.bodies().len()).find(|&o| o != b && turning(context, o) == Some(other));
        let (Some(o), Some(r)) = (partner, context.sampler.scalar(ratio)?) else {
            continue;
        };
        let r = r.abs();
        let here = &context.here;
        let d = norm(sub(
            here.points[model.bodies()[o].centre.index()],
            here.points[model.bodies()[b].centre.index()],
        ));
        if d > context.eps && r > 0.0 {
            return Ok(Some(if me_driver {
                d * r / (1.0 + r)
            } else {
                d / (1.0 + r)
            }));
        }
    }
    Ok(None)
}

/// The point an expression of a point's position starts from: `A` in `A + l*sin(θ)*N.x`,
/// `origin` when it names none.
fn base(expr: &model::Expr) -> usize {
    match &expr.kind {
        ExprKind::Point(id) => id.index(),
        ExprKind::Binary {
            op: BinaryOp::Add | BinaryOp::Sub,
            lhs,
            ..
        } => base(lhs),
        _ => 0,
    }
}

/// Rigid links: a point defined from another one at a distance that never changes, unless a
/// body already draws both.
fn links(context: &Context<'_, '_>, shaken: &[Snapshot]) -> Vec<(usize, usize)> {
    let model = context.sampler.model;
    let here = &context.here;
    let mut links = Vec::new();
    for (i, point) in model.points().iter().enumerate() {
        let Some(expr) = &point.position else {
            continue;
        };
        let a = base(expr);
        let d = norm(sub(here.points[i], here.points[a]));
        let rigid = shaken
            .iter()
            .all(|s| (norm(sub(s.points[i], s.points[a])) - d).abs() < 1e3 * context.eps);
        if a == i || d < 1e3 * context.eps || !rigid || (context.fixed[a] && context.fixed[i]) {
            continue;
        }
        if context
            .shapes
            .iter()
            .enumerate()
            .any(|(b, s)| drawn_by(context, b, s, a, i))
        {
            continue;
        }
        links.push((a, i));
    }
    links
}

/// Whether shape `s` of body `b` already shows the segment from point `a` to point `i`.
fn drawn_by(context: &Context<'_, '_>, b: usize, s: &Shape, a: usize, i: usize) -> bool {
    let here = &context.here;
    let centre = context.sampler.model.bodies()[b].centre.index();
    match s {
        Shape::Rod { points, .. } => points.contains(&a) && points.contains(&i),
        Shape::Disk { radius, shaft, .. } => {
            let on_rim = |c: usize, p: usize| {
                c == centre
                    && (norm(sub(here.points[p], here.points[c])) - radius).abs() < 1e-6 * radius
            };
            on_rim(a, i)
                || on_rim(i, a)
                || (*shaft == Some(i) && a == centre)
                || (*shaft == Some(a) && i == centre)
        }
        Shape::Block { .. } => false,
    }
}

/// Particles that move along one fixed line as one coordinate changes, and with nothing else:
/// carts and sliding or hanging masses, drawn as blocks.
fn sliders(context: &Context<'_, '_>) -> Result<Vec<(usize, P3)>, DrawError> {
    let model = context.sampler.model;
    let mut sliders = Vec::new();
    for particle in model.particles() {
        let i = particle.point.index();
        let moving: Vec<(usize, P3)> = context
            .rates
            .iter()
            .enumerate()
            .filter_map(|(k, r)| Some((k, r.as_ref()?.points[i])))
            .filter(|(_, u)| norm(*u) > 1e-6)
            .collect();
        let [(k, u)] = moving[..] else { continue };
        if translates(context, i, k, u)? {
            if let Some(u) = unit(u) {
                sliders.push((i, u));
            }
        }
    }
    Ok(sliders)
}

/// Whether point `i` moves by exactly `Δ u` when coordinate `k` moves by `Δ`.
pub(crate) fn translates(
    context: &Context<'_, '_>,
    i: usize,
    k: usize,
    u: P3,
) -> Result<bool, DrawError> {
    let delta = 0.3;
    let moved = context.sampler.moved(k, delta)?;
    let expected = add(context.here.points[i], scale(delta, u));
    Ok(norm(sub(moved.points[i], expected)) < 1e-6 * (1.0 + context.size))
}

/// The rods, bodies, blocks, particles, hinges and supports.
fn structure(context: &Context<'_, '_>, items: &mut Vec<Item>) {
    let model = context.sampler.model;
    let here = &context.here;
    let mut rods: Vec<(P3, P3)> = Vec::new();
    for &(a, b) in &context.links {
        if slides_on(context, a, b) {
            items.push(Item::Sphere {
                centre: here.points[a],
                radius: norm(sub(here.points[b], here.points[a])),
            });
        } else {
            rods.push((here.points[a], here.points[b]));
        }
    }
    let mut centres = Vec::new();
    for (b, shape) in context.shapes.iter().enumerate() {
        let g = here.points[model.bodies()[b].centre.index()];
        match shape {
            Shape::Rod { a, b: e, .. } => rods.push((*a, *e)),
            Shape::Disk { shaft, .. } => {
                centres.push(g);
                if let Some(s) = shaft {
                    rods.push((here.points[*s], g));
                }
            }
            Shape::Block { .. } => {}
        }
    }
    surfaces(context, items);
    tracks(context, items);
    let joints = joints(context, &rods, &centres);
    bodies(context, items);
    for (at, _) in joints.iter().filter(|(_, fixed)| *fixed) {
        items.push(Item::Support {
            at: *at,
            down: context.down,
        });
    }
    for (a, b) in rods {
        items.push(Item::Rod { a, b });
    }
    for particle in model.particles() {
        let i = particle.point.index();
        let name = model.points()[i].name.name.clone();
        match context.sliders.iter().find(|(p, _)| *p == i) {
            Some((_, along)) => items.push(Item::Block {
                name,
                centre: here.points[i],
                along: *along,
                size: context.block,
            }),
            None => items.push(Item::Particle {
                name,
                at: here.points[i],
            }),
        }
    }
    for (at, _) in joints {
        items.push(Item::Hinge { at });
    }
}

/// Whether point `i`, at a fixed distance from the fixed point `a`, is in contact along that
/// line (`reaction …: contact P on … normal n` with n along `a`→`i`): it slides on a fixed
/// sphere about `a` rather than hanging from a rod.
fn slides_on(context: &Context<'_, '_>, a: usize, i: usize) -> bool {
    let here = &context.here;
    let Some(d) = unit(sub(here.points[i], here.points[a])) else {
        return false;
    };
    context.fixed[a]
        && context.sampler.model.releases().iter().any(|r| {
            let normal = r
                .direction
                .as_ref()
                .and_then(|n| context.sampler.vector(n).ok()?);
            r.word == ReleaseWord::Contact
                && r.point.index() == i
                && normal.is_some_and(|n| norm(cross(n, d)) < 1e-9 * (1.0 + norm(n)))
        })
}

/// Where hinges go, and whether each is fixed (then it stands on a support): a fixed rod end
/// or axle, two rods meeting, a rod on a block or at a disk's centre, a hinge the model names.
/// A particle at a rod's end is its bob, drawn as a dot instead.
fn joints(context: &Context<'_, '_>, rods: &[(P3, P3)], centres: &[P3]) -> Vec<(P3, bool)> {
    let model = context.sampler.model;
    let here = &context.here;
    let near = |p: P3, q: P3| norm(sub(p, q)) < 1e-6 * context.size;
    let ends: Vec<P3> = rods.iter().flat_map(|(a, b)| [*a, *b]).collect();
    let mut joints: Vec<(P3, bool)> = Vec::new();
    for &p in ends.iter().chain(centres) {
        if joints.iter().any(|(q, _)| near(p, *q)) {
            continue;
        }
        let named = |i: usize| near(here.points[i], p);
        // Fixed when every named point there is (a cart passing over the origin is not).
        let there: Vec<usize> = (0..here.points.len()).filter(|&i| named(i)).collect();
        let fixed = !there.is_empty() && there.iter().all(|&i| context.fixed[i]);
        let slider = context.sliders.iter().any(|(i, _)| named(*i));
        let bob = model.particles().iter().any(|q| named(q.point.index())) && !slider;
        let released = model
            .releases()
            .iter()
            .any(|r| r.word == ReleaseWord::Hinge && named(r.point.index()));
        let meeting = ends.iter().filter(|&&q| near(p, q)).count() > 1;
        let centre = centres.iter().any(|&q| near(p, q));
        let pivot = context.links.iter().any(|&(a, _)| named(a));
        if !bob && (fixed || slider || released || meeting || centre || pivot) {
            joints.push((p, fixed));
        }
    }
    joints
}

/// The surfaces of contacts: a named contact's (hatched away from its normal) and a rolling
/// body's in a planar system (normal towards its centre).
fn surfaces(context: &Context<'_, '_>, items: &mut Vec<Item>) {
    let model = context.sampler.model;
    let here = &context.here;
    let mut done: Vec<usize> = context.sliders.iter().map(|(i, _)| *i).collect();
    let mut add_surface = |at: usize, normal: P3, reach: f64, items: &mut Vec<Item>| {
        if done.contains(&at) {
            return;
        }
        done.push(at);
        let Some(n) = unit(normal) else { return };
        let along = match context.plane {
            Some(plane) => unit(cross(plane, n)),
            None => None,
        };
        let Some(t) = along else { return };
        let p = here.points[at];
        items.push(Item::Track {
            a: sub(p, scale(reach, t)),
            b: add(p, scale(reach, t)),
            side: scale(-1.0, n),
        });
    };
    for release in model.releases() {
        if matches!(release.word, ReleaseWord::Contact | ReleaseWord::Rolling) {
            let Some(direction) = &release.direction else {
                continue;
            };
            let Ok(Some(n)) = context.sampler.vector(direction) else {
                continue;
            };
            let at = match release.constraint.map(|c| &model.constraint(c).kind) {
                Some(ConstraintKind::Rolling { contact, .. }) => contact.index(),
                _ => release.point.index(),
            };
            if context
                .links
                .iter()
                .any(|&(a, i)| i == at && slides_on(context, a, i))
            {
                continue;
            }
            add_surface(at, n, 0.4 * context.size, items);
        }
    }
    for c in model.constraints() {
        if let ConstraintKind::Rolling { body, contact } = &c.kind {
            let g = here.points[model.bodies()[body.index()].centre.index()];
            let n = sub(g, here.points[contact.index()]);
            add_surface(contact.index(), n, 0.4 * context.size, items);
        }
    }
}

/// Tracks under the sliders: on the side of a contact's surface when the model names one,
/// else on the ground's side (or over the block, when a rod hangs from it that way).
fn tracks(context: &Context<'_, '_>, items: &mut Vec<Item>) {
    let model = context.sampler.model;
    let here = &context.here;
    for &(i, u) in &context.sliders {
        let contact = model.releases().iter().find_map(|r| {
            let named = r.word == ReleaseWord::Contact && r.point.index() == i;
            let n = context.sampler.vector(r.direction.as_ref()?).ok()??;
            named.then(|| scale(-1.0, n))
        });
        let guess = sub(context.down, scale(dot(context.down, u), u));
        let Some(mut side) = unit(contact.unwrap_or(guess)) else {
            continue;
        };
        let hanging = context.links.iter().any(|&(a, b)| {
            let other = if a == i {
                b
            } else if b == i {
                a
            } else {
                return false;
            };
            dot(sub(here.points[other], here.points[i]), side) > 0.0
        }) || context.shapes.iter().any(|s| match s {
            Shape::Rod { a, b, points } if points.contains(&i) => {
                let p = here.points[i];
                let far = if norm(sub(*a, p)) > norm(sub(*b, p)) {
                    *a
                } else {
                    *b
                };
                dot(sub(far, p), side) > 0.0
            }
            _ => false,
        });
        if hanging && contact.is_none() {
            side = scale(-1.0, side);
        }
        let p = add(here.points[i], scale(0.5 * context.block, side));
        let reach = 1.5 * context.block;
        items.push(Item::Track {
            a: sub(p, scale(reach, u)),
            b: add(p, scale(reach, u)),
            side,
        });
    }
}

fn bodies(context: &Context<'_, '_>, items: &mut Vec<Item>) {
    let model = context.sampler.model;
    for (b, shape) in context.shapes.iter().enumerate() {
        let body = &model.bodies()[b];
        let g = context.here.points[body.centre.index()];
        let name = body.name.name.clone();
        match shape {
            Shape::Disk {
                normal,
                radius,
                marker,
                ..
            } => items.push(Item::Disk {
                name,
                centre: g,
                normal: *normal,
                radius: *radius,
                marker: *marker,
            }),
            Shape::Block { along, size } => items.push(Item::Block {
                name,
                centre: g,
                along: *along,
                size: *size,
            }),
            Shape::Rod { .. } => {}
        }
    }
}

/// A label for every named point the drawing shows (particles carry their own).
fn labels(context: &Context<'_, '_>, items: &mut Vec<Item>) {
    let model = context.sampler.model;
    let here = &context.here;
    let particles: Vec<usize> = model.particles().iter().map(|p| p.point.index()).collect();
    let mut shown: Vec<usize> = Vec::new();
    let near = |p: P3, q: P3| norm(sub(p, q)) < 1e-6 * context.size;
    for item in items.iter() {
        let at: Vec<P3> = match item {
            Item::Rod { a, b } => vec![*a, *b],
            Item::Disk { centre, marker, .. } => vec![*centre, *marker],
            Item::Spring { a, b } | Item::Damper { a, b } => vec![*a, *b],
            Item::Arrow { from, .. } => vec![*from],
            Item::Hinge { at } | Item::Support { at, .. } => vec![*at],
            Item::Sphere { centre, .. } => vec![*centre],
            _ => Vec::new(),
        };
        for p in at {
            for (i, q) in here.points.iter().enumerate() {
                if near(p, *q) && !shown.contains(&i) && !particles.contains(&i) {
                    shown.push(i);
                }
            }
        }
    }
    // One label per place: a particle's own, else the first point declared there (`origin`
    // last: a named point at the origin is the better name).
    let mut places: Vec<P3> = particles.iter().map(|&i| here.points[i]).collect();
    shown.sort_by_key(|&i| (i == 0, i));
    for i in shown {
        let p = here.points[i];
        if places.iter().any(|&q| near(p, q)) {
            continue;
        }
        places.push(p);
        let name = if i == 0 {
            "O".to_owned()
        } else {
            model.points()[i].name.name.clone()
        };
        items.push(Item::Point { name, at: p });
    }
}
