//! Issue 20: the right-hand side grew as n²·³ (the `O(n²)` mass matrix on the tape and the
//! dense `L D Lᵀ` solve, `O(n³)`) and fell behind Pinocchio's ABA near n = 37. A model without
//! constraints now has its kinematic tree read off the symbolic model
//! (`mechanics::KinematicTree`) and `q̈` eliminated on it in O(n) (`numeric::Articulated`).
//!
//! The tree's `q̈` must be the dense solve's to 1e-10 (relative to the largest) at random
//! states, on every example that has a tree and on the generated n-link pendulums and 3-D
//! chains of the benchmarks; those chains must have a tree, and the large ones must use it.

use lagrange::{Analysis, SimulationOptions};

fn examples() -> Vec<std::path::PathBuf> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut files: Vec<_> = ["", "seed"]
        .iter()
        .flat_map(|dir| std::fs::read_dir(root.join(dir)).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "lag"))
        // Lagrange's route stops at its work limit on the Whipple bicycle (issue 18).
        .filter(|p| !p.ends_with("whipple-bicycle.lag"))
        .collect();
    files.sort();
    files
}

/// `bench/models/nlink.sh N`: point masses on rods, absolute angles.
fn nlink(n: usize) -> String {
    let coordinates: Vec<String> = (1..=n).map(|i| format!("th{i}")).collect();
    let mut text = format!(
        "coordinates {}\nparameters g = 9.81",
        coordinates.join(", ")
    );
    for i in 1..=n {
        // Unequal masses and lengths, so that no column coincides by accident.
        text += &format!(
            ", m{i} = {}, l{i} = {}",
            1.0 + 0.1 * i as f64,
            1.0 - 0.03 * i as f64
        );
    }
    text += "\nframe N\n";
    for i in 1..=n {
        let previous = if i > 1 {
            format!("P{} + ", i - 1)
        } else {
            String::new()
        };
        text += &format!(
            "point P{i} = {previous}l{i}*sin(th{i})*N.x - l{i}*cos(th{i})*N.y\nparticle P{i} mass m{i}\n"
        );
    }
    text + "gravity -g*N.y\ninitial th1 = 0.5\n"
}

/// `bench/models/chain3d.sh N`: rods on universal joints, absolute frames.
fn chain3d(n: usize) -> String {
    let coordinates: Vec<String> = (1..=n).map(|i| format!("a{i}, b{i}")).collect();
    let mut text = format!(
        "coordinates {}\nparameters g = 9.81, m = 1, l = 1, J = 0.001\nframe N\n",
        coordinates.join(", ")
    );
    for i in 1..=n {
        let from = if i > 1 {
            format!("P{}", i - 1)
        } else {
            "origin".into()
        };
        text += &format!(
            "frame B{i} = N rotated a{i} about x then b{i} about y\n\
             point G{i} = {from} - l/2*B{i}.z\n\
             point P{i} = {from} - l*B{i}.z\n\
             body rod{i} mass m at G{i} frame B{i} inertia m*l^2/12, m*l^2/12, J\n"
        );
    }
    text + "gravity -g*N.z\ninitial a1 = 0.5, b1 = 0.3\n"
}

/// Compares the two routes at `samples` random states; returns whether the model has a tree
/// and whether its right-hand side goes by it.
fn compare(analysis: &Analysis, what: &str, next: &mut dyn FnMut() -> f64) -> (bool, bool) {
    let options = SimulationOptions {
        t_end: Some(1.0),
        ..SimulationOptions::default()
    };
    let Ok(mut simulation) = analysis.simulation(&options) else {
        return (false, false);
    };
    let n = simulation.initial_state().len() / 2;
    let mut has_tree = false;
    for _ in 0..5 {
        let state: Vec<f64> = (0..2 * n).map(|_| 2.0 * next()).collect();
        let t = 1.5 * next().abs();
        let (dense, tree) = simulation.rhs_both_routes(t, &state).unwrap();
        let (Ok(dense), Some(tree)) = (dense, tree) else {
            continue;
        };
        has_tree = true;
        let scale = dense.iter().fold(1.0f64, |s, x| s.max(x.abs()));
        // Both routes are exact eliminations; they differ by rounding, which the mass
        // matrix's condition amplifies (the top near its pole at a random θ: 5e-12).
        for k in 0..n {
            assert!(
                (dense[k] - tree[k]).abs() <= 1e-10 * scale,
                "{what}: q̈_{k} = {} dense, {} by the tree (largest {scale})",
                dense[k],
                tree[k]
            );
        }
    }
    (has_tree, simulation.rhs_by_tree())
}

fn random() -> impl FnMut() -> f64 {
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        -1.0 + 2.0 * ((seed >> 11) as f64 / (1u64 << 53) as f64)
    }
}

#[test]
fn the_tree_gives_the_dense_accelerations_on_every_example_that_has_one() {
    let mut next = random();
    let mut with_tree = Vec::new();
    for path in examples() {
        let analysis = Analysis::from_file(&path).unwrap();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if compare(&analysis, &name, &mut next).0 {
            with_tree.push(name);
        }
    }
    for expected in ["double-pendulum", "simple-pendulum", "heavy-symmetric-top"] {
        assert!(
            with_tree.iter().any(|n| n == expected),
            "{expected} has no tree; these have: {with_tree:?}"
        );
    }
}

#[test]
fn the_tree_gives_the_dense_accelerations_on_the_benchmark_chains() {
    let mut next = random();
    for n in [1, 2, 3, 5, 10, 20] {
        let analysis = Analysis::from_text(&nlink(n)).unwrap();
        let (has_tree, used) = compare(&analysis, &format!("n-link {n}"), &mut next);
        assert!(has_tree, "the {n}-link pendulum has no tree");
        assert!(
            used || n < 10,
            "the {n}-link pendulum's rhs does not go by its tree"
        );
    }
    for n in [1, 2, 3, 5] {
        let analysis = Analysis::from_text(&chain3d(n)).unwrap();
        let (has_tree, used) = compare(&analysis, &format!("3-D chain {n}"), &mut next);
        assert!(has_tree, "the 3-D chain of {n} rods has no tree");
        assert!(
            used || n < 20,
            "the 3-D chain of {n} rods does not go by its tree"
        );
    }
}

#[test]
fn a_long_run_by_the_tree_keeps_the_energy() {
    let analysis = Analysis::from_text(&nlink(12)).unwrap();
    let options = SimulationOptions {
        t_end: Some(5.0),
        ..SimulationOptions::default()
    };
    let mut simulation = analysis.simulation(&options).unwrap();
    assert!(simulation.rhs_by_tree());
    let mut worst = 0.0f64;
    let columns = simulation.columns();
    let column = columns.iter().position(|c| c == "energy_error").unwrap();
    let outcome = simulation.run(&mut |row| worst = worst.max(row[column].abs()));
    assert!(
        matches!(outcome.stop, lagrange::numeric::StopReason::Finished),
        "{outcome:?}"
    );
    assert!(worst < 1e-6, "relative energy error {worst}");
}
