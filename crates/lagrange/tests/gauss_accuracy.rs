//! The symplectic method's step comes from the dynamics and its reported error estimate is
//! honest: the heavy top (issue 14: 0.057 rad off at t = 10 with a step from the span).

use lagrange::{run_kept, Analysis, Ending, MethodName, SimulationOptions};

fn top() -> Analysis {
    let path = format!(
        "{}/../../examples/heavy-symmetric-top.lag",
        env!("CARGO_MANIFEST_DIR")
    );
    Analysis::from_file(std::path::Path::new(&path)).unwrap()
}

/// The state `(ψ, θ, φ)` at t = 10, and the run's error estimate.
fn at_ten(options: SimulationOptions) -> (Vec<f64>, Option<f64>, u64) {
    let mut simulation = top().simulation(&options).unwrap();
    let run = run_kept(&mut simulation);
    assert_eq!(run.ending, Ending::Finished);
    let last = run.rows.last().unwrap();
    assert_eq!(last[0], 10.0);
    let mut simulation = top().simulation(&options).unwrap();
    let outcome = simulation.run(&mut |_| {});
    (
        last[1..=3].to_vec(),
        outcome.error_estimate,
        outcome.stats.steps,
    )
}

#[test]
fn the_heavy_top_with_gauss_agrees_with_tight_dopri5_within_its_estimate() {
    let (reference, none, _) = at_ten(SimulationOptions {
        t_end: Some(10.0),
        rtol: Some(1e-12),
        atol: Some(1e-14),
        ..SimulationOptions::default()
    });
    assert_eq!(none, None);
    // The model's rtol 1e-10, a row every step or every second: the step no longer depends
    // on the span or on the output step. At this tolerance both runs are within 1e-10 of each
    // other (the reference's own error is of that order, so the estimate is checked below).
    for output_step in [None, Some(1.0)] {
        let (gauss, estimate, steps) = at_ten(SimulationOptions {
            method: Some(MethodName::Gauss),
            t_end: Some(10.0),
            output_step,
            ..SimulationOptions::default()
        });
        let difference = largest_difference(&gauss, &reference);
        assert!(difference < 1e-9, "{output_step:?}: {difference:e} rad");
        assert!(estimate.is_some_and(|e| e < 1e-8), "{estimate:?}");
        assert!(steps < 100_000, "{steps} steps");
    }
    // Looser tolerances, where the gauss error stands well above the reference's: the
    // estimate bounds the difference and is not far above it.
    for rtol in [1e-5, 1e-7] {
        let (gauss, estimate, _) = at_ten(SimulationOptions {
            method: Some(MethodName::Gauss),
            t_end: Some(10.0),
            rtol: Some(rtol),
            atol: Some(rtol * 1e-2),
            ..SimulationOptions::default()
        });
        let estimate = estimate.expect("gauss estimates its error");
        let difference = largest_difference(&gauss, &reference);
        assert!(
            difference <= estimate,
            "rtol {rtol}: difference {difference:e} above the estimate {estimate:e}"
        );
        assert!(
            estimate < 1e3 * difference.max(1e-12),
            "rtol {rtol}: {estimate:e} vs {difference:e}"
        );
        assert!(difference < 1e-3, "rtol {rtol}: {difference:e} rad");
    }
}

fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
}
