//! Every model file under `examples/` parses and checks without a diagnostic, and the seed
//! exercises have the degrees of freedom their solutions use.

use std::path::{Path, PathBuf};

fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn model_files(dir: &Path, found: &mut Vec<PathBuf>) {
    let entries =
        std::fs::read_dir(dir).unwrap_or_else(|e| panic!("reading {}: {e}", dir.display()));
    for entry in entries {
        let path = entry.expect("a directory entry").path();
        if path.is_dir() {
            model_files(&path, found);
        } else if path.extension().is_some_and(|e| e == "lag") {
            found.push(path);
        }
    }
}

fn load(path: &Path) -> model::Model {
    let source = std::fs::read_to_string(path).expect("readable example");
    let name = path.display().to_string();
    match model::load(&source) {
        Ok(model) => model,
        Err(errors) => panic!(
            "{}",
            model::render(&errors.0, &name, &source, model::RenderOptions::default())
        ),
    }
}

#[test]
fn every_example_checks_cleanly() {
    let mut files = Vec::new();
    model_files(&examples_dir(), &mut files);
    files.sort();
    assert!(
        files.len() >= 14,
        "expected the seed and classic examples, found {files:?}"
    );
    for path in &files {
        let model = load(path);
        assert!(
            model.warnings().is_empty(),
            "{}: {:#?}",
            path.display(),
            model.warnings()
        );
        // Every example can be run numerically as it stands.
        let missing = model.require_values();
        assert!(missing.is_empty(), "{}: {missing:?}", path.display());
        // The summary renders.
        assert!(model.summary().to_string().contains("degrees of freedom"));
    }
}

#[test]
fn seed_exercises_have_the_expected_degrees_of_freedom() {
    let seed = examples_dir().join("seed");
    let dof = |file: &str| load(&seed.join(file)).summary().degrees_of_freedom;
    assert_eq!(dof("7.1-cart-pendulum.lag"), 2);
    // Rolling is a velocity constraint and takes a degree of freedom away (2 coordinates,
    // 1 rolling), as `solve` counts it.
    assert_eq!(dof("7.2-rolling-cone.lag"), 1);
    // The gear with a constant ratio eliminates one coordinate.
    assert_eq!(dof("7.3-gears-pendulum.lag"), 2);
    assert_eq!(dof("7.4-inverted-pendulum.lag"), 2);
}

#[test]
fn summary_of_the_design_sketch() {
    let model = load(&examples_dir().join("seed/7.1-cart-pendulum.lag"));
    let summary = model.summary().to_string();
    assert_eq!(
        summary,
        "degrees of freedom: 2 (2 coordinates − 0 holonomic constraints)
coordinates: x, theta
bodies:
  particle at A, mass m_A
  particle at B, mass m_B
forces:
  gravity g*N.y
  spring k from origin to A
  force F*N.x at A
  generalized force C on theta
constraints: none
reactions: hinge_A (hinge at A), track (contact at A)
"
    );
}

/// DESIGN.md's sketch of exercise 7.1 is the canonical example and must stay valid as
/// written. The design documents live beside the repository (`../shared`), where CI has them;
/// the sketch is also kept verbatim in `examples/seed/7.1-cart-pendulum.lag`, which the test
/// above checks everywhere.
#[test]
fn design_sketch_stays_valid() {
    let design = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/DESIGN.md");
    let Ok(text) = std::fs::read_to_string(&design) else {
        return;
    };
    let start = text
        .find("```text\n# Cart on a spring")
        .expect("the 7.1 sketch in DESIGN.md");
    let body = &text[start + "```text\n".len()..];
    let sketch = &body[..body.find("```").expect("end of the sketch")];
    if let Err(errors) = model::load(sketch) {
        panic!(
            "{}",
            model::render(
                &errors.0,
                "DESIGN.md",
                sketch,
                model::RenderOptions::default()
            )
        );
    }
    let example =
        std::fs::read_to_string(examples_dir().join("seed/7.1-cart-pendulum.lag")).expect("7.1");
    assert!(
        example.contains(sketch),
        "examples/seed/7.1-cart-pendulum.lag must contain the sketch verbatim"
    );
}

#[test]
fn declarations_come_in_file_order_and_refer_backwards() {
    let model = load(&examples_dir().join("seed/7.2-rolling-cone.lag"));
    let kinds: Vec<String> = model
        .declarations()
        .iter()
        .map(|d| format!("{d:?}"))
        .collect();
    assert_eq!(
        kinds.first().map(String::as_str),
        Some("Coordinate(CoordinateId(0))")
    );
    // theta, phi, 7 parameters, 3 constants, 4 frames, 2 points, 1 body, 1 constraint.
    assert_eq!(kinds.len(), 2 + 7 + 3 + 4 + 2 + 1 + 1);
    assert!(matches!(
        model.declarations().last(),
        Some(model::Declaration::Constraint(_))
    ));
}
