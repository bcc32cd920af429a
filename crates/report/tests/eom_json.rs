//! The eom JSON on every example model: every expression string reads back (lagrange's own
//! reader) and the explicit accelerations and their adjugate form are right by numbers
//! (`M q̈ = f`, `adj(M) M = Δ I` at pseudo-random states); issue 23's double pendulum of two
//! off-axis rigid bodies gets accelerations under 2,000 characters.
//!
//! With `LAGRANGE_JSON_NUMBERS=DIR` set, every string's value at those states is written to
//! `DIR/<model>.json` for `tools/json_sympy/check.py`, which checks that SymPy reads each
//! string to the same number; with `LAGRANGE_JSON_MODELS=DIR`, the `*.lag` files in `DIR`
//! are checked beside the examples (check.sh puts generated models there).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use cas::print::to_sympy;
use cas::{parse, Expr, Node, ParseContext, Symbol};
use serde_json::{json, Value};

fn examples() -> Vec<PathBuf> {
    fn walk(dir: &Path, found: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).expect("examples").flatten() {
            let path = entry.path();
            if path.is_dir() {
                walk(&path, found);
            } else if path.extension().is_some_and(|e| e == "lag")
                && !path.ends_with("whipple-bicycle.lag")
            {
                // (The Whipple bicycle's equations are Kane's, evaluated, not printed: issue 18.)
                found.push(path);
            }
        }
    }
    let mut found = Vec::new();
    walk(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples"),
        &mut found,
    );
    // More models, such as the generated ones tools/json_sympy/check.sh writes.
    if let Some(extra) = std::env::var_os("LAGRANGE_JSON_MODELS") {
        walk(Path::new(&extra), &mut found);
    }
    found.sort();
    found
}

fn eom(source: &str) -> Option<(Value, Vec<String>)> {
    let model = model::load(source).ok()?;
    let system = model::lower(&model).ok()?;
    let equations = mechanics::derive(&system).ok()?;
    Some((
        report::eom_json(&system, &equations),
        equations.coordinates().to_vec(),
    ))
}

/// Every string in `v`, with its JSON pointer.
fn strings(v: &Value, at: &str, out: &mut Vec<(String, String)>) {
    match v {
        Value::String(s) => out.push((at.to_string(), s.clone())),
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                strings(x, &format!("{at}/{i}"), out);
            }
        }
        Value::Object(o) => {
            for (k, x) in o {
                strings(x, &format!("{at}/{k}"), out);
            }
        }
        _ => {}
    }
}

/// Keys whose strings are names or prose, not expressions.
fn is_expression(pointer: &str) -> bool {
    let last = pointer.rsplit('/').next().unwrap_or("");
    !(pointer.starts_with("/coordinates/")
        || pointer == "/accelerations_note"
        || ["name", "kind", "coordinate", "constraint"].contains(&last))
}

/// A value in `[0.35, 1.65]` from a symbol's name, order and a round.
fn sample(s: Symbol, round: u64) -> f64 {
    let mut h: u64 = 0x9e37_79b9_7f4a_7c15 ^ round.wrapping_mul(0xcbf2_9ce4_8422_2325);
    for b in s.name().bytes().chain([s.order()]) {
        h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
    }
    0.35 + 1.3 * ((h >> 11) as f64 / (1u64 << 53) as f64)
}

/// The symbols `e` contains.
fn symbols_of(e: Expr, out: &mut Vec<Symbol>) {
    match e.node() {
        Node::Symbol(s) => {
            if !out.contains(s) {
                out.push(*s);
            }
        }
        _ => {
            for c in e.children() {
                symbols_of(*c, out);
            }
        }
    }
}

fn value(e: Expr, round: u64) -> Option<f64> {
    e.eval(&|s| Some(sample(s, round)))
        .ok()
        .filter(|v| v.is_finite())
}

fn read(text: &str, coordinates: &[String]) -> Expr {
    let ctx = ParseContext::new().with_coordinates(coordinates);
    parse(text, &ctx).unwrap_or_else(|e| panic!("`{text}` does not read back: {e:?}"))
}

fn at(json: &Value, pointer: &str, coordinates: &[String]) -> Expr {
    let text = json
        .pointer(pointer)
        .and_then(Value::as_str)
        .unwrap_or_else(|| panic!("no string at {pointer}"));
    read(text, coordinates)
}

