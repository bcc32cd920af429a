//! Equilibria, stability and linearized dynamics for people (text) and programs (JSON,
//! `"schema": 1`, sections `equilibria` and `linearized` of `docs/json.md`).

use std::fmt::Write as _;

use cas::print::{to_sympy, to_unicode};
use cas::{Condition, Expr};
use mechanics::equilibria::{EquilibriumSet, RestEquations};
use mechanics::linearize::{LinearizeError, Linearized};
use serde_json::{json, Map, Value};

/// One equilibrium's linearization, or why it failed.
pub type LinearizedResult = Result<Linearized, LinearizeError>;

pub(crate) fn condition_text(c: &Condition, print: fn(Expr) -> String) -> String {
    match c {
        Condition::AbsAtMostOne(e) => format!("abs({}) <= 1", print(*e)),
        Condition::NonNegative(e) => format!("{} >= 0", print(*e)),
        Condition::NonZero(e) => format!("{} != 0", print(*e)),
        Condition::Zero(e) => format!("{} == 0", print(*e)),
        _ => "a further condition".to_string(),
    }
}

fn by_coordinate<T: Into<Value> + Clone>(names: &[String], values: &[T]) -> Value {
    let mut map = Map::new();
    for (n, v) in names.iter().zip(values) {
        map.insert(n.clone(), v.clone().into());
    }
    Value::Object(map)
}

fn matrix(m: &[Vec<f64>]) -> Value {
    json!(m)
}

fn exact_matrix(m: &[Vec<Expr>]) -> Value {
    m.iter()
        .map(|row| row.iter().map(|e| to_sympy(*e)).collect::<Vec<_>>())
        .collect()
}

fn eigen_pairs(l: &[(f64, f64)]) -> Value {
    l.iter().map(|(re, im)| json!([re, im])).collect()
}

/// The `equilibria` array: each with `values`, `exact`, `conditions`, `stable`, `criterion`,
/// `eigenvalues`.
#[must_use]
pub fn equilibria_array(
    rest: &RestEquations,
    set: &EquilibriumSet,
    lin: &[LinearizedResult],
) -> Value {
    set.equilibria
        .iter()
        .zip(lin)
        .enumerate()
        .map(|(i, (e, l))| {
            let exact = e.exact.as_ref().map(|x| {
                let s: Vec<String> = x.iter().map(|v| to_sympy(*v)).collect();
                by_coordinate(&rest.coordinates, &s)
            });
            let (stable, criterion, eigenvalues) = match l {
                Ok(l) => (json!(l.stable), json!(l.criterion.to_string()), eigen_pairs(&l.eigenvalues)),
                Err(err) => (Value::Null, json!(format!("not decided: {err}")), json!([])),
            };
            let also_at: Vec<Value> = set
                .repeated
                .iter()
                .filter(|r| r.same_as == i)
                .map(|r| by_coordinate(&rest.coordinates, &r.values))
                .collect();
            json!({
                "index": i,
                "values": by_coordinate(&rest.coordinates, &e.values),
                "multipliers": multipliers_json(rest, &e.multipliers, e.exact_multipliers.as_deref()),
                "also_at": also_at,
                "exact": exact,
                "conditions": e.conditions.iter().map(|c| condition_text(c, to_sympy)).collect::<Vec<_>>(),
                "stable": stable,
                "criterion": criterion,
                "eigenvalues": eigenvalues,
            })
        })
        .collect()
}

/// The constraints kept by multipliers: `[{"name", "multiplier", "function"}]`.
fn constraints_json(rest: &RestEquations) -> Value {
    let Some(kept) = &rest.constraints else {
        return json!([]);
    };
    kept.names
        .iter()
        .zip(&kept.multipliers)
        .zip(&kept.functions)
        .map(|((name, symbol), f)| {
            json!({ "name": name, "multiplier": to_sympy(*symbol), "function": to_sympy(*f) })
        })
        .collect()
}

