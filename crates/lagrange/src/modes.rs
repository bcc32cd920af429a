//! A linearized mode of an [`Analysis`] about its first stable equilibrium, for
//! [`Analysis::mode_animation`]: the equilibrium `q₀`, the mode shape `φₖ` of
//! `K₀ φ = ω² M₀ φ` and its angular frequency `ωₖ`, and the amplitude that makes its motion
//! visible in the figure.

use draw::{Item, Scene, P3};

use crate::analysis::Analysis;
use crate::error::Error;

/// How far the farthest-moving drawn point goes at the mode's amplitude, as a part of the
/// figure's extent: a visible swing that stays near the linear range.
const REACH: f64 = 0.125;

/// The `k`-th undamped mode about an equilibrium.
#[derive(Clone, Debug)]
pub(crate) struct Mode {
    /// The equations' coordinates (a coordinate a constraint eliminates is not among them).
    names: Vec<String>,
    /// `q₀`, by coordinate.
    rest: Vec<f64>,
    /// `φₖ` (`φᵀ M₀ φ = 1`), by coordinate.
    shape: Vec<f64>,
    /// `ωₖ`, in radians per unit of time.
    pub omega: f64,
}

impl Mode {
    /// The `k`-th mode (from 1, by increasing `ω`) about the first stable equilibrium.
    ///
    /// # Errors
    /// As [`Analysis::equilibria`]; [`Error::NotAvailable`] when no equilibrium is known to
    /// be stable, when `k` is not between 1 and the number of modes, or when mode `k` does
    /// not oscillate (`ω² ≤ 0`).
    pub(crate) fn of(analysis: &Analysis, k: usize) -> Result<Mode, Error> {
        let equilibria = analysis.equilibria()?;
        let stable = equilibria
            .set
            .equilibria
            .iter()
            .zip(&equilibria.linearized)
            .find_map(|(e, l)| match l {
                Ok(l) if l.stable == Some(true) => Some((e, l)),
                _ => None,
            });
        let Some((equilibrium, linearized)) = stable else {
            return Err(Error::NotAvailable(format!(
                "no stable equilibrium was found ({} equilibria, none stable): a mode is an \
                 oscillation about a stable one (`lagrange equilibria` lists them)",
                equilibria.set.equilibria.len()
            )));
        };
        let omega_squared = linearized.omega_squared.as_deref().unwrap_or(&[]);
        let count = omega_squared.len();
        if k == 0 || k > count {
            return Err(Error::NotAvailable(format!(
                "no mode {k}: the linearization about the stable equilibrium has {count} \
                 mode(s), numbered from 1"
            )));
        }
        let w2 = omega_squared[k - 1];
        if !(w2 > 0.0 && w2.is_finite()) {
            let oscillating: Vec<String> = (1..=count)
                .filter(|&j| omega_squared[j - 1] > 0.0)
                .map(|j| j.to_string())
                .collect();
            return Err(Error::NotAvailable(format!(
                "mode {k} does not oscillate (ω² = {w2}: a coordinate that drifts freely); \
                 the modes that oscillate: {}",
                if oscillating.is_empty() {
                    "none".to_owned()
                } else {
                    oscillating.join(", ")
                }
            )));
        }
        Ok(Mode {
            names: equilibria.rest.coordinates.clone(),
            rest: equilibrium.values.clone(),
            shape: linearized.modes[k - 1].clone(),
            omega: w2.sqrt(),
        })
    }

    /// The value of coordinate `name` at `q₀ + s φ` (0 for one the equations do not have: a
    /// driven or an eliminated coordinate, filled in elsewhere).
    pub(crate) fn value(&self, name: &str, s: f64) -> f64 {
        self.names
            .iter()
            .position(|n| n == name)
            .map_or(0.0, |i| self.rest[i] + s * self.shape[i])
    }

    /// The amplitude `a` at which the drawn point that moves farthest moves by [`REACH`] of
    /// the figure's extent, from the scenes at `q₀` and at `q₀ + ε φ` (the motion is linear
    /// in `a` for small `a`). A mode that moves nothing drawn gets the amplitude that turns
    /// its largest component by 0.3.
    pub(crate) fn amplitude(&self, at_rest: &Scene, nudged: &Scene, epsilon: f64) -> f64 {
        let before: Vec<P3> = at_rest.items.iter().flat_map(positions).collect();
        let after: Vec<P3> = nudged.items.iter().flat_map(positions).collect();
        let moved = before
            .iter()
            .zip(&after)
            .map(|(a, b)| distance(*a, *b))
            .fold(0.0, f64::max);
        let extent = (0..3)
            .map(|i| {
                let (lo, hi) = before
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                        (lo.min(p[i]), hi.max(p[i]))
                    });
                hi - lo
            })
            .fold(0.0, f64::max);
        let rate = moved / epsilon;
        if before.len() == after.len() && rate > 0.0 && extent > 0.0 {
            REACH * extent / rate
        } else {
            0.3 / self
                .shape
                .iter()
                .fold(0.0, |m: f64, x| m.max(x.abs()))
                .max(f64::MIN_POSITIVE)
        }
    }

    /// A step `ε` small enough for [`Mode::amplitude`]'s linear estimate.
    pub(crate) fn epsilon(&self) -> f64 {
        1e-4 / self
            .shape
            .iter()
            .fold(0.0, |m: f64, x| m.max(x.abs()))
            .max(1e-300)
    }
}

/// The positions an item is drawn at that move with the system.
fn positions(item: &Item) -> Vec<P3> {
    match item {
        Item::Rod { a, b } => vec![*a, *b],
        Item::Disk { centre, marker, .. } => vec![*centre, *marker],
        Item::Block { centre, .. } => vec![*centre],
        Item::Particle { at, .. } | Item::Point { at, .. } => vec![*at],
        _ => Vec::new(),
    }
}

fn distance(a: P3, b: P3) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}
