//! Recorded zero crossings and stop conditions of a run, at the library level: the canonical
//! pendulum's crossings of θ = 0 and θ̇ = 0 against its exact period (an elliptic integral),
//! and a stop condition that ends the run where it crosses.

use lagrange::mechanics::canonical;
use lagrange::{Analysis, Ending, SimulationOptions};

/// The period of a pendulum of length 1 released from rest at `theta0`:
/// `4 K(sin(θ₀/2)) / √g`, with `K(k) = π / (2 AGM(1, √(1 − k²)))`.
fn exact_period(theta0: f64, g: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (theta0 / 2.0).cos());
    for _ in 0..10 {
        (a, b) = ((a + b) / 2.0, (a * b).sqrt());
    }
    4.0 * (std::f64::consts::PI / (2.0 * a)) / g.sqrt()
}

fn pendulum() -> Analysis {
    // m = 1, l = 1, g = 9.81; released from rest at 0.5 rad.
    let mut analysis = Analysis::from_system(canonical::pendulum());
    analysis.set_value("theta", 0.5).unwrap();
    analysis
}

#[test]
fn crossings_follow_the_exact_period_in_both_directions() {
    let options = SimulationOptions {
        t_end: Some(10.0),
        rtol: Some(1e-10),
        atol: Some(1e-12),
        record_when: vec!["theta".into(), "theta_d".into()],
        ..SimulationOptions::default()
    };
    let run = pendulum().simulate(&options).unwrap();
    assert_eq!(run.ending, Ending::Finished);
    let period = exact_period(0.5, 9.81);
    let theta: Vec<_> = run.crossings.iter().filter(|c| c.event == 0).collect();
    let rate: Vec<_> = run.crossings.iter().filter(|c| c.event == 1).collect();
    assert!(theta.len() >= 9, "{}", theta.len());
    for (k, c) in theta.iter().enumerate() {
        let exact = (2 * k + 1) as f64 * period / 4.0;
        assert!((c.state[0] - exact).abs() < 1e-8, "θ crossing {k}: {c:?}");
        assert_eq!(c.rising, k % 2 == 1);
    }
    for (k, c) in rate.iter().enumerate() {
        let exact = (k + 1) as f64 * period / 2.0;
        assert!((c.state[0] - exact).abs() < 1e-8, "θ̇ crossing {k}: {c:?}");
        assert!((c.state[1].abs() - 0.5).abs() < 1e-8, "{c:?}");
    }
}

#[test]
fn a_stop_condition_ends_the_run_where_it_crosses() {
    let options = SimulationOptions {
        t_end: Some(10.0),
        rtol: Some(1e-10),
        atol: Some(1e-12),
        stop_when: Some("theta".into()),
        ..SimulationOptions::default()
    };
    let run = pendulum().simulate(&options).unwrap();
    assert_eq!(
        run.ending,
        Ending::Condition {
            text: "theta".into()
        }
    );
    assert!(
        (run.t - exact_period(0.5, 9.81) / 4.0).abs() < 1e-8,
        "{}",
        run.t
    );
    // An unknown name is the caller's mistake, with its column.
    let bad = SimulationOptions {
        stop_when: Some("thet".into()),
        ..options
    };
    let error = pendulum().simulate(&bad).unwrap_err();
    assert_eq!(error.kind(), lagrange::ErrorKind::Input);
    assert!(error.to_string().contains("column 1"), "{error}");
}
