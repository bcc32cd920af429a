//! Steady-motion linearizations, sweeps and canonical forms as text and JSON (docs/json.md,
//! "Steady motions"), and the plot of the eigenvalues against the swept parameter.

use std::path::Path;

use mechanics::kane::SteadyLinearization;
use serde_json::{json, Value};

use crate::steady::{CanonicalForm, ChangeKind, StabilityChange, SteadySweep};
use crate::Error;

/// Whether every eigenvalue has a negative real part (to rounding).
#[must_use]
pub fn is_stable(lin: &SteadyLinearization) -> bool {
    lin.eigenvalues.iter().all(|(re, _)| *re < -1e-12)
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
    canonical: Option<&CanonicalForm>,
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
    });
    if let (Some(c), Some(map)) = (canonical, v.as_object_mut()) {
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
    canonical: Option<&CanonicalForm>,
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
    out.push_str("\neigenvalues:\n");
    for (re, im) in &lin.eigenvalues {
        out.push_str(&format!(
            "  {re:.14} {} {:.14} i\n",
            if *im < 0.0 { '-' } else { '+' },
            im.abs()
        ));
    }
    out.push_str(if is_stable(lin) {
        "stable\n"
    } else {
        "unstable\n"
    });
    if let Some(c) = canonical {
        out.push_str(&format!(
            "\ncanonical form in ({}): M q'' + {v} C1 q' + (g K0 + {v}^2 K2) q = 0\n",
            c.coordinates.join(", "),
            v = c.speed
        ));
        for (name, m) in [("M", &c.mass), ("C1", &c.c1), ("K0", &c.k0), ("K2", &c.k2)] {
            out.push_str(&matrix_text(name, m));
        }
    }
    out
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
                json!({ "value": x, "eigenvalues": eigen_json(lin), "stable": is_stable(lin) })
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
    let mut out = format!("{:>10}  stable  eigenvalues\n", sweep.parameter);
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
                let s = if is_stable(lin) { "yes" } else { "no" };
                out.push_str(&format!("{x:>10.4}  {s:>6}  {}\n", e.join(", ")));
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
