//! Steady-motion linearizations, sweeps and canonical forms as text and JSON (docs/json.md,
//! "Steady motions"), and the plot of the eigenvalues against the swept parameter.

use std::path::Path;

use mechanics::kane::{SteadyLinearization, SteadySpectrum, SteadyVerdict};
use mechanics::stability_condition::StabilityCondition;
use serde_json::{json, Value};

use crate::steady::{CanonicalForm, ChangeKind, StabilityChange, SteadySweep};
use crate::steady_condition::{condition_json, condition_lines};
use crate::Error;

/// What is printed beside a steady linearization: its whole spectrum and verdict, the
/// canonical form, the condition in the parameters (each where there is one).
#[derive(Clone, Copy, Debug, Default)]
pub struct SteadyExtras<'a> {
    /// The canonical form `M q̈ + v C₁ q̇ + (g K₀ + v² K₂) q = 0`.
    pub canonical: Option<&'a CanonicalForm>,
    /// Every eigenvalue and the verdict relative to the family of steady motions.
    pub spectrum: Option<&'a SteadySpectrum>,
    /// The stability condition in the parameters.
    pub condition: Option<&'a StabilityCondition>,
}

/// Whether the motion is stable relative to the family of steady motions, asymptotically or
/// to first order (`false` when the eigenproblem fails).
#[must_use]
pub fn is_stable(lin: &SteadyLinearization) -> bool {
    lin.spectrum().is_ok_and(|s| s.verdict.is_stable())
}

/// The verdict's short name (`asymptotic`, `marginal`, `unstable`).
fn verdict_short(lin: &SteadyLinearization) -> &'static str {
    lin.spectrum().map_or("unstable", |s| s.verdict.short())
}

/// Why the verdict is what it is, in a course's words.
#[must_use]
pub fn verdict_reason(s: &SteadySpectrum) -> String {
    let family = s.family.iter().filter(|f| **f).count();
    let zeros = match (s.zero_multiplicity, s.kernel_dimension) {
        (0, _) => "no zero eigenvalue".to_owned(),
        (k, d) if k > d => format!(
            "the zero eigenvalue has multiplicity {k} but {d} independent eigenvector(s): a \
             Jordan block, whose mode grows linearly in time"
        ),
        (k, _) => format!(
            "the zero eigenvalue (multiplicity {k}) has as many independent eigenvectors, each \
             a neighbouring steady motion: the family of steady motions through this one has \
             dimension {family}, and the verdict is the other eigenvalues'"
        ),
    };
    let others = match s.verdict {
        SteadyVerdict::AsymptoticallyStable => "; every other eigenvalue has a negative real part",
        SteadyVerdict::Marginal => {
            "; the others lie on the imaginary axis (none to the right): bounded oscillations \
             to first order, which the linearization cannot turn into a proof of stability"
        }
        SteadyVerdict::Unstable => "; an eigenvalue has a positive real part",
        _ => "",
    };
    format!("{zeros}{others}")
}

fn eigen_json(lin: &SteadyLinearization) -> Value {
    Value::Array(
        lin.eigenvalues
            .iter()
            .map(|(re, im)| json!([re + 0.0, im + 0.0]))
            .collect(),
    )
}

fn named(names: &[String], values: &[f64], suffix: &str) -> Value {
    let map = names
        .iter()
        .zip(values)
        .map(|(n, v)| (format!("{n}{suffix}"), json!(v)))
        .collect();
    Value::Object(map)
}

/// The linearization (and the canonical form when there is one) as JSON.
#[must_use]
pub fn steady_json(
    coordinates: &[String],
    lin: &SteadyLinearization,
    extras: SteadyExtras<'_>,
) -> Value {
    let mut v = json!({
        "schema": 1,
        "method": "kane",
        "steady_motion": {
            "configuration": named(coordinates, &lin.configuration, ""),
            "rates": named(coordinates, &lin.rates, "_d"),
        },
        "cyclic": lin.cyclic,
        "shape": lin.shape,
        "holonomic": lin.holonomic,
        "speeds": lin.speeds,
        "states": lin.states,
        "decoupled": lin.decoupled,
        "state_matrix": lin.state_matrix,
        "mass": lin.mass,
        "damping": lin.damping,
        "stiffness": lin.stiffness,
        "eigenvalues": eigen_json(lin),
        "stable": is_stable(lin),
        "verdict": verdict_short(lin),
    });
    if let (Some(spectrum), Some(map)) = (extras.spectrum, v.as_object_mut()) {
        map.insert("spectrum".into(), spectrum_json(spectrum));
    }
    if let (Some(c), Some(map)) = (extras.condition, v.as_object_mut()) {
        map.insert("condition".into(), condition_json(c));
    }
    if let (Some(c), Some(map)) = (extras.canonical, v.as_object_mut()) {
        map.insert(
            "canonical".into(),
            json!({
                "form": format!("M q'' + {v} C1 q' + (g K0 + {v}^2 K2) q = 0", v = c.speed),
                "speed": c.speed,
                "coordinates": c.coordinates,
                "M": c.mass,
                "C1": c.c1,
                "K0": c.k0,
                "K2": c.k2,
                "eliminated": c.eliminated.iter().map(|(s, a)| json!({"speed": s, "coefficients": a})).collect::<Vec<_>>(),
            }),
        );
    }
    v
}