/// The multipliers of the constraints kept by them at an equilibrium, by constraint:
/// `[{"constraint", "symbol", "value", "exact"}]` (empty without such constraints).
fn multipliers_json(rest: &RestEquations, values: &[f64], exact: Option<&[Expr]>) -> Value {
    let Some(kept) = &rest.constraints else {
        return json!([]);
    };
    kept.names
        .iter()
        .zip(&kept.multipliers)
        .zip(values)
        .enumerate()
        .map(|(k, ((name, symbol), value))| {
            json!({
                "constraint": name,
                "symbol": to_sympy(*symbol),
                "value": value,
                "exact": exact.and_then(|x| x.get(k)).map(|e| to_sympy(*e)),
            })
        })
        .collect()
}

/// The lines of the multipliers at an equilibrium: `λ1 (loop_x) = …`.
fn multipliers_text(rest: &RestEquations, values: &[f64], exact: Option<&[Expr]>) -> Vec<String> {
    let Some(kept) = &rest.constraints else {
        return Vec::new();
    };
    kept.names
        .iter()
        .zip(&kept.multipliers)
        .zip(values)
        .enumerate()
        .map(|(k, ((name, symbol), value))| {
            let exact = exact
                .and_then(|x| x.get(k))
                .map(|e| format!(" = {}", to_unicode(*e)))
                .unwrap_or_default();
            format!("{} ({name}){exact} = {}", to_unicode(*symbol), six(*value))
        })
        .collect()
}

/// The JSON of `lagrange equilibria`.
#[must_use]
pub fn equilibria_json(
    rest: &RestEquations,
    set: &EquilibriumSet,
    lin: &[LinearizedResult],
) -> Value {
    json!({
        "schema": crate::SCHEMA,
        "coordinates": rest.coordinates,
        "angles": rest.periodic,
        "spinning": rest.spinning,
        "free": rest.coordinates.iter().zip(&rest.free).filter(|(_, f)| **f).map(|(q, _)| q.clone()).collect::<Vec<_>>(),
        "method": set.method.name(),
        "complete": set.method.complete(),
        "constraints": constraints_json(rest),
        "bounds": set.bounds.iter().map(|(a, b)| json!([a, b])).collect::<Vec<_>>(),
        "equilibria": equilibria_array(rest, set, lin),
    })
}

/// One `linearized` entry.
#[must_use]
pub fn linearized_entry(
    index: usize,
    rest: &RestEquations,
    values: &[f64],
    l: &Linearized,
    inputs: &[String],
) -> Value {
    let exact = l.exact.as_ref().map(|[m, c, k, b]| {
        json!({ "M0": exact_matrix(m), "C0": exact_matrix(c), "K0": exact_matrix(k), "B0": exact_matrix(b) })
    });
    json!({
        "equilibrium": index,
        "values": by_coordinate(&rest.coordinates, values),
        "inputs": inputs,
        "M0": matrix(&l.m0),
        "C0": matrix(&l.c0),
        "K0": matrix(&l.k0),
        "B0": matrix(&l.b0),
        "exact": exact,
        "A": matrix(&l.a),
        "B": matrix(&l.b),
        "omega_squared": l.omega_squared,
        "frequencies": l.frequencies(),
        "modes": l.modes,
        "damping_ratios": l.damping_ratios,
        "eigenvalues": eigen_pairs(&l.eigenvalues),
        "reduced": l.reduced.as_ref().map(|r| json!({
            "basis": r.basis,
            "M": matrix(&r.mass),
            "C": matrix(&r.damping),
            "K": matrix(&r.stiffness),
            "B": matrix(&r.input),
        })),
        "controllability_rank": l.controllability_rank,
        "state_dimension": l.a.len(),
        "stable": l.stable,
        "criterion": l.criterion.to_string(),
    })
}

/// The JSON of `lagrange linearize`.
#[must_use]
pub fn linearized_json(
    rest: &RestEquations,
    set: &EquilibriumSet,
    lin: &[LinearizedResult],
    inputs: &[String],
    only: Option<usize>,
) -> Value {
    let entries: Vec<Value> = set
        .equilibria
        .iter()
        .zip(lin)
        .enumerate()
        .filter(|(i, _)| only.is_none_or(|k| k == *i))
        .filter_map(|(i, (e, l))| {
            l.as_ref()
                .ok()
                .map(|l| linearized_entry(i, rest, &e.values, l, inputs))
        })
        .collect();
    json!({
        "schema": crate::SCHEMA,
        "coordinates": rest.coordinates,
        "method": set.method.name(),
        "complete": set.method.complete(),
        "linearized": entries,
    })
}

