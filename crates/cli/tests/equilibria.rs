//! `lagrange equilibria` and `lagrange linearize` on the command line: JSON keys, sweeps,
//! errors, one equilibrium by index, every example answered.

use lagrange::cas::{self, Symbol};

mod common;
use common::run;

#[test]
fn equilibria_json_has_the_documented_keys() {
    let (ok, text, _) = run(&[
        "equilibria",
        "examples/bead-on-rotating-hoop.lag",
        "--format",
        "json",
    ]);
    assert!(ok);
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["schema"], 1);
    assert_eq!(v["complete"], true);
    let list = v["equilibria"].as_array().unwrap();
    assert_eq!(list.len(), 4);
    for e in list {
        assert!(e["values"]["theta"].is_number());
        assert!(e["exact"]["theta"].is_string());
        assert!(e["stable"].is_boolean());
        assert!(e["criterion"].is_string());
        assert!(e["eigenvalues"][0].as_array().unwrap().len() == 2);
    }
}

#[test]
fn linearize_json_has_the_documented_keys() {
    let (ok, text, _) = run(&[
        "linearize",
        "examples/seed/7.4-inverted-pendulum.lag",
        "--format",
        "json",
    ]);
    assert!(ok);
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let list = v["linearized"].as_array().unwrap();
    assert_eq!(list.len(), 2);
    for (i, e) in list.iter().enumerate() {
        assert_eq!(e["equilibrium"], i);
        for key in ["M0", "C0", "K0", "B0", "A", "B"] {
            assert!(e[key].is_array(), "{key}");
        }
        assert_eq!(e["frequencies"].as_array().unwrap().len(), 2);
        assert_eq!(e["controllability_rank"], 4);
    }
}

#[test]
fn sweep_prints_the_bifurcation_table() {
    let (ok, text, _) = run(&[
        "equilibria",
        "examples/bead-on-rotating-hoop.lag",
        "--sweep",
        "Omega=2..8",
        "--steps",
        "6",
    ]);
    assert!(ok);
    let rows: Vec<&str> = text.lines().skip(1).collect();
    assert_eq!(rows.len(), 7);
    // Ω = 2, 3, 4: bottom stable, two equilibria; Ω = 5…8 (Ω² R > g): four.
    assert!(rows[0].contains("(0.0000)s") && rows[0].matches('(').count() == 2);
    assert!(rows[6].contains("(0.0000)u") && rows[6].matches('(').count() == 4);
}

#[test]
fn unsupported_models_fail_with_a_clear_error() {
    let (ok, _, err) = run(&["equilibria", "examples/driven-pivot-pendulum.lag"]);
    assert!(!ok);
    assert!(err.contains("depend on time"));
    // A non-holonomic constraint kept by a multiplier does not fix the configuration.
    let (ok, _, err) = run(&["equilibria", "examples/knife-edge.lag"]);
    assert!(!ok);
    assert!(
        err.contains("non-holonomic") && err.contains("not supported"),
        "{err}"
    );
    let (ok, _, err) = run(&[
        "equilibria",
        "examples/simple-pendulum.lag",
        "--set",
        "nope=1",
    ]);
    assert!(!ok);
    assert!(err.contains("nope"));
    let (ok, _, err) = run(&[
        "equilibria",
        "examples/simple-pendulum.lag",
        "--sweep",
        "g=3",
    ]);
    assert!(!ok);
    assert!(err.contains("NAME=A..B"));
}

#[test]
fn linearize_one_equilibrium_keeps_its_index() {
    let (ok, text, _) = run(&[
        "linearize",
        "examples/seed/7.1-cart-pendulum.lag",
        "--format",
        "json",
        "--equilibrium",
        "1",
    ]);
    assert!(ok);
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let list = v["linearized"].as_array().unwrap();
    assert_eq!(list.len(), 1);
    assert_eq!(list[0]["equilibrium"], 1);
    let (ok, _, err) = run(&[
        "linearize",
        "examples/seed/7.1-cart-pendulum.lag",
        "--equilibrium",
        "9",
    ]);
    assert!(!ok);
    assert!(err.contains("there are 2 equilibria"));
}

/// Compares with SymPy's `LagrangesMethod` on independent models
/// (`tools/sympy_reference/equilibria.sh` → `tests/data/equilibria/*.json`).
#[test]
fn every_example_gets_an_answer_or_a_clear_error() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../");
    let mut files = Vec::new();
    for dir in ["examples", "examples/seed"] {
        for entry in std::fs::read_dir(format!("{root}{dir}")).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "lag") {
                files.push(path.display().to_string());
            }
        }
    }
    assert!(files.len() > 10);
    for f in &files {
        for command in ["equilibria", "linearize"] {
            // The Whipple bicycle is the model Lagrange's route cannot derive (issue 18):
            // `equilibria` would expand its equations; `linearize` goes by Kane's method.
            if command == "equilibria" && f.ends_with("whipple-bicycle.lag") {
                continue;
            }
            let (ok, out, err) = run(&[command, f, "--format", "json"]);
            assert!(!err.contains("panicked"), "{command} {f}: {err}");
            if ok {
                serde_json::from_str::<serde_json::Value>(&out).expect("valid JSON");
            } else {
                assert!(err.starts_with("error: "), "{command} {f}: {err}");
            }
        }
    }
}

#[test]
fn free_response_formula_matches_the_modal_sum() {
    let (ok, text, _) = run(&[
        "linearize",
        "examples/seed/7.1-cart-pendulum.lag",
        "--format",
        "json",
        "--equilibrium",
        "0",
        "--initial",
        "x=0.01",
        "--initial",
        "theta'=0.1",
    ]);
    assert!(ok);
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let response = &v["linearized"][0]["free_response"];
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/seed/7.1-cart-pendulum.lag"
    );
    let analysis = lagrange::Analysis::from_file(std::path::Path::new(path)).unwrap();
    let lin = &analysis.equilibria().unwrap().linearized;
    for t in [0.0, 0.7, 2.3] {
        let expected = lin[0]
            .as_ref()
            .unwrap()
            .free_response(&[0.01, 0.0], &[0.0, 0.1], t)
            .unwrap();
        for (i, q) in ["x", "theta"].iter().enumerate() {
            let formula = response[q].as_str().unwrap();
            let e = cas::parse(formula, &cas::ParseContext::new()).unwrap();
            let value = e.eval(&|s: Symbol| (s.name() == "t").then_some(t)).unwrap();
            assert!(
                (value - expected[i]).abs() < 1e-9,
                "{q}({t}): {value} vs {}",
                expected[i]
            );
        }
    }
    // Initial conditions hold.
    let e = cas::parse(response["x"].as_str().unwrap(), &cas::ParseContext::new()).unwrap();
    assert!(
        (e.eval(&|s: Symbol| (s.name() == "t").then_some(0.0))
            .unwrap()
            - 0.01)
            .abs()
            < 1e-12
    );
}
