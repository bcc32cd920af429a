//! Issue 14: `check` and `solve` disagreed on the degrees of freedom — 1 and 3 for the Atwood
//! machine, whose three coordinates are tied by two holonomic constraints kept with
//! multipliers. `solve` printed the number of coordinates. Now the derivation counts the
//! independent virtual displacements (`Equations::degrees_of_freedom`: the coordinates left
//! after elimination less the rank of the kept constraints), and `check` counts its statements
//! the same way (a velocity constraint takes one away too), so the two agree on every example.

use std::path::{Path, PathBuf};

use lagrange::Analysis;

fn examples() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut files = Vec::new();
    for dir in [root.clone(), root.join("seed"), root.join("canonical")] {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "lag") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

fn degrees_of_freedom(file: &str) -> usize {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(file);
    let analysis = Analysis::from_file(&path).unwrap();
    analysis.equations().unwrap().degrees_of_freedom()
}

#[test]
fn the_derivation_counts_independent_displacements() {
    // Three coordinates, two holonomic constraints kept with multipliers.
    assert_eq!(degrees_of_freedom("atwood-machine.lag"), 1);
    // The four-bar's three angles and its loop's two closure conditions.
    assert_eq!(degrees_of_freedom("four-bar.lag"), 1);
    // Cartesian pendulum: x, y and the rod.
    assert_eq!(degrees_of_freedom("cartesian-pendulum.lag"), 1);
    // A knife edge: three coordinates, one nonholonomic condition.
    assert_eq!(degrees_of_freedom("knife-edge.lag"), 2);
    // Rolling without slipping on an incline integrates: x = R φ eliminates one coordinate.
    assert_eq!(degrees_of_freedom("rolling-disk-incline.lag"), 1);
    assert_eq!(degrees_of_freedom("seed/7.1-cart-pendulum.lag"), 2);
    assert_eq!(degrees_of_freedom("seed/7.2-rolling-cone.lag"), 1);
    assert_eq!(degrees_of_freedom("seed/7.3-gears-pendulum.lag"), 2);
}

#[test]
fn check_and_solve_agree_on_every_example() {
    let files = examples();
    assert!(files.len() >= 20, "{files:?}");
    for path in files {
        // Lagrange's route stops at its work limit on the Whipple bicycle (issue 18).
        if path.ends_with("whipple-bicycle.lag") {
            continue;
        }
        let analysis = Analysis::from_file(&path).unwrap();
        let Some(source) = analysis.source() else {
            panic!("{}: a model file has its source", path.display());
        };
        let summary = source.model.summary();
        let checked = summary.degrees_of_freedom;
        let derived = analysis.equations().unwrap().degrees_of_freedom();
        // A 3-D rolling contact is one statement with three rows, two of them independent:
        // `check` counts the rank of the rows as the derivation does (issue 18).
        assert_eq!(checked, derived, "{}", path.display());
        assert!(
            !summary.to_string().contains("provisional"),
            "{}",
            path.display()
        );
        let solution = analysis.solution(None).unwrap();
        let text = solution.document.to_text();
        assert!(
            text.contains(&format!("Degrees of freedom: {derived}")),
            "{}",
            path.display()
        );
    }
}
