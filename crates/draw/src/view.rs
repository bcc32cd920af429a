//! The projection from the world to the page: a planar system seen square-on in its plane
//! (gravity pointing down the page when it lies in the plane), a spatial one in an oblique
//! (cabinet) projection with `z` up and `x` receding at 45°. Page coordinates are SVG pixels,
//! `y` down.

use crate::sample::dot;
use crate::scene::{Item, Scene, P3};

/// Pixels for the larger side of the drawing.
const SIDE: f64 = 440.0;

/// A linear projection `p ↦ origin + scale (p·u, −p·v)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// The world vector drawn as the page's rightward unit.
    pub u: P3,
    /// The world vector drawn as the page's upward unit.
    pub v: P3,
    /// Pixels per metre.
    pub scale: f64,
    /// The page position of the world origin.
    pub origin: (f64, f64),
    /// Whether the system is planar and seen square-on.
    pub planar: bool,
}

impl View {
    /// The page position of `p`.
    #[must_use]
    pub fn page(&self, p: P3) -> (f64, f64) {
        (
            self.origin.0 + self.scale * dot(p, self.u),
            self.origin.1 - self.scale * dot(p, self.v),
        )
    }

    /// The page direction of the world vector `d` (not normalised).
    #[must_use]
    pub fn direction(&self, d: P3) -> (f64, f64) {
        (dot(d, self.u), -dot(d, self.v))
    }
}

/// The view of a scene: its plane (`None` for a spatial system) and gravity's direction
/// choose the axes; the drawing's extent chooses the scale.
#[must_use]
pub fn fit(scene: &Scene, plane: Option<P3>) -> View {
    let (u, mut v, planar) = match plane {
        Some(n) if n[2] == 1.0 => ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], true),
        Some(n) if n[1] == 1.0 => ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], true),
        Some(_) => ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0], true),
        None => {
            let k = 0.5 * std::f64::consts::FRAC_1_SQRT_2;
            ([-k, 1.0, 0.0], [-k, 0.0, 1.0], false)
        }
    };
    let gravity = scene.items.iter().find_map(|i| match i {
        Item::Gravity { direction, .. } => Some(*direction),
        _ => None,
    });
    if let Some(g) = gravity {
        // Gravity up the page: look at the plane from its other side.
        if planar && dot(g, v) > 1e-9 {
            v = v.map(|x| -x);
        }
    }
    let mut view = View {
        u,
        v,
        scale: 1.0,
        origin: (0.0, 0.0),
        planar,
    };
    let (lo, hi) = bounds(scene, &view);
    let side = (hi.0 - lo.0).max(hi.1 - lo.1);
    view.scale = if side > 1e-12 { SIDE / side } else { SIDE };
    view.origin = (-view.scale * lo.0, -view.scale * lo.1);
    view
}

/// The box (page units at scale 1, origin 0) around every point of the scene.
fn bounds(scene: &Scene, view: &View) -> ((f64, f64), (f64, f64)) {
    let mut lo = (f64::INFINITY, f64::INFINITY);
    let mut hi = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut take = |p: P3| {
        let (x, y) = view.page(p);
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    };
    for item in &scene.items {
        match item {
            Item::Rod { a, b }
            | Item::Track { a, b, .. }
            | Item::Spring { a, b }
            | Item::Damper { a, b }
            | Item::Reference { a, b } => {
                take(*a);
                take(*b);
            }
            Item::Arrow { from, to, .. } => {
                take(*from);
                take(*to);
            }
            Item::Disk { centre, radius, .. } | Item::Sphere { centre, radius } => {
                for d in [view.u, view.v] {
                    take(crate::sample::add(
                        *centre,
                        crate::sample::scale(*radius, d),
                    ));
                    take(crate::sample::sub(
                        *centre,
                        crate::sample::scale(*radius, d),
                    ));
                }
            }
            Item::Block { centre, size, .. } => {
                for d in [view.u, view.v] {
                    take(crate::sample::add(
                        *centre,
                        crate::sample::scale(0.7 * size, d),
                    ));
                    take(crate::sample::sub(
                        *centre,
                        crate::sample::scale(0.7 * size, d),
                    ));
                }
            }
            Item::Arc { points, .. } => points.iter().for_each(|p| take(*p)),
            Item::Support { at, .. }
            | Item::Wall { at, .. }
            | Item::Hinge { at }
            | Item::Particle { at, .. }
            | Item::Coil { at, .. }
            | Item::Point { at, .. } => take(*at),
            Item::Gravity { .. } => {}
        }
    }
    if lo.0.is_finite() {
        (lo, hi)
    } else {
        ((0.0, 0.0), (0.0, 0.0))
    }
}