fn matrix_text(name: &str, m: &[Vec<f64>]) -> String {
    let mut out = format!("{name} =\n");
    for row in m {
        // `+ 0.0` turns −0 into 0, which is never printed.
        let cells: Vec<String> = row.iter().map(|x| format!("{:>22.14}", x + 0.0)).collect();
        out.push_str(&format!("  [{} ]\n", cells.join(" ")));
    }
    out
}

/// The linearization (and the canonical form when there is one) as text.
#[must_use]
pub fn steady_text(
    coordinates: &[String],
    lin: &SteadyLinearization,
    extras: SteadyExtras<'_>,
) -> String {
    let rates: Vec<String> = coordinates
        .iter()
        .zip(&lin.rates)
        .filter(|(_, r)| r.abs() > 0.0)
        .map(|(q, r)| format!("{q}' = {r}"))
        .collect();
    let mut out = String::from("steady motion (Kane's method)\n");
    out.push_str(&format!("  rates: {}\n", rates.join(", ")));
    out.push_str(&format!(
        "  cyclic coordinates: {}\n",
        lin.cyclic.join(", ")
    ));
    out.push_str(&format!(
        "  held by holonomic constraints: {}\n",
        lin.holonomic.join(", ")
    ));
    out.push_str(&format!(
        "  independent speeds: {}\n",
        lin.speeds.join(", ")
    ));
    out.push_str(&format!("  states: {}", lin.states.join(", ")));
    if !lin.decoupled.is_empty() {
        out.push_str(&format!(
            " ({} decoupled: a zero eigenvalue)",
            lin.decoupled.join(", ")
        ));
    }
    out.push_str("\n\n");
    out.push_str(&matrix_text("A (state matrix)", &lin.state_matrix));
    match extras.spectrum {
        Some(spectrum) => out.push_str(&spectrum_text(spectrum)),
        None => {
            out.push_str("\neigenvalues:\n");
            for (re, im) in &lin.eigenvalues {
                out.push_str(&format!("  {}\n", complex_text(*re, *im, 14)));
            }
            out.push_str(if is_stable(lin) {
                "stable\n"
            } else {
                "unstable\n"
            });
        }
    }
    if let Some(c) = extras.condition {
        for line in condition_lines(c) {
            out.push_str(&format!("{line}\n"));
        }
    }
    if let Some(c) = extras.canonical {
        out.push_str(&format!(
            "\ncanonical form in ({}): M q'' + {v} C1 q' + (g K0 + {v}^2 K2) q = 0\n",
            c.coordinates.join(", "),
            v = c.speed
        ));
        for (speed, coefficients) in &c.eliminated {
            let terms: Vec<String> = coefficients
                .iter()
                .zip(&c.coordinates)
                .map(|(a, q)| format!("{} {q}", a + 0.0))
                .collect();
            out.push_str(&format!(
                "  {speed} = {} (+ a constant fixed by the family): its linearized equation is a \
                 combination of shape rates, integrated and eliminated\n",
                terms.join(" + ")
            ));
        }
        for (name, m) in [("M", &c.mass), ("C1", &c.c1), ("K0", &c.k0), ("K2", &c.k2)] {
            out.push_str(&matrix_text(name, m));
        }
    }
    out
}

pub(crate) fn complex_text(re: f64, im: f64, digits: usize) -> String {
    // Parts below the last printed digit print as 0, not −0.
    let last = 0.5 * 10_f64.powi(-i32::try_from(digits).unwrap_or(14));
    let shown = |x: f64| if x.abs() < last { 0.0 } else { x };
    let (re, im) = (shown(re), shown(im));
    format!(
        "{re:.digits$} {} {:.digits$} i",
        if im < 0.0 { '-' } else { '+' },
        im.abs()
    )
}

