//! `lagrange reactions`: text and JSON on the examples, and errors.

mod common;
use common::run_code as run;

#[test]
fn the_sphere_is_left_at_two_thirds() {
    let (code, text, _) = run(&["reactions", "examples/particle-on-sphere.lag"]);
    assert_eq!(code, Some(0));
    assert!(text.contains("N = m (−r θ̇² + g cos θ)"), "{text}");
    assert!(text.contains("agree exactly"), "{text}");
    // From θ₀ = 0.01 at rest: cos θ = (2/3) cos θ₀ = 0.666633.
    assert!(text.contains("cos = 0.666633"), "{text}");
}

#[test]
fn json_lists_reactions_with_components_and_methods() {
    let (code, text, _) = run(&[
        "reactions",
        "examples/seed/7.4-inverted-pendulum.lag",
        "--format",
        "json",
    ]);
    assert_eq!(code, Some(0));
    let value: serde_json::Value = serde_json::from_str(&text).expect("json");
    assert_eq!(value["schema"], 1);
    let hinge = &value["reactions"][0];
    assert_eq!(hinge["name"], "hinge_A");
    assert_eq!(hinge["kind"], "hinge");
    assert_eq!(hinge["point"]["name"], "A");
    assert_eq!(hinge["bodies"], serde_json::json!(["rod"]));
    assert_eq!(hinge["components"].as_array().map(Vec::len), Some(3));
    assert_eq!(
        hinge["methods"],
        serde_json::json!(["lagrange_1", "newton_euler"])
    );
    assert_eq!(hinge["agreement"], "exact");
    // The components read back as SymPy expressions: no Unicode.
    let x = hinge["components"][0].as_str().expect("string");
    assert!(x.contains("theta_d") && !x.contains('θ'), "{x}");
}

#[test]
fn every_example_with_reactions_runs() {
    for model in [
        "examples/seed/7.1-cart-pendulum.lag",
        "examples/seed/7.2-rolling-cone.lag",
        "examples/seed/7.3-gears-pendulum.lag",
        "examples/atwood-machine.lag",
        "examples/bead-on-rotating-hoop.lag",
        "examples/cart-with-mast.lag",
        "examples/driven-pivot-pendulum.lag",
        "examples/particle-on-sphere.lag",
        "examples/seed/7.4-inverted-pendulum.lag",
        "examples/cartesian-pendulum.lag",
        "examples/double-pendulum.lag",
        "examples/knife-edge.lag",
        "examples/ladder.lag",
        "examples/rolling-disk-incline.lag",
        "examples/simple-pendulum.lag",
    ] {
        let (code, text, err) = run(&["reactions", model]);
        assert_eq!(code, Some(0), "{model}: {err}");
        assert!(!text.contains("DISAGREE"), "{model}: {text}");
    }
}

#[test]
fn a_model_without_reactions_is_an_error() {
    let (code, _, err) = run(&["reactions", "examples/spherical-pendulum.lag"]);
    assert_eq!(code, Some(1));
    assert!(err.contains("asks for no reaction"), "{err}");
}

#[test]
fn a_zero_normal_is_an_error_with_its_position() {
    let dir = std::env::temp_dir().join(format!("lagrange-reactions-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join("zero-normal.lag");
    std::fs::write(
        &file,
        "coordinates theta\nparameters m = 1, r = 1, g = 9.81\nframe N\n\
         point P = r*sin(theta)*N.x + r*cos(theta)*N.y\nparticle P mass m\ngravity -g*N.y\n\
         reaction n: contact P on P normal 0*N.x\n",
    )
    .expect("write");
    let path = file.to_string_lossy().into_owned();
    let (code, _, err) = run(&["reactions", &path]);
    assert_eq!(code, Some(1));
    assert!(err.contains("zero-normal.lag:7:35"), "{err}");
    assert!(err.contains("zero vector"), "{err}");
}