pub(crate) fn stability_word(s: Option<bool>) -> &'static str {
    match s {
        Some(true) => "stable",
        Some(false) => "unstable",
        None => "undecided by linearization",
    }
}

/// A number to six decimals, without the minus of a value that rounds to zero ("-0.000000").
#[must_use]
pub fn six(v: f64) -> String {
    let text = format!("{v:.6}");
    match text.strip_prefix('-') {
        Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_owned(),
        _ => text,
    }
}

/// `re±im i` to six decimals, a part that rounds to zero without its minus.
fn complex_six(re: f64, im: f64) -> String {
    let im_text = six(im);
    let sign = if im_text.starts_with('-') { "" } else { "+" };
    format!("{}{sign}{im_text}i", six(re))
}

fn point_text(rest: &RestEquations, values: &[f64], exact: Option<&Vec<Expr>>) -> String {
    rest.coordinates
        .iter()
        .enumerate()
        .map(|(i, q)| {
            if rest.free.get(i).copied().unwrap_or(false) {
                return format!("{q} = any (free; shown at {})", six(values[i]));
            }
            let exact = exact
                .and_then(|x| x.get(i))
                .map(|e| format!(" = {}", to_unicode(*e)))
                .unwrap_or_default();
            format!("{q}{exact} = {}", six(values[i]))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The text of `lagrange equilibria`.
#[must_use]
pub fn equilibria_text(
    rest: &RestEquations,
    set: &EquilibriumSet,
    lin: &[LinearizedResult],
) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "rest equations {} ({}):",
        if rest.constraints.is_some() {
            "f(q, 0) − A(q)ᵀλ = 0, Φ(q) = 0"
        } else {
            "f(q, 0) = 0"
        },
        if set.method.complete() {
            "solved exactly; this list is complete"
        } else {
            "solved numerically; completeness is not guaranteed"
        }
    );
    for (q, r) in rest.coordinates.iter().zip(&rest.residuals) {
        let _ = writeln!(out, "  [{q}]  0 = {}", to_unicode(*r));
    }
    if let Some(kept) = &rest.constraints {
        for ((name, symbol), f) in kept
            .names
            .iter()
            .zip(&kept.multipliers)
            .zip(&kept.functions)
        {
            let _ = writeln!(
                out,
                "  [{name}, {}]  0 = {}",
                to_unicode(*symbol),
                to_unicode(*f)
            );
        }
    }
    let _ = writeln!(out, "method: {}", set.method.name());
    if set.equilibria.is_empty() {
        let where_ = if set.method.complete() {
            "for these values"
        } else {
            "in the search box"
        };
        let _ = writeln!(out, "no equilibrium {where_}");
    }
    for (i, (e, l)) in set.equilibria.iter().zip(lin).enumerate() {
        let _ = writeln!(
            out,
            "\n#{i}: {}",
            point_text(rest, &e.values, e.exact.as_ref())
        );
        for c in &e.conditions {
            let _ = writeln!(out, "    exists when {}", condition_text(c, to_unicode));
        }
        let exact_multipliers = e.exact_multipliers.as_deref();
        for line in multipliers_text(rest, &e.multipliers, exact_multipliers) {
            let _ = writeln!(out, "    multiplier {line}");
        }
        for r in set.repeated.iter().filter(|r| r.same_as == i) {
            let other = point_text(rest, &r.values, None);
            let _ = writeln!(
                out,
                "    also at {other}: the coordinates reach this configuration twice"
            );
        }
        match l {
            Ok(l) => {
                let _ = writeln!(out, "    {} — {}", stability_word(l.stable), l.criterion);
                let eig: Vec<String> = l
                    .eigenvalues
                    .iter()
                    .map(|(re, im)| complex_six(*re, *im))
                    .collect();
                let _ = writeln!(out, "    eigenvalues: {}", eig.join(", "));
            }
            Err(err) => {
                let _ = writeln!(out, "    stability not decided: {err}");
            }
        }
    }
    out
}

fn matrix_text(name: &str, m: &[Vec<f64>]) -> String {
    let rows: Vec<String> = m
        .iter()
        .map(|r| {
            r.iter()
                .map(|v| format!("{v:>12.6}"))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect();
    format!("  {name} =\n    [{}]\n", rows.join("]\n    ["))
}

/// The linearization in independent coordinates `δq = N y` of a constrained system.
fn reduced_text(
    out: &mut String,
    rest: &RestEquations,
    r: &mechanics::linearize::Reduced,
    multipliers: &[f64],
    inputs: bool,
) {
    for line in multipliers_text(rest, multipliers, None) {
        let _ = writeln!(out, "  multiplier {line}");
    }
    let _ = writeln!(
        out,
        "  on the constraints: δq = N y, N an orthonormal basis of the null space of A(q0) \
         (K0 includes the constraints' curvature Σ λ ∂²Φ/∂q²)"
    );
    let columns: Vec<Vec<f64>> = (0..rest.coordinates.len())
        .map(|i| r.basis.iter().map(|u| u[i]).collect())
        .collect();
    out.push_str(&matrix_text("N", &columns));
    out.push_str(&matrix_text("NᵀM0N", &r.mass));
    out.push_str(&matrix_text("NᵀC0N", &r.damping));
    out.push_str(&matrix_text("NᵀK0N", &r.stiffness));
    if inputs {
        out.push_str(&matrix_text("NᵀB0", &r.input));
    }
}

/// The text of `lagrange linearize`.
#[must_use]
pub fn linearized_text(
    rest: &RestEquations,
    set: &EquilibriumSet,
    lin: &[LinearizedResult],
    inputs: &[String],
    only: Option<usize>,
) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "M0 δq̈ + C0 δq̇ + K0 δq = B0 δu,  δq = ({}),  δu = ({})",
        rest.coordinates.join(", "),
        inputs.join(", ")
    );
    for (i, (e, l)) in set.equilibria.iter().zip(lin).enumerate() {
        if only.is_some_and(|k| k != i) {
            continue;
        }
        let _ = writeln!(
            out,
            "\n#{i}: {}",
            point_text(rest, &e.values, e.exact.as_ref())
        );
        let l = match l {
            Ok(l) => l,
            Err(err) => {
                let _ = writeln!(out, "  not linearized: {err}");
                continue;
            }
        };
        if let Some([m, c, k, b]) = &l.exact {
            for (name, mat) in [("M0", m), ("C0", c), ("K0", k), ("B0", b)] {
                let rows: Vec<String> = mat
                    .iter()
                    .map(|r| {
                        r.iter()
                            .map(|e| to_unicode(*e))
                            .collect::<Vec<_>>()
                            .join(", ")
                    })
                    .collect();
                let _ = writeln!(out, "  {name} = [{}]", rows.join("; "));
            }
        }
        out.push_str(&matrix_text("M0", &l.m0));
        out.push_str(&matrix_text("C0", &l.c0));
        out.push_str(&matrix_text("K0", &l.k0));
        if !inputs.is_empty() {
            out.push_str(&matrix_text("B0", &l.b0));
        }
        if let Some(r) = &l.reduced {
            reduced_text(&mut out, rest, r, &e.multipliers, !inputs.is_empty());
        }
        let freqs: Vec<String> = l
            .frequencies()
            .iter()
            .zip(l.omega_squared.as_deref().unwrap_or(&[]))
            .map(|(f, w2)| match f {
                Some(w) => format!("{} rad/s", six(*w)),
                None => format!("none (ω² = {})", six(*w2)),
            })
            .collect();
        let _ = writeln!(out, "  natural frequencies: {}", freqs.join(", "));
        for (k, m) in l.modes.iter().enumerate() {
            let m: Vec<String> = m.iter().map(|v| six(*v)).collect();
            let _ = writeln!(out, "  mode {}: ({})", k + 1, m.join(", "));
        }
        if !l.damping_ratios.is_empty() {
            let z: Vec<String> = l.damping_ratios.iter().map(|v| six(*v)).collect();
            let _ = writeln!(out, "  damping ratios: {}", z.join(", "));
        }
        let eig: Vec<String> = l
            .eigenvalues
            .iter()
            .map(|(re, im)| complex_six(*re, *im))
            .collect();
        let _ = writeln!(out, "  eigenvalues of A: {}", eig.join(", "));
        if let Some(r) = l.controllability_rank {
            let _ = writeln!(
                out,
                "  controllability rank: {r} of {} ({})",
                l.a.len(),
                if r == l.a.len() {
                    "controllable"
                } else {
                    "not controllable"
                }
            );
        }
        let _ = writeln!(out, "  {} — {}", stability_word(l.stable), l.criterion);
    }
    out
}

/// One row of a parameter sweep.
#[derive(Clone, Debug)]
pub struct SweepRow {
    /// The parameter's value.
    pub value: f64,
    /// The equilibria and their linearizations at that value.
    pub set: EquilibriumSet,
    /// One per equilibrium.
    pub lin: Vec<LinearizedResult>,
}

/// The JSON of a sweep: `{"parameter", "sweep": [{"value", "equilibria": [...]}]}`.
#[must_use]
pub fn sweep_json(rest: &RestEquations, parameter: &str, rows: &[SweepRow]) -> Value {
    json!({
        "schema": crate::SCHEMA,
        "coordinates": rest.coordinates,
        "parameter": parameter,
        "sweep": rows.iter().map(|r| json!({
            "value": r.value,
            "method": r.set.method.name(),
            "equilibria": equilibria_array(rest, &r.set, &r.lin),
        })).collect::<Vec<_>>(),
    })
}

/// The bifurcation table of a sweep.
#[must_use]
pub fn sweep_text(rest: &RestEquations, parameter: &str, rows: &[SweepRow]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{parameter:>12}  equilibria ({}) : s = stable, u = unstable, ? = undecided",
        rest.coordinates.join(", ")
    );
    for r in rows {
        let cells: Vec<String> = r
            .set
            .equilibria
            .iter()
            .zip(&r.lin)
            .map(|(e, l)| {
                let mark = match l.as_ref().ok().and_then(|l| l.stable) {
                    Some(true) => "s",
                    Some(false) => "u",
                    None => "?",
                };
                let v: Vec<String> = e.values.iter().map(|v| format!("{v:.4}")).collect();
                format!("({}){mark}", v.join(", "))
            })
            .collect();
        let _ = writeln!(out, "{:>12.6}  {}", r.value, cells.join("  "));
    }
    out
}

