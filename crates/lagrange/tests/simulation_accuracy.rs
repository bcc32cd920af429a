//! Simulation accuracy against independent references and against the laws the methods keep:
//! SciPy DOP853 at 1e-12 on equations SymPy derived (tests/data/simulation, made by
//! tools/scipy_reference/run.sh), energy over 10⁴ periods with the symplectic method, and
//! constraint drift with projection.

use lagrange::{numeric, Analysis, MethodName, SimulationOptions};

fn root(path: &str) -> String {
    format!("{}/../../{path}", env!("CARGO_MANIFEST_DIR"))
}

fn model(example: &str, overrides: &[(&str, f64)]) -> Analysis {
    let mut analysis = Analysis::from_file(std::path::Path::new(&root(example))).unwrap();
    for (name, value) in overrides {
        analysis.set_value(name, *value).unwrap();
    }
    analysis
}

fn run(analysis: &Analysis, options: &SimulationOptions) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut simulation = analysis.simulation(options).unwrap();
    let mut rows = Vec::new();
    let outcome = simulation.run(&mut |row| rows.push(row.to_vec()));
    assert_eq!(outcome.stop, numeric::StopReason::Finished);
    (simulation.columns(), rows)
}

/// Reads a reference CSV: the header and the rows.
fn reference(name: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(root(&format!("tests/data/simulation/{name}.csv"))).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// The largest difference over every reference row and column, matched by column name.
fn max_difference(name: &str, columns: &[String], rows: &[Vec<f64>]) -> f64 {
    let (header, expected) = reference(name);
    assert_eq!(rows.len(), expected.len(), "{name}: row count");
    let mut worst: f64 = 0.0;
    for (row, reference) in rows.iter().zip(&expected) {
        assert_eq!(row[0], reference[0], "{name}: output times");
        for (k, column) in header.iter().enumerate() {
            let ours = columns.iter().position(|c| c == column).unwrap();
            worst = worst.max((row[ours] - reference[k]).abs());
        }
    }
    worst
}

fn tight(t_end: f64) -> SimulationOptions {
    SimulationOptions {
        t_start: Some(0.0),
        t_end: Some(t_end),
        rtol: Some(1e-12),
        atol: Some(1e-12),
        output_step: Some(0.5),
        ..SimulationOptions::default()
    }
}

#[test]
fn double_pendulum_from_a_chaotic_start_matches_dop853_to_1e_6_at_10_s() {
    let start = [
        ("theta1", 2.0),
        ("theta2", 2.0),
        ("theta1_d", 0.0),
        ("theta2_d", 0.0),
    ];
    let (columns, rows) = run(&model("examples/double-pendulum.lag", &start), &tight(10.0));
    let worst = max_difference("double_pendulum_chaotic", &columns, &rows);
    assert!(worst < 1e-6, "largest difference {worst:e}");
}

#[test]
fn double_pendulum_from_a_regular_start_matches_dop853_to_1e_9() {
    let start = [
        ("theta1", 1.5),
        ("theta2", 1.0),
        ("theta1_d", 0.0),
        ("theta2_d", 0.5),
    ];
    let (columns, rows) = run(&model("examples/double-pendulum.lag", &start), &tight(10.0));
    let worst = max_difference("double_pendulum_regular", &columns, &rows);
    assert!(worst < 1e-9, "largest difference {worst:e}");
}

#[test]
fn pendulum_near_the_top_matches_dop853_and_gauss_does_too() {
    let m = model("examples/simple-pendulum.lag", &[("theta", 3.0)]);
    let (columns, rows) = run(&m, &tight(10.0));
    let worst = max_difference("simple_pendulum_large", &columns, &rows);
    assert!(worst < 1e-8, "dopri5: largest difference {worst:e}");
    let gauss = SimulationOptions {
        method: Some(MethodName::Gauss),
        step: Some(0.005),
        ..tight(10.0)
    };
    let (columns, rows) = run(&m, &gauss);
    let worst = max_difference("simple_pendulum_large", &columns, &rows);
    assert!(worst < 1e-8, "gauss: largest difference {worst:e}");
}

#[test]
fn constrained_cartesian_pendulum_follows_the_angle_reference_without_drift() {
    // The same pendulum as simple_pendulum_large, in Cartesian coordinates with the rod as a
    // constraint kept with a multiplier: x = sin θ, y = −cos θ.
    let theta0: f64 = 3.0;
    let m = model(
        "examples/cartesian-pendulum.lag",
        &[("x", theta0.sin()), ("y", -theta0.cos())],
    );
    let (columns, rows) = run(&m, &tight(10.0));
    let (_, expected) = reference("simple_pendulum_large");
    let (x, y, drift) = (
        columns.iter().position(|c| c == "x").unwrap(),
        columns.iter().position(|c| c == "y").unwrap(),
        columns
            .iter()
            .position(|c| c == "constraint_drift")
            .unwrap(),
    );
    for (row, reference) in rows.iter().zip(&expected) {
        let theta = reference[1];
        assert!((row[x] - theta.sin()).abs() < 1e-7, "x at t = {}", row[0]);
        assert!((row[y] + theta.cos()).abs() < 1e-7, "y at t = {}", row[0]);
        assert!(row[drift] < 1e-12, "drift {} at t = {}", row[drift], row[0]);
    }
}

#[test]
fn constraint_drift_stays_below_tolerance_over_a_long_run() {
    let m = model("examples/cartesian-pendulum.lag", &[]);
    let options = SimulationOptions {
        t_end: Some(200.0),
        rtol: Some(1e-6),
        atol: Some(1e-8),
        output_step: Some(1.0),
        ..SimulationOptions::default()
    };
    let (columns, rows) = run(&m, &options);
    let drift = columns
        .iter()
        .position(|c| c == "constraint_drift")
        .unwrap();
    let worst = rows.iter().map(|r| r[drift]).fold(0.0, f64::max);
    assert!(worst < 1e-8, "drift {worst:e}");
}

#[test]
fn gauss_keeps_the_pendulum_energy_within_1e_8_over_ten_thousand_periods() {
    // Small-amplitude period 2π/√g ≈ 2.006 s; θ₀ = 0.5 is well into the nonlinear range.
    let m = model("examples/simple-pendulum.lag", &[("theta", 0.5)]);
    let periods = 10_000.0;
    let options = SimulationOptions {
        method: Some(MethodName::Gauss),
        t_end: Some(periods * 2.006),
        step: Some(0.1),
        output_step: Some(50.0),
        ..SimulationOptions::default()
    };
    let (columns, rows) = run(&m, &options);
    let energy = columns.iter().position(|c| c == "energy_error").unwrap();
    let worst = rows.iter().map(|r| r[energy].abs()).fold(0.0, f64::max);
    assert!(worst < 1e-8, "relative energy error {worst:e}");
    // The explicit method at a loose tolerance drifts instead: the contrast is the point.
    let loose = SimulationOptions {
        method: Some(MethodName::Dopri5),
        rtol: Some(1e-5),
        atol: Some(1e-7),
        t_end: Some(2000.0),
        step: None,
        ..options
    };
    let (_, rows) = run(&m, &loose);
    let drifted = rows.last().map_or(0.0, |r| r[energy].abs());
    assert!(
        drifted > 10.0 * worst,
        "dopri5 {drifted:e} vs gauss {worst:e}"
    );
}
