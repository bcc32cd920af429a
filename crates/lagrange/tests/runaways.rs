//! Runs that cannot finish stop at once, typed, with the rows computed so far: the
//! reproductions of issue 14 (a pendulum with `g = 1e300`, a stiff spring `k = 1e12`), each
//! bounded well under a second.

use lagrange::numeric::{Failure, StopReason, STIFF_STEPS};
use lagrange::{run_kept, Analysis, Ending, MethodName, SimulationOptions};

fn pendulum() -> Analysis {
    let path = format!(
        "{}/../../examples/simple-pendulum.lag",
        env!("CARGO_MANIFEST_DIR")
    );
    Analysis::from_file(std::path::Path::new(&path)).unwrap()
}

#[test]
fn a_pendulum_with_g_1e300_stops_on_a_collapsed_step_keeping_its_rows() {
    let mut analysis = pendulum();
    analysis.set_value("g", 1e300).unwrap();
    let options = SimulationOptions {
        t_end: Some(1.0),
        ..SimulationOptions::default()
    };
    let mut simulation = analysis.simulation(&options).unwrap();
    let run = run_kept(&mut simulation);
    match run.ending {
        Ending::Failed(Failure::StepCollapse { t, h, span, .. }) => {
            assert_eq!(span, 1.0);
            assert!(h < 1e-12, "h = {h}");
            assert_eq!(run.t, t);
        }
        ref other => panic!("{other:?}"),
    }
    // The initial row and those before the collapse are kept, and are finite.
    assert!(
        !run.rows.is_empty() && run.rows.len() < 1000,
        "{}",
        run.rows.len()
    );
    assert_eq!(run.rows[0][1], 0.5);
    assert!(run.rows.iter().flatten().all(|x| x.is_finite()));
    let json = Ending::Failed(match run.ending {
        Ending::Failed(f) => f,
        _ => unreachable!(),
    })
    .to_json(run.t);
    assert_eq!(json["kind"], "failed");
    assert_eq!(json["failure"], "step_collapse");
    assert_eq!(json["numbers"]["span"], 1.0);
}

/// The damped oscillator with a damper `c = 1e7`: eigenvalues −10⁷ and −4·10⁻⁷, the classic
/// stiff pair: the explicit method's step is held at its stability limit.
fn damped(c: f64) -> Analysis {
    let path = format!(
        "{}/../../examples/damped-oscillator.lag",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut analysis = Analysis::from_file(std::path::Path::new(&path)).unwrap();
    analysis.set_value("c", c).unwrap();
    analysis
}

#[test]
fn a_stiff_damper_stops_the_explicit_method_and_sdirk_runs_it() {
    let analysis = damped(1e7);
    let mut simulation = analysis.simulation(&SimulationOptions::default()).unwrap();
    let run = run_kept(&mut simulation);
    match run.ending {
        Ending::Failed(Failure::Stiff {
            h, h_lambda, steps, ..
        }) => {
            assert!(h_lambda > 3.0, "{h_lambda}");
            assert!(h * 1e7 < 4.0, "h = {h}");
            assert_eq!(steps, STIFF_STEPS);
        }
        ref other => panic!("{other:?}"),
    }
    assert!(run.stats.steps < 10_000, "{:?}", run.stats);
    // The model writes a row every 0.01: only the initial one was due.
    assert_eq!(run.rows.len(), 1);
    let sentence = run.ending.sentence(run.t).unwrap();
    assert!(
        sentence.contains("stiff") && sentence.contains("sdirk"),
        "{sentence}"
    );

    let options = SimulationOptions {
        method: Some(MethodName::Sdirk),
        t_end: Some(1.0),
        ..SimulationOptions::default()
    };
    let mut simulation = analysis.simulation(&options).unwrap();
    let run = run_kept(&mut simulation);
    assert_eq!(run.ending, Ending::Finished);
    assert!(run.stats.steps < 10_000, "{:?}", run.stats);
    // The slow mode creeps: x' ≈ (F − k x)/c, so x stays within 1e-6 of 1 over a second.
    let last = run.rows.last().unwrap();
    assert!((last[1] - 1.0).abs() < 1e-6, "{}", last[1]);
}

#[test]
fn a_fast_stiff_spring_that_oscillates_stops_at_the_row_limit() {
    // k = 1e12 on one mass, started stretched: a real oscillation at ω = 10⁶, resolved by
    // accuracy (not stiff); the row limit ends it with the rows kept.
    let text = "coordinates x\nparameters m = 1, k = 1e12\nframe N\npoint P = x*N.x\n\
                particle P mass m\nspring k from origin to P\ninitial x = 1\nsimulate to 10\n";
    let analysis = Analysis::from_text(text).unwrap();
    let options = SimulationOptions {
        max_rows: Some(5_000),
        ..SimulationOptions::default()
    };
    let mut simulation = analysis.simulation(&options).unwrap();
    let run = run_kept(&mut simulation);
    assert!(
        matches!(
            run.ending,
            Ending::Failed(Failure::TooManyOutputs { rows: 5_000, .. })
        ),
        "{:?}",
        run.ending
    );
    assert_eq!(run.rows.len(), 5_000);
    // What was kept is right: x = cos(10⁶ t).
    for row in run.rows.iter().step_by(97) {
        assert!(
            (row[1] - (1e6 * row[0]).cos()).abs() < 1e-5,
            "t = {}",
            row[0]
        );
    }
    // The step limit the same way.
    let options = SimulationOptions {
        max_steps: Some(300),
        ..SimulationOptions::default()
    };
    let mut simulation = analysis.simulation(&options).unwrap();
    let outcome = simulation.run(&mut |_| {});
    assert!(matches!(
        outcome.stop,
        StopReason::Failed(Failure::TooManySteps { steps: 300, .. })
    ));
}
