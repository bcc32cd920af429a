//! Issue 17: `equilibria` and `linearize` refused every model with constraints kept by
//! multipliers ("not supported yet"). They now solve the KKT system `f(q, 0) − Aᵀλ = 0`,
//! `Φ(q) = 0` for `q` and `λ` and linearize in independent coordinates (the null space `N`
//! of `A`, the stiffness with the constraints' curvature). Checked here against an independent
//! reference, `tools/kkt_reference/kkt_reference.py`: each system stated by hand and solved
//! with SciPy, its results checked in as `tests/data/kkt_*.json`; and one case exactly (the
//! pendulum in Cartesian coordinates: `λ = m g/(2 ℓ)` at the bottom, `ω² = g/ℓ`).

use std::path::PathBuf;

use lagrange::Analysis;
use serde_json::Value;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn reference(model: &str) -> Value {
    let path = root().join(format!("crates/lagrange/tests/data/kkt_{model}.json"));
    let text = std::fs::read_to_string(&path).expect("reference data");
    serde_json::from_str(&text).expect("reference JSON")
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

fn angle_difference(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()))
}

/// Every equilibrium of the reference is found once, with the same multipliers, reduced `ω²`
/// and verdict, and no other.
fn agrees_with_reference(model: &str) {
    let data = reference(model);
    let analysis = Analysis::from_file(&root().join(format!("examples/{model}.lag"))).unwrap();
    let found = analysis.equilibria().unwrap();
    let expected = data["equilibria"].as_array().unwrap();
    assert_eq!(
        found.set.equilibria.len(),
        expected.len(),
        "{}",
        found.to_text()
    );
    for e in expected {
        let q = numbers(&e["q"]);
        let position = found.set.equilibria.iter().position(|f| {
            f.values
                .iter()
                .zip(&q)
                .zip(&found.rest.periodic)
                .all(|((a, b), p)| {
                    let d = if *p {
                        angle_difference(*a, *b)
                    } else {
                        (a - b).abs()
                    };
                    d <= 1e-9 * (1.0 + b.abs())
                })
        });
        let i = position.unwrap_or_else(|| panic!("{model}: no equilibrium at {q:?}"));
        let ours = &found.set.equilibria[i];
        for (a, b) in ours.multipliers.iter().zip(numbers(&e["lambda"])) {
            assert!(close(*a, b), "{model} at {q:?}: λ = {a}, reference {b}");
        }
        let lin = found.linearized[i].as_ref().unwrap();
        let w2 = lin.omega_squared.as_ref().unwrap();
        let reference_w2 = numbers(&e["omega_squared"]);
        assert_eq!(w2.len(), reference_w2.len());
        for (a, b) in w2.iter().zip(&reference_w2) {
            assert!(close(*a, *b), "{model} at {q:?}: ω² = {a}, reference {b}");
        }
        assert_eq!(
            lin.stable,
            Some(e["stable"].as_bool().unwrap()),
            "{model} at {q:?}"
        );
        // The modes are shown in all the coordinates and satisfy the constraints to first
        // order: A(q0) φ = 0.
        let kept = found.rest.constraints.as_ref().unwrap();
        let values: lagrange::mechanics::equilibria::Values =
            analysis.values().unwrap().into_iter().collect();
        let a = kept
            .gradient_at(&found.rest, &ours.values, &values)
            .unwrap();
        for mode in &lin.modes {
            assert_eq!(mode.len(), q.len());
            for row in &a {
                let dot: f64 = row.iter().zip(mode).map(|(x, y)| x * y).sum();
                assert!(dot.abs() < 1e-9, "{model}: A φ = {dot}");
            }
        }
    }
}

#[test]
fn four_bar_equilibria_multipliers_and_frequencies_match_the_scipy_reference() {
    agrees_with_reference("four-bar");
}

#[test]
fn slider_crank_equilibria_multipliers_and_frequencies_match_the_scipy_reference() {
    agrees_with_reference("slider-crank");
}

#[test]
fn cartesian_pendulum_matches_the_scipy_reference() {
    agrees_with_reference("cartesian-pendulum");
}

