//! `lagrange eom` on the seed's 7.1, as text and as JSON.

use std::process::Command;

fn run(args: &[&str]) -> (bool, String) {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let out = Command::new(env!("CARGO_BIN_EXE_lagrange"))
        .args(args)
        .current_dir(root)
        .output()
        .expect("runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
    )
}

#[test]
fn eom_prints_the_seed_equations() {
    let (ok, text) = run(&["eom", "examples/seed/7.1-cart-pendulum.lag"]);
    assert!(ok);
    assert!(text.contains("(m_A + m_B) ẍ + m_B ℓ θ̈ cos θ − m_B ℓ θ̇² sin θ + k x = F"));
}

#[test]
fn eom_json_has_the_schema_keys() {
    let (ok, text) = run(&[
        "eom",
        "examples/seed/7.1-cart-pendulum.lag",
        "--format",
        "json",
    ]);
    assert!(ok);
    let value: serde_json::Value = serde_json::from_str(&text).expect("json");
    assert_eq!(value["schema"], 1);
    for key in [
        "coordinates",
        "parameters",
        "kinetic_energy",
        "potential_energy",
        "lagrangian",
        "generalized_forces",
        "mass_matrix",
        "forcing",
        "first_integrals",
    ] {
        assert!(value.get(key).is_some(), "missing {key}");
    }
    assert_eq!(value["coordinates"], serde_json::json!(["x", "theta"]));
}
