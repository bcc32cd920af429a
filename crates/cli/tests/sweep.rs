//! `lagrange simulate --sweep`: a grid of runs and Monte-Carlo runs in parallel give, row for
//! row, what the same single runs give; a seed makes the draws repeatable.

use std::process::Output;

mod common;
use common::{lagrange, lagrange_with, SPHERE_RUN};

fn rows(o: &Output) -> Vec<Vec<String>> {
    String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

#[test]
fn a_grid_sweep_equals_the_single_runs() {
    let o = lagrange(&[
        "simulate",
        "examples/double-pendulum.lag",
        "--t-end",
        "1",
        "--sweep",
        "theta1=0.5..1.5",
        "--steps",
        "2",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let table = rows(&o);
    assert_eq!(table[0][..3], ["run", "theta1", "final_t"]);
    assert_eq!(table.len(), 4, "a header and 3 runs");
    for (k, value) in ["0.5", "1.0", "1.5"].iter().enumerate() {
        let row = &table[k + 1];
        assert_eq!(row[1], *value);
        // The same run alone: its last CSV row is the sweep's final state.
        let single = lagrange(&[
            "simulate",
            "examples/double-pendulum.lag",
            "--t-end",
            "1",
            "--set",
            &format!("theta1={value}"),
        ]);
        let last = rows(&single).pop().expect("rows");
        // The run's own columns (a single run also writes its reactions after them).
        let state = table[0].iter().position(|h| h == "steps").expect("steps") - 2;
        assert_eq!(row[2..2 + state], last[..state], "run {k}");
    }
}

#[test]
fn monte_carlo_draws_are_in_range_and_repeatable() {
    let args = [
        "simulate",
        "examples/seed/7.1-cart-pendulum.lag",
        "--t-end",
        "0.5",
        "--sweep",
        "k=10..40",
        "--sweep",
        "theta=0.1..0.5",
        "--samples",
        "6",
        "--seed",
        "7",
    ];
    let a = lagrange(&args);
    assert!(a.status.success(), "{}", String::from_utf8_lossy(&a.stderr));
    let table = rows(&a);
    assert_eq!(table.len(), 7);
    for row in &table[1..] {
        let k: f64 = row[1].parse().expect("k");
        let theta: f64 = row[2].parse().expect("theta");
        assert!(
            (10.0..=40.0).contains(&k) && (0.1..=0.5).contains(&theta),
            "{row:?}"
        );
        assert_eq!(row.last().map(String::as_str), Some("\"finished\""));
    }
    assert_eq!(
        rows(&lagrange(&args)),
        table,
        "the same seed gives the same runs"
    );
}

#[test]
fn a_bad_sweep_is_an_error() {
    let o = lagrange(&[
        "simulate",
        "examples/double-pendulum.lag",
        "--sweep",
        "nope=0..1",
    ]);
    assert_eq!(o.status.code(), Some(1));
    let o = lagrange(&[
        "simulate",
        "examples/double-pendulum.lag",
        "--sweep",
        "theta1=2..1",
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("lower end is above"));
}

#[test]
fn a_bifurcation_diagram_is_drawn_for_a_sweep() {
    let path = std::env::temp_dir().join(format!("lagrange-bif-{}.svg", std::process::id()));
    let o = lagrange(&[
        "equilibria",
        "examples/bead-on-rotating-hoop.lag",
        "--sweep",
        "Omega=0..10",
        "--steps",
        "10",
        "--plot",
        path.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let svg = std::fs::read_to_string(&path).expect("the diagram is written");
    let _ = std::fs::remove_file(&path);
    assert!(svg.starts_with("<svg"));
    // 11 values: θ = 0 and π at each, and the two side branches once Ω² R > g (Ω > 4.43
    // for R = 0.5): 11·2 + 6·2 = 34 markers, plus the three legend markers.
    assert_eq!(svg.matches("<circle").count(), 34 + 2, "{}", svg.len());
    let o = lagrange(&[
        "equilibria",
        "examples/bead-on-rotating-hoop.lag",
        "--plot",
        "x.svg",
    ]);
    assert!(!o.status.success());
}

#[test]
fn sweep_runs_stop_where_a_contact_is_lost_like_single_runs() {
    // The particle leaves the sphere where cos θ = ⅔ cos θ₀.
    let o = lagrange_with(&SPHERE_RUN, &["--sweep", "theta=0.1..0.5", "--steps", "2"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let table = rows(&o);
    let outcome = table[0]
        .iter()
        .position(|c| c == "outcome")
        .expect("outcome");
    assert_eq!(table.len(), 4, "a header and 3 runs");
    for (k, row) in table[1..].iter().enumerate() {
        assert_eq!(row[outcome], "\"contact lost: normal\"", "run {k}");
        // The grid's value as the sweep wrote it (0.30000000000000004, not 0.3).
        let value = &row[1];
        let theta0: f64 = value.parse().expect("a number");
        let theta: f64 = row[3].parse().expect("a number");
        let want = (2.0 / 3.0 * theta0.cos()).acos();
        assert!(
            (theta - want).abs() < 1e-7,
            "run {k}: θ = {theta} vs {want}"
        );
        let single = lagrange_with(&SPHERE_RUN, &["--set", &format!("theta={value}")]);
        let last = rows(&single).pop().expect("rows");
        // The run's own columns (a single run also writes its reactions after them).
        let state = table[0].iter().position(|h| h == "steps").expect("steps") - 2;
        assert_eq!(row[2..2 + state], last[..state], "run {k}");
    }
}