/// `M q̈ = f` and `adj(M) M = Δ I` by numbers.
fn check_accelerations(name: &str, json: &Value, coordinates: &[String]) {
    let n = coordinates.len();
    let mass = |i: usize, j: usize| at(json, &format!("/mass_matrix/{i}/{j}"), coordinates);
    for round in 0..3 {
        let v = |e: Expr| value(e, round);
        if json["accelerations"].is_array() {
            for i in 0..n {
                let f = v(at(json, &format!("/forcing/{i}"), coordinates));
                let mq: Option<f64> = (0..n)
                    .map(|j| {
                        let a = at(json, &format!("/accelerations/{j}"), coordinates);
                        Some(v(mass(i, j))? * v(a)?)
                    })
                    .sum();
                if let (Some(f), Some(mq)) = (f, mq) {
                    assert!(
                        (f - mq).abs() <= 1e-8 * (1.0 + f.abs()),
                        "{name}: row {i}: M q̈ = {mq}, f = {f}"
                    );
                }
            }
        }
        if json["acceleration_form"].is_object() {
            let det = v(at(json, "/acceleration_form/determinant", coordinates));
            for i in 0..n {
                for k in 0..n {
                    let p: Option<f64> = (0..n)
                        .map(|j| {
                            let a = at(
                                json,
                                &format!("/acceleration_form/adjugate/{i}/{j}"),
                                coordinates,
                            );
                            Some(v(a)? * v(mass(j, k))?)
                        })
                        .sum();
                    let want = det.map(|d| if i == k { d } else { 0.0 });
                    if let (Some(p), Some(want)) = (p, want) {
                        assert!(
                            (p - want).abs() <= 1e-8 * (1.0 + want.abs()),
                            "{name}: (adj M)[{i}][{k}] = {p}, want {want}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn every_string_reads_back_and_the_accelerations_are_right() {
    let dump = std::env::var_os("LAGRANGE_JSON_NUMBERS").map(PathBuf::from);
    let mut checked = 0;
    for path in examples() {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let source = std::fs::read_to_string(&path).unwrap();
        let Some((json, coordinates)) = eom(&source) else {
            continue;
        };
        let mut all = Vec::new();
        strings(&json, "", &mut all);
        let mut values = Vec::new();
        let mut symbols = BTreeMap::new();
        for (pointer, text) in all.iter().filter(|(p, _)| is_expression(p)) {
            let e = read(text, &coordinates);
            // Printing what was read gives the string back: nothing is lost in print.
            assert_eq!(&to_sympy(e), text, "{name}{pointer}");
            let mut found = Vec::new();
            symbols_of(e, &mut found);
            for s in found {
                for round in 0..3 {
                    symbols.insert(
                        format!("{}#{round}", to_sympy(Expr::from_symbol(s))),
                        sample(s, round),
                    );
                }
            }
            let v: Vec<Option<f64>> = (0..3).map(|r| value(e, r)).collect();
            values.push(json!({ "pointer": pointer, "text": text, "values": v }));
        }
        check_accelerations(&name, &json, &coordinates);
        if let Some(dir) = &dump {
            let out = json!({ "model": name, "symbols": symbols, "expressions": values });
            std::fs::create_dir_all(dir).unwrap();
            let file = dir.join(format!(
                "{}.json",
                path.display().to_string().replace(['/', '.'], "_")
            ));
            std::fs::write(file, serde_json::to_string_pretty(&out).unwrap()).unwrap();
        }
        checked += 1;
    }
    assert!(checked > 15, "{checked} examples checked");
}

/// Issue 23: a double pendulum of two rigid bodies with mass centres off their axes.
const OFF_AXIS: &str = "
coordinates th1, th2
parameters m1 = 1, m2 = 1, l1 = 1, a = 1/2, b = 1/2, c = 1/5, e = 1/10, J1 = 1/10, Jz = 1/10, g = 981/100
frame N
frame B1 = N rotated th1 about z
frame B2 = B1 rotated th2 about z
point G1 = a*B1.x + e*B1.y
point P1 = l1*B1.x
point G2 = P1 + b*B2.x + c*B2.y
body rb1 mass m1 at G1 frame B1 inertia 1, 1, J1
body rb2 mass m2 at G2 frame B2 inertia 1, 1, Jz
gravity -g*N.y
";

#[test]
fn off_axis_bodies_get_small_explicit_accelerations() {
    let (json, coordinates) = eom(OFF_AXIS).expect("derives");
    let accelerations = json["accelerations"]
        .as_array()
        .expect("explicit accelerations");
    for a in accelerations {
        let a = a.as_str().unwrap();
        assert!(a.len() < 2000, "{} characters", a.len());
    }
    assert!(json["acceleration_form"]["determinant"].is_string());
    assert!(json["accelerations_note"].is_null());
    check_accelerations("off-axis", &json, &coordinates);
}

#[test]
fn constrained_systems_get_a_note_instead() {
    let source = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/canonical/four-bar.lag"),
    )
    .unwrap();
    let (json, _) = eom(&source).expect("derives");
    assert!(json["accelerations"].is_null());
    assert!(json["acceleration_form"].is_null());
    assert!(json["accelerations_note"]
        .as_str()
        .is_some_and(|n| n.contains("multipliers")));
}