/// One term of a free response: a coefficient times a function of time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Wave {
    /// `cos(ω t)`.
    Cos(f64),
    /// `sin(ω t)`.
    Sin(f64),
    /// `cosh(γ t)` (a divergent mode, `ω² = −γ²`).
    Cosh(f64),
    /// `sinh(γ t)`.
    Sinh(f64),
    /// `1` (a neutral mode's offset).
    One,
    /// `t` (a neutral mode's drift).
    Time,
}

/// `δq_i(t) = Σ c · wave(t)` for every coordinate, from the modes: `None` when the response has
/// no closed form here (damped systems).
#[must_use]
pub fn free_response_waves(
    l: &Linearized,
    dq0: &[f64],
    dv0: &[f64],
) -> Option<Vec<Vec<(f64, Wave)>>> {
    let terms = l.modal_terms(dq0, dv0)?;
    let n = l.m0.len();
    let scale = dq0.iter().chain(dv0).fold(0.0_f64, |a, v| a.max(v.abs()));
    let tiny = 1e-14 * scale.max(f64::MIN_POSITIVE);
    Some(
        (0..n)
            .map(|i| {
                let mut parts = Vec::new();
                for term in &terms {
                    let a = term.shape[i] * term.a;
                    let b = term.shape[i] * term.b;
                    let w2 = term.omega_squared;
                    let tol = 1e-12 * w2.abs().max(1.0);
                    let pair = if w2 > tol {
                        let w = w2.sqrt();
                        [(a, Wave::Cos(w)), (b / w, Wave::Sin(w))]
                    } else if w2 < -tol {
                        let g = (-w2).sqrt();
                        [(a, Wave::Cosh(g)), (b / g, Wave::Sinh(g))]
                    } else {
                        [(a, Wave::One), (b, Wave::Time)]
                    };
                    parts.extend(pair.into_iter().filter(|(c, _)| c.abs() > tiny));
                }
                parts
            })
            .collect(),
    )
}