/// Every eigenvalue, the family's marked, and the verdict with its reason.
fn spectrum_text(s: &SteadySpectrum) -> String {
    let mut out = format!("\neigenvalues (all {}):\n", s.eigenvalues.len());
    for (k, (re, im)) in s.eigenvalues.iter().enumerate() {
        let note = if s.family[k] {
            "   (the family of steady motions)"
        } else if s.on_axis(k) {
            "   (on the imaginary axis)"
        } else {
            ""
        };
        out.push_str(&format!("  {}{note}\n", complex_text(*re, *im, 14)));
    }
    out.push_str(&format!("{}\n", s.verdict.words()));
    out.push_str(&format!("  why: {}\n", verdict_reason(s)));
    out
}

fn spectrum_json(s: &SteadySpectrum) -> Value {
    json!({
        "eigenvalues": s.eigenvalues.iter().map(|(re, im)| json!([re + 0.0, im + 0.0])).collect::<Vec<_>>(),
        "family": s.family,
        "zero_multiplicity": s.zero_multiplicity,
        "kernel_dimension": s.kernel_dimension,
        "symmetric": s.symmetric,
        "axis_tolerance": s.axis_tolerance(),
        "verdict": s.verdict.short(),
        "words": s.verdict.words(),
        "reason": verdict_reason(s),
    })
}

fn kind_name(kind: ChangeKind) -> &'static str {
    match kind {
        ChangeKind::Real => "real eigenvalue through zero",
        ChangeKind::Oscillatory => "complex pair through the imaginary axis",
        ChangeKind::Coalescence => "real pair becomes complex",
    }
}

/// A sweep and its stability changes as JSON.
#[must_use]
pub fn sweep_json(sweep: &SteadySweep, changes: &[StabilityChange]) -> Value {
    let steps: Vec<Value> = sweep
        .steps
        .iter()
        .map(|(x, lin)| match lin {
            Ok(lin) => {
                json!({
                    "value": x,
                    "eigenvalues": eigen_json(lin),
                    "stable": is_stable(lin),
                    "verdict": verdict_short(lin),
                })
            }
            Err(e) => json!({ "value": x, "error": e.to_string() }),
        })
        .collect();
    let changes: Vec<Value> = changes
        .iter()
        .map(|c| json!({ "at": c.at, "kind": kind_name(c.kind) }))
        .collect();
    json!({ "schema": 1, "method": "kane", "parameter": sweep.parameter, "steps": steps, "changes": changes })
}

/// A sweep and its stability changes as text.
#[must_use]
pub fn sweep_text(sweep: &SteadySweep, changes: &[StabilityChange]) -> String {
    let mut out = format!("{:>10}    stable  eigenvalues\n", sweep.parameter);
    for (x, lin) in &sweep.steps {
        match lin {
            Ok(lin) => {
                let e: Vec<String> = lin
                    .eigenvalues
                    .iter()
                    .map(|(re, im)| {
                        if *im == 0.0 {
                            format!("{re:.6}")
                        } else {
                            format!(
                                "{re:.6}{}{:.6}i",
                                if *im < 0.0 { '-' } else { '+' },
                                im.abs()
                            )
                        }
                    })
                    .collect();
                let s = match verdict_short(lin) {
                    "asymptotic" => "yes",
                    "marginal" => "marginal",
                    _ => "no",
                };
                out.push_str(&format!("{x:>10.4}  {s:>8}  {}\n", e.join(", ")));
            }
            Err(e) => out.push_str(&format!("{x:>10.4}  {e}\n")),
        }
    }
    out.push_str("\nstability changes:\n");
    for c in changes {
        out.push_str(&format!(
            "  {} = {:.14}: {}\n",
            sweep.parameter,
            c.at,
            kind_name(c.kind)
        ));
    }
    out
}

/// Plots the real and imaginary parts of the eigenvalues against the parameter (filled
/// where the motion is stable), as the bifurcation diagrams are drawn.
///
/// # Errors
/// [`Error::Plot`] for a wrong extension or a drawing failure.
pub fn plot_sweep(path: &Path, sweep: &SteadySweep) -> Result<(), Error> {
    let mut points = Vec::new();
    for (x, lin) in &sweep.steps {
        let Ok(lin) = lin else { continue };
        let stable = Some(is_stable(lin));
        for (re, im) in &lin.eigenvalues {
            for (coordinate, value) in [(0, *re), (1, im.abs())] {
                points.push(report::BifurcationPoint {
                    parameter: *x,
                    coordinate,
                    value,
                    stable,
                });
            }
        }
    }
    let names = ["Re λ (1/s)".to_string(), "|Im λ| (rad/s)".to_string()];
    report::plot_bifurcation(path, &sweep.parameter, &names, &points)?;
    Ok(())
}