#[test]
fn the_cartesian_pendulum_is_solved_exactly() {
    let analysis = Analysis::from_file(&root().join("examples/cartesian-pendulum.lag")).unwrap();
    let found = analysis.equilibria().unwrap();
    assert_eq!(
        found.set.method,
        lagrange::mechanics::equilibria::Method::Exact
    );
    let bottom = found
        .set
        .equilibria
        .iter()
        .position(|e| e.values[1] < 0.0)
        .unwrap();
    let e = &found.set.equilibria[bottom];
    let exact = e.exact_multipliers.as_ref().unwrap();
    // λ = m g √(ℓ²)/(2 ℓ²): m g/(2 ℓ) for ℓ > 0 — the rod's tension 2 ℓ λ = m g.
    let (m, g, l) = (
        lagrange::cas::Expr::symbol("m"),
        lagrange::cas::Expr::symbol("g"),
        lagrange::cas::Expr::symbol("l"),
    );
    let expected = m * g * l.powi(2).sqrt() / (2 * l.powi(2));
    assert!((exact[0] - expected).is_zero(), "λ = {}", exact[0]);
    assert!(close(e.multipliers[0], 9.81 / 2.0));
    let lin = found.linearized[bottom].as_ref().unwrap();
    assert!(close(lin.omega_squared.as_ref().unwrap()[0], 9.81));
    assert_eq!(lin.stable, Some(true));
    // Another length and mass: the same closed forms.
    let mut other = analysis.clone();
    other.set_value("l", 2.5).unwrap();
    other.set_value("m", 3.0).unwrap();
    let found = other.equilibria().unwrap();
    let e = found
        .set
        .equilibria
        .iter()
        .position(|e| e.values[1] < 0.0)
        .unwrap();
    assert!(close(
        found.set.equilibria[e].multipliers[0],
        3.0 * 9.81 / 5.0
    ));
    let w2 = found.linearized[e]
        .as_ref()
        .unwrap()
        .omega_squared
        .clone()
        .unwrap();
    assert!(close(w2[0], 9.81 / 2.5));
}

#[test]
fn the_unbalanced_atwood_machine_has_no_equilibrium_for_certain() {
    let data = reference("atwood-machine");
    // The reference's linear KKT system is inconsistent (a non-zero least-squares residual).
    assert!(data["least_squares_residual"].as_f64().unwrap() > 0.1);
    assert!(data["equilibria"].as_array().unwrap().is_empty());
    let analysis = Analysis::from_file(&root().join("examples/atwood-machine.lag")).unwrap();
    let found = analysis.equilibria().unwrap();
    assert!(found.set.equilibria.is_empty());
    // Exactly: every choice of the rows that give λ leaves `(m1 − m2) g`-like equations.
    assert!(found.set.method.complete(), "{}", found.to_text());
}

#[test]
fn the_free_response_stays_on_the_constraints() {
    let analysis = Analysis::from_file(&root().join("examples/four-bar.lag")).unwrap();
    let found = analysis.equilibria().unwrap();
    let i = found
        .linearized
        .iter()
        .position(|l| l.as_ref().is_ok_and(|l| l.stable == Some(true)))
        .unwrap();
    let lin = found.linearized[i].as_ref().unwrap();
    let mode = &lin.modes[0];
    let w = lin.omega_squared.as_ref().unwrap()[0].sqrt();
    // Started along the mode, the response is the mode times cos ωt.
    let dq0: Vec<f64> = mode.iter().map(|x| 0.01 * x).collect();
    let t = 0.3;
    let response = lin.free_response(&dq0, &[0.0; 3], t).unwrap();
    for (r, x) in response.iter().zip(&dq0) {
        assert!(
            (r - x * (w * t).cos()).abs() < 1e-12,
            "{r} vs {}",
            x * (w * t).cos()
        );
    }
}

#[test]
fn equilibria_and_linearize_print_the_multipliers_by_constraint() {
    let analysis = Analysis::from_file(&root().join("examples/four-bar.lag")).unwrap();
    let found = analysis.equilibria().unwrap();
    let text = found.to_text();
    assert!(text.contains("multiplier λ1 (loop_x) = "), "{text}");
    assert!(text.contains("[loop_y, λ2]  0 = "), "{text}");
    let json = found.to_json();
    assert_eq!(
        json["equilibria"][0]["multipliers"][1]["constraint"],
        "loop_y"
    );
    assert_eq!(json["constraints"][0]["multiplier"], "lambda1");
    let linearized = found.linearized_json(None, None);
    let reduced = &linearized["linearized"][0]["reduced"];
    assert_eq!(reduced["basis"].as_array().unwrap().len(), 1);
    assert_eq!(reduced["K"].as_array().unwrap().len(), 1);
}

#[test]
fn the_modes_of_a_closed_loop_animate() {
    for model in ["four-bar", "slider-crank"] {
        let analysis = Analysis::from_file(&root().join(format!("examples/{model}.lag"))).unwrap();
        let page = analysis.mode_animation(1, None, 10.0, &[]).unwrap();
        assert!(
            page.contains("<html") || page.contains("<!DOCTYPE"),
            "{model}"
        );
        // One degree of freedom: one mode.
        let error = analysis.mode_animation(2, None, 10.0, &[]).unwrap_err();
        assert!(error.to_string().contains("1 mode(s)"), "{model}: {error}");
    }
}