/// `δq_i(t)` in closed form, one SymPy-syntax string per coordinate (`t` is time); `None`
/// when the response has no closed form here (damped systems).
fn free_response_formulas(l: &Linearized, dq0: &[f64], dv0: &[f64]) -> Option<Vec<String>> {
    let waves = free_response_waves(l, dq0, dv0)?;
    Some(
        waves
            .into_iter()
            .map(|parts| {
                if parts.is_empty() {
                    return "0".to_string();
                }
                parts
                    .iter()
                    .map(|(c, wave)| {
                        let f = match wave {
                            Wave::Cos(w) => format!("cos({w:.12}*t)"),
                            Wave::Sin(w) => format!("sin({w:.12}*t)"),
                            Wave::Cosh(g) => format!("cosh({g:.12}*t)"),
                            Wave::Sinh(g) => format!("sinh({g:.12}*t)"),
                            Wave::One => "1".to_string(),
                            Wave::Time => "t".to_string(),
                        };
                        format!("{c:.12e}*{f}")
                    })
                    .collect::<Vec<_>>()
                    .join(" + ")
            })
            .collect(),
    )
}

/// The free response as JSON: `{coordinate: formula}` (SymPy syntax in `t`), or `null` for a
/// damped system.
#[must_use]
pub fn free_response_json(rest: &RestEquations, l: &Linearized, dq0: &[f64], dv0: &[f64]) -> Value {
    match free_response_formulas(l, dq0, dv0) {
        Some(f) => by_coordinate(&rest.coordinates, &f),
        None => Value::Null,
    }
}

