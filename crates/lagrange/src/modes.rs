//! A linearized mode of an [`Analysis`] about its first stable equilibrium, for
//! [`Analysis::mode_animation`]: the equilibrium `q₀`, the mode shape `φₖ` of
//! `K₀ φ = ω² M₀ φ` and its angular frequency `ωₖ`, and the amplitude that makes its motion
//! visible in the figure.

use cas::Expr;
use draw::{Item, Scene, P3};
use mechanics::equilibria::{Method, RestEquations, Values};
use mechanics::linearize::{evaluate_matrix, LinearizeError};
use numeric::eigen::EigenError;

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
    /// With constraints kept by multipliers: the constraints, the rest equations and the
    /// values, to bring `q₀ + s φ` back onto `Φ = 0` (a closed loop stays closed at the
    /// amplitude drawn).
    manifold: Option<(mechanics::KeptRest, RestEquations, Values)>,
}

impl Mode {
    /// The `k`-th mode (from 1, by increasing `ω`) about the first stable equilibrium; at a
    /// pole of the coordinates (the spherical pendulum's bottom, a top's axis along the
    /// vertical), where the mass matrix is singular, the modes of the directions that move
    /// the system ([`reduced`]).
    ///
    /// # Errors
    /// As [`Analysis::equilibria`]; [`Error::NotAvailable`] when no equilibrium is known to
    /// be stable (the sentence says why for each), when `k` is not between 1 and the number
    /// of modes, or when mode `k` does not oscillate (`ω² ≤ 0`).
    pub(crate) fn of(analysis: &Analysis, k: usize) -> Result<Mode, Error> {
        let equilibria = analysis.equilibria()?;
        let modes = about_a_stable_equilibrium(analysis, equilibria)?;
        let count = modes.omega_squared.len().min(modes.shapes.len());
        if k == 0 || k > count {
            return Err(Error::NotAvailable(format!(
                "no mode {k}: the linearization about the stable equilibrium has {count} \
                 mode(s), numbered from 1{}",
                modes.pole.as_deref().unwrap_or("")
            )));
        }
        // An ω² this small against the others is a zero that rounding left (a top's free
        // spin): its "period" would be astronomical.
        let scale = modes
            .omega_squared
            .iter()
            .fold(0.0_f64, |m, w| m.max(w.abs()));
        let oscillates = |w2: f64| w2 > 1e-9 * scale && w2.is_finite();
        let mut w2 = modes.omega_squared[k - 1];
        if !oscillates(w2) {
            if w2.abs() <= 1e-9 * scale {
                w2 = 0.0;
            }
            let oscillating: Vec<String> = (1..=count)
                .filter(|&j| oscillates(modes.omega_squared[j - 1]))
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
        let manifold = match &equilibria.rest.constraints {
            Some(kept) => Some((
                kept.clone(),
                equilibria.rest.clone(),
                analysis.values()?.into_iter().collect(),
            )),
            None => None,
        };
        Ok(Mode {
            manifold,
            names: equilibria.rest.coordinates.clone(),
            rest: modes.rest,
            shape: modes.shapes[k - 1].clone(),
            omega: w2.sqrt(),
        })
    }

    /// The value of coordinate `name` at `q₀ + s φ` (0 for one the equations do not have: a
    /// driven or an eliminated coordinate, filled in elsewhere).
    pub(crate) fn value(&self, name: &str, s: f64) -> f64 {
        let Some(i) = self.names.iter().position(|n| n == name) else {
            return 0.0;
        };
        match &self.manifold {
            Some((kept, rest, values)) => {
                let q: Vec<f64> = self
                    .rest
                    .iter()
                    .zip(&self.shape)
                    .map(|(q0, x)| q0 + s * x)
                    .collect();
                kept.project(rest, &q, values)[i]
            }
            None => self.rest[i] + s * self.shape[i],
        }
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

/// The undamped modes about one equilibrium.
struct Modes {
    /// `q₀`, by coordinate.
    rest: Vec<f64>,
    /// `ω²`, increasing.
    omega_squared: Vec<f64>,
    /// The mode shapes (`φᵀ M₀ φ = 1`), one per `ω²`.
    shapes: Vec<Vec<f64>>,
    /// At a pole of the coordinates, the clause that says so (for a "no mode k" sentence).
    pole: Option<String>,
}

/// The modes about the first equilibrium whose linearization is stable, else about the first
/// at a pole of the coordinates that is stable in the directions that move the system.
///
/// # Errors
/// [`Error::NotAvailable`] with a sentence that says, for each equilibrium, why it has no
/// modes to animate, or that there is no equilibrium at all.
fn about_a_stable_equilibrium(
    analysis: &Analysis,
    equilibria: &crate::equilibria::Equilibria,
) -> Result<Modes, Error> {
    let pairs = || equilibria.set.equilibria.iter().zip(&equilibria.linearized);
    if let Some(modes) = pairs().find_map(|(e, l)| match l {
        Ok(l) if l.stable == Some(true) && !l.modes.is_empty() => Some(Modes {
            rest: e.values.clone(),
            omega_squared: l.omega_squared.clone().unwrap_or_default(),
            shapes: l.modes.clone(),
            pole: None,
        }),
        _ => None,
    }) {
        return Ok(modes);
    }
    let mut reasons = Vec::new();
    for (i, (e, l)) in pairs().enumerate() {
        let at = describe(&equilibria.rest.coordinates, &e.values);
        let reason = match l {
            Ok(l) if l.stable == Some(true) => {
                "stable, but its coordinates are coupled gyroscopically (complex modes)".to_owned()
            }
            Ok(l) if l.stable == Some(false) => "unstable".to_owned(),
            Ok(l) => format!("stability undecided ({})", l.criterion),
            Err(LinearizeError::Eigen(EigenError::MassNotPositiveDefinite)) => {
                match reduced(analysis, &equilibria.rest, &e.values)? {
                    Reduced::Stable(modes) => return Ok(modes),
                    Reduced::Unstable(pole) => format!("unstable{pole}"),
                    Reduced::Undecided(why) => why,
                }
            }
            Err(err) => format!("not linearized ({err})"),
        };
        reasons.push(format!("#{i} ({at}): {reason}"));
    }
    Err(Error::NotAvailable(if reasons.is_empty() {
        no_equilibrium(&equilibria.rest, equilibria.set.method)
    } else {
        format!(
            "no stable equilibrium was found, so there is no oscillation about one to animate \
             (`lagrange equilibria` lists them): {}",
            reasons.join("; ")
        )
    }))
}

/// Why there is no mode when there is no equilibrium.
fn no_equilibrium(rest: &RestEquations, method: Method) -> String {
    let complete = matches!(method, Method::Exact | Method::Polynomial | Method::Scan);
    format!(
        "{} for these values: the rest equations f(q, 0) = 0 in ({}) have no solution{}, so \
         the system never rests and no mode oscillates about a rest (the equilibria's \
         listing prints the equations; the simulated motion can be animated instead; values \
         of the parameters for which it rests, a level slope for instance, may have one)",
        if complete {
            "the model has no equilibrium"
        } else {
            "no equilibrium was found"
        },
        rest.coordinates.join(", "),
        if complete {
            ""
        } else {
            " that the search found"
        },
    )
}

/// `q = value, …` for a sentence.
fn describe(names: &[String], values: &[f64]) -> String {
    names
        .iter()
        .zip(values)
        .map(|(n, v)| format!("{n} = {}", float(*v)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A value to four decimals, without trailing zeros.
fn float(x: f64) -> String {
    let s = format!("{x:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_owned()
    } else {
        s.to_owned()
    }
}

/// The linearization at an equilibrium where the mass matrix `M₀` is singular.
enum Reduced {
    /// Stable in the directions that move the system: their modes.
    Stable(Modes),
    /// Unstable in them; the clause that names the pole.
    Unstable(String),
    /// Not decided, and why.
    Undecided(String),
}

/// The modes about `q₀` where `M₀` is singular, in the directions that move the system.
///
/// Where a chart of the configuration has a pole (the spherical pendulum's `θ = 0`, where
/// the azimuth `φ` moves nothing; a top's Euler angles with its axis vertical, where
/// precession and spin turn about the same line), some combination `v` of the coordinates
/// moves no point at first order: `M₀ v = 0`. The kinetic energy does not see `v`, and
/// neither does the potential when `K₀ v = 0` (nothing moves, so nothing changes). The
/// motion then lives in the range of `M₀`, spanned by its eigenvectors `V` with positive
/// eigenvalues: with `q = q₀ + V y`, `(Vᵀ K₀ V) y = ω² (Vᵀ M₀ V) y`, and `φ = V y` (so that
/// `φᵀ M₀ φ = 1`). Each such mode is a true small oscillation of the system (seen in the
/// chart; the directions the pole hides are these same motions turned about it).
fn reduced(analysis: &Analysis, rest: &RestEquations, q0: &[f64]) -> Result<Reduced, Error> {
    let values: Values = analysis.values()?.into_iter().collect();
    let equations = analysis.equations()?;
    let stiffness: Vec<Vec<Expr>> = rest
        .jacobian
        .iter()
        .map(|row| row.iter().map(|j| -*j).collect())
        .collect();
    let (Some(m0), Some(k0)) = (
        evaluate_matrix(equations.mass_matrix(), rest, q0, &values).ok(),
        evaluate_matrix(&stiffness, rest, q0, &values).ok(),
    ) else {
        return Ok(Reduced::Undecided(
            "the mass matrix is singular there and the linearization cannot be evaluated"
                .to_owned(),
        ));
    };
    let n = m0.len();
    let identity: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| f64::from(u8::from(i == j))).collect())
        .collect();
    let Ok(mass) = numeric::eigen::symmetric_generalized(&m0, &identity) else {
        return Ok(Reduced::Undecided(
            "the mass matrix has no eigenvectors".to_owned(),
        ));
    };
    let top = mass.values.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let (range, null): (Vec<usize>, Vec<usize>) =
        (0..n).partition(|&i| mass.values[i] > 1e-9 * top);
    let pole = pole_clause(&rest.coordinates, &null, &mass.modes);
    let k_scale = k0.iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
    let felt = null.iter().any(|&i| {
        let v = &mass.modes[i];
        (0..n).any(|r| (0..n).map(|c| k0[r][c] * v[c]).sum::<f64>().abs() > 1e-9 * k_scale)
    });
    if range.is_empty() || felt {
        return Ok(Reduced::Undecided(format!(
            "stability undecided: the mass matrix is singular there{pole}, and the forces \
             change in a direction that moves nothing"
        )));
    }
    let basis: Vec<&Vec<f64>> = range.iter().map(|&i| &mass.modes[i]).collect();
    let project = |a: &[Vec<f64>]| -> Vec<Vec<f64>> {
        basis
            .iter()
            .map(|u| {
                basis
                    .iter()
                    .map(|w| {
                        (0..n)
                            .map(|r| u[r] * (0..n).map(|c| a[r][c] * w[c]).sum::<f64>())
                            .sum()
                    })
                    .collect()
            })
            .collect()
    };
    let Ok(small) = numeric::eigen::symmetric_generalized(&project(&k0), &project(&m0)) else {
        return Ok(Reduced::Undecided(format!(
            "stability undecided: the mass matrix is singular there{pole}"
        )));
    };
    let scale = small.values.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if small.values.iter().any(|w2| *w2 < -1e-9 * scale) {
        return Ok(Reduced::Unstable(pole));
    }
    let shapes = small
        .modes
        .iter()
        .map(|y| {
            (0..n)
                .map(|r| basis.iter().zip(y).map(|(u, c)| u[r] * c).sum())
                .collect()
        })
        .collect();
    Ok(Reduced::Stable(Modes {
        rest: q0.to_vec(),
        omega_squared: small.values,
        shapes,
        pole: Some(format!(
            " (in the directions that move the system: the mass matrix is singular at this \
             equilibrium{pole}; the motions the pole hides are these same modes turned about it)"
        )),
    }))
}

/// `, a pole of the coordinates: moving (phi) moves nothing`, naming the coordinates that
/// take part in the null directions `null` of `M₀` (eigenvectors `modes`).
fn pole_clause(names: &[String], null: &[usize], modes: &[Vec<f64>]) -> String {
    let mut moving: Vec<&str> = Vec::new();
    for &i in null {
        for (j, x) in modes[i].iter().enumerate() {
            if x.abs() > 1e-6 && !moving.contains(&names[j].as_str()) {
                moving.push(&names[j]);
            }
        }
    }
    if moving.is_empty() {
        return String::new();
    }
    let what = if moving.len() == 1 {
        format!("moving {} alone", moving[0])
    } else {
        format!("a combination of {}", moving.join(", "))
    };
    format!(", a pole of the coordinates: {what} moves nothing")
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