/// The free response as text, one line per coordinate.
#[must_use]
pub fn free_response_text(
    rest: &RestEquations,
    l: &Linearized,
    dq0: &[f64],
    dv0: &[f64],
) -> String {
    match free_response_formulas(l, dq0, dv0) {
        Some(f) => rest
            .coordinates
            .iter()
            .zip(f)
            .map(|(q, f)| format!("  δ{q}(t) = {f}\n"))
            .collect(),
        None => "  (no closed form here: the linearization is damped)\n".to_string(),
    }
}

/// [`linearized_json`] with the free response from initial deviations `(δq₀, δq̇₀)` about
/// each equilibrium shown, when given.
#[must_use]
pub fn linearized_json_with_response(
    rest: &RestEquations,
    set: &EquilibriumSet,
    lin: &[LinearizedResult],
    inputs: &[String],
    only: Option<usize>,
    deviations: Option<(&[f64], &[f64])>,
) -> Value {
    let mut value = linearized_json(rest, set, lin, inputs, only);
    if let (Some((dq, dv)), Some(list)) = (deviations, value["linearized"].as_array_mut()) {
        for entry in list {
            let i = entry["equilibrium"].as_u64().unwrap_or(0) as usize;
            if let Some(Ok(l)) = lin.get(i) {
                entry["free_response"] = free_response_json(rest, l, dq, dv);
            }
        }
    }
    value
}

/// [`linearized_text`] followed by the free response about each equilibrium shown, when
/// initial deviations are given.
#[must_use]
pub fn linearized_text_with_response(
    rest: &RestEquations,
    set: &EquilibriumSet,
    lin: &[LinearizedResult],
    inputs: &[String],
    only: Option<usize>,
    deviations: Option<(&[f64], &[f64])>,
) -> String {
    let mut text = linearized_text(rest, set, lin, inputs, only);
    if let Some((dq, dv)) = deviations {
        for (i, l) in lin.iter().enumerate() {
            if only.is_some_and(|k| k != i) {
                continue;
            }
            if let Ok(l) = l {
                text.push_str(&format!("\nfree response about #{i}:\n"));
                text.push_str(&free_response_text(rest, l, dq, dv));
            }
        }
    }
    text
}

/// The points of a bifurcation diagram: every equilibrium's coordinates at every step of a
/// sweep, with its stability.
#[must_use]
pub fn bifurcation_points(rows: &[SweepRow]) -> Vec<crate::BifurcationPoint> {
    rows.iter()
        .flat_map(|row| {
            row.set
                .equilibria
                .iter()
                .zip(&row.lin)
                .flat_map(move |(e, l)| {
                    let stable = l.as_ref().ok().and_then(|l| l.stable);
                    e.values
                        .iter()
                        .enumerate()
                        .map(move |(k, v)| crate::BifurcationPoint {
                            parameter: row.value,
                            coordinate: k,
                            value: *v,
                            stable,
                        })
                })
        })
        .collect()
}
