//! Runs that cannot finish stop at once, typed, with the rows computed so far: the
//! reproductions of issue 14 (a pendulum with `g = 1e300`, a stiff spring `k = 1e12`) and of
//! the mutation fuzzer's known failures 2, 3, 4 and 6 (docs/reliability.md: an end time of
//! 1e29, a forcing at ω = 1e300, an input of 1e29 on the knife edge, a start time from the
//! model equal to the end time), each bounded well under a second.

use lagrange::numeric::{Failure, StopReason, STEP_COLLAPSE_FRACTION, STIFF_STEPS};
use lagrange::simulation::{Limit, SimulationError};
use lagrange::{
    run_kept, run_sampled, run_to_csv, Analysis, Ending, Error, ErrorKind, MethodName,
    SimulationOptions,
};

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
    // The default at the model's tolerance (issue 20): dop853, whose stability interval on
    // the negative real axis ends near h·λ = 6 (dopri5's near 3.3).
    assert_eq!(simulation.method(), MethodName::Dop853);
    let run = run_kept(&mut simulation);
    match run.ending {
        Ending::Failed(Failure::Stiff {
            h, h_lambda, steps, ..
        }) => {
            assert!(h_lambda > 6.0, "{h_lambda}");
            assert!(h * 1e7 < 7.0, "h = {h}");
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

/// An example model's text with `from` replaced by `to` (once, and it must be there).
fn mutant(example: &str, from: &str, to: &str) -> String {
    let path = format!("{}/../../examples/{example}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains(from), "{example} has no `{from}`");
    text.replacen(from, to, 1)
}

/// The 1-based line and column of the first `needle` in `text`.
fn line_col(text: &str, needle: &str) -> (usize, usize) {
    let at = text.find(needle).unwrap();
    let line = text[..at].matches('\n').count() + 1;
    let column = at - text[..at].rfind('\n').map_or(0, |k| k + 1) + 1;
    (line, column)
}

#[test]
fn an_end_time_far_beyond_the_motions_time_scale_stops_at_once() {
    // Known failure 2: `solve` integrated for ever. Now the first step the dynamics ask for
    // is already below 10⁻¹² of the span, and the run says so at t = 0.
    for (example, from, to) in [
        (
            "simple-pendulum.lag",
            "simulate from 0 to 10",
            "simulate from 0 to 1e29",
        ),
        (
            "spring-chain.lag",
            "simulate to 5",
            "simulate to 123456789012345678901234567890",
        ),
        (
            "spherical-pendulum.lag",
            "simulate to 10",
            "simulate to 123456789012345678901234567890",
        ),
    ] {
        let analysis = Analysis::from_text(&mutant(example, from, to)).unwrap();
        let mut simulation = analysis.simulation(&SimulationOptions::default()).unwrap();
        let run = run_kept(&mut simulation);
        match run.ending {
            Ending::Failed(Failure::StepCollapse { t, h, span, .. }) => {
                assert_eq!(t, 0.0, "{example}");
                assert!(span >= 1e29, "{example}: {span}");
                // The step of the motion itself (its time scale is about a second), not one
                // near the floor.
                assert!(h > 1e-4 && h < 1.0, "{example}: h = {h}");
                assert!(h < STEP_COLLAPSE_FRACTION * span);
            }
            ref other => panic!("{example}: {other:?}"),
        }
        assert_eq!(run.rows.len(), 1, "{example}");
        assert_eq!(run.stats.steps, 0, "{example}");
        let sentence = run.ending.sentence(run.t).unwrap();
        assert!(sentence.contains("end time is too far"), "{sentence}");
    }
    // `solve` (which runs the model's own simulation) finishes and says why the run stopped.
    let text = mutant(
        "simple-pendulum.lag",
        "simulate from 0 to 10",
        "simulate from 0 to 1e29",
    );
    let solution = Analysis::from_text(&text).unwrap().solution(None).unwrap();
    let json = solution.document.to_json().to_string();
    assert!(json.contains("end time is too far"), "{json}");
}

#[test]
fn an_output_step_that_asks_for_more_rows_than_the_limit_is_refused_at_its_line() {
    // Known failure 2 with an output step: `to 1e308 step 0.01` asks for 10³¹⁰ rows. Nothing
    // can stop the run early, so it is refused before it starts, at the model's `step`.
    let text = mutant(
        "damped-oscillator.lag",
        "simulate from 0 to 30 step 0.01",
        "simulate from 0 to 1e308 step 0.01",
    );
    let analysis = Analysis::from_text(&text).unwrap();
    let (line, column) = line_col(&text, "0.01");
    for options in [
        SimulationOptions::default(),
        // The end from the caller, the step from the model: still the model's line.
        SimulationOptions {
            t_end: Some(1e7),
            ..SimulationOptions::default()
        },
    ] {
        let error = analysis.simulation(&options).unwrap_err();
        assert_eq!(error.kind(), ErrorKind::Input);
        match &error {
            Error::Located {
                message,
                line: l,
                column: c,
                ..
            } => {
                assert_eq!((*l, *c), (line, column), "{message}");
                assert!(message.contains("row limit of 1000000"), "{message}");
            }
            other => panic!("{other:?}"),
        }
    }
    // Known failure 7: `step 0.0000001` over the model's 30 s made `solve` keep 3·10⁸ rows
    // in memory until it aborted past 4 GiB. Its section now says why it did not run, and
    // where.
    let text = mutant(
        "damped-oscillator.lag",
        "simulate from 0 to 30 step 0.01",
        "simulate from 0 to 30 step 0.0000001",
    );
    let (line, column) = line_col(&text, "0.0000001");
    let solution = Analysis::from_text(&text).unwrap().solution(None).unwrap();
    let json = solution.document.to_json().to_string();
    assert!(
        json.contains(&format!(
            "line {line}, column {column}: in the `simulate` statement"
        )) && json.contains("300000001 rows, more than the row limit of 1000000"),
        "{json}"
    );
    // Within the limit: 10⁶ rows exactly (0, 0.01, …, 9999.99) is allowed.
    let within = SimulationOptions {
        t_end: Some(9999.99),
        ..SimulationOptions::default()
    };
    assert_eq!(analysis.settings(&within).unwrap().max_rows, 1_000_000);
    assert!(analysis.simulation(&within).is_ok());
    // The span and step from the caller: the same error, without a line (the caller adds
    // its flags).
    let options = SimulationOptions {
        t_end: Some(1e9),
        output_step: Some(1.0),
        max_rows: Some(1000),
        ..SimulationOptions::default()
    };
    match analysis.simulation(&options).unwrap_err() {
        Error::Simulation(SimulationError::BeyondLimit {
            limit: Limit::Rows,
            count,
            allowed: 1000,
            ..
        }) => assert_eq!(count, 1e9 + 1.0),
        other => panic!("{other:?}"),
    }
    // gauss's fixed step counts the same way against the step limit.
    let options = SimulationOptions {
        method: Some(MethodName::Gauss),
        step: Some(1e-3),
        max_steps: Some(1000),
        t_end: Some(2.0),
        output_step: Some(1.0),
        ..SimulationOptions::default()
    };
    assert!(matches!(
        analysis.simulation(&options).unwrap_err(),
        Error::Simulation(SimulationError::BeyondLimit {
            limit: Limit::Steps,
            ..
        })
    ));
}

#[test]
fn a_run_that_a_stop_event_may_end_is_not_refused_for_its_rows() {
    // Ten million rows every 0.01 over 10⁵ s, but the stop condition ends the run first.
    let options = SimulationOptions {
        t_end: Some(1e5),
        output_step: Some(0.01),
        stop_when: Some("theta".into()),
        ..SimulationOptions::default()
    };
    let mut simulation = pendulum().simulation(&options).unwrap();
    let run = run_kept(&mut simulation);
    assert!(
        matches!(run.ending, Ending::Condition { .. }),
        "{:?}",
        run.ending
    );
    assert!(run.t > 0.4 && run.t < 0.6, "{}", run.t);
}

#[test]
fn a_forcing_too_fast_to_resolve_stops_at_the_step_limit_keeping_its_rows() {
    // Known failure 3: ω = 1e300 in F0 cos(ω t) — noise at any step the time can resolve —
    // took 6.3 million steps for half a second. It is not stiff (the Jacobian's |λ| is 2);
    // the step limit, 10⁶ by default, ends it. Here a small limit keeps the test fast.
    let mut analysis = damped(0.4);
    analysis.set_value("omega", 1e300).unwrap();
    let defaults = analysis.settings(&SimulationOptions::default()).unwrap();
    assert_eq!(
        (defaults.max_steps, defaults.max_rows),
        (1_000_000, 1_000_000)
    );
    let options = SimulationOptions {
        t_end: Some(0.5),
        output_step: None,
        max_steps: Some(20_000),
        ..SimulationOptions::default()
    };
    let mut simulation = analysis.simulation(&options).unwrap();
    let run = run_kept(&mut simulation);
    match run.ending {
        Ending::Failed(Failure::TooManySteps { t, steps: 20_000 }) => {
            assert_eq!(run.t, t);
            assert!(t > 0.0 && t < 0.5, "{t}");
        }
        ref other => panic!("{other:?}"),
    }
    assert_eq!(run.stats.steps, 20_000);
    // The model's row every 0.01: those due before the stop are kept, all finite.
    assert_eq!(run.rows.len() as f64, 1.0 + (run.t / 0.01).floor());
    assert!(run.rows.iter().flatten().all(|x| x.is_finite()));
    let sentence = run.ending.sentence(run.t).unwrap();
    assert!(
        sentence.contains("after 20000 steps: the step limit was reached"),
        "{sentence}"
    );
}

#[test]
fn a_huge_input_on_the_knife_edge_writes_a_few_bytes_not_200_megabytes() {
    // Known failure 4: `inputs T = 1e29`, `simulate --t-end 0.5` wrote > 200 MB of CSV.
    let text = mutant(
        "knife-edge.lag",
        "inputs      T = 0.1",
        "inputs      T = 1e29",
    );
    let analysis = Analysis::from_text(&text).unwrap();
    let options = SimulationOptions {
        t_end: Some(0.5),
        ..SimulationOptions::default()
    };
    let mut simulation = analysis.simulation(&options).unwrap();
    let mut csv = Vec::new();
    let run = run_to_csv(
        &mut simulation,
        &mut csv,
        false,
        lagrange::DEFAULT_MAX_BYTES,
        &mut |_| {},
    )
    .unwrap();
    assert!(
        matches!(run.ending, Ending::Failed(Failure::StepCollapse { .. })),
        "{:?}",
        run.ending
    );
    assert_eq!(run.bytes, csv.len() as u64);
    assert!(csv.len() < 10_000, "{} bytes", csv.len());
}

#[test]
fn the_byte_limit_stops_the_csv_within_it_with_the_rows_so_far() {
    let options = SimulationOptions {
        t_end: Some(1000.0),
        ..SimulationOptions::default()
    };
    let mut simulation = pendulum().simulation(&options).unwrap();
    let mut csv = Vec::new();
    let run = run_to_csv(&mut simulation, &mut csv, true, 20_000, &mut |_| {}).unwrap();
    assert_eq!(run.ending, Ending::OutputLimit { bytes: 20_000 });
    assert!(run.ending.stopped_short());
    assert!(csv.len() <= 20_000 && csv.len() > 19_000, "{}", csv.len());
    assert_eq!(run.bytes, csv.len() as u64);
    // Whole rows only, the last at the time the run reached.
    let text = String::from_utf8(csv).unwrap();
    assert!(text.ends_with('\n'));
    let last: Vec<f64> = text
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(last[0], run.outcome.t);
    assert_eq!(run.kept.len() as u64, run.tally.rows);
    assert_eq!(text.lines().count() as u64, run.tally.rows + 1);
    let summary = run.summary_json("pendulum", &simulation);
    assert_eq!(summary["outcome"]["failure"], "too_many_bytes", "{summary}");
    assert_eq!(summary["outcome"]["numbers"]["bytes"], 20_000);
}

#[test]
fn an_empty_span_from_the_model_points_at_its_simulate_line() {
    // Known failure 6: `simulate from 0.5 …` in the model, `--t-end 0.5` from the caller.
    let text = mutant(
        "canonical/pendulum.lag",
        "simulate from 0 to 10",
        "simulate from 0.5 to 10",
    );
    let analysis = Analysis::from_text(&text).unwrap();
    let options = SimulationOptions {
        t_end: Some(0.5),
        ..SimulationOptions::default()
    };
    let (line, column) = line_col(&text, "0.5 to 10");
    for error in [
        analysis.simulation(&options).unwrap_err(),
        analysis.settings(&options).unwrap_err(),
    ] {
        match error {
            Error::Located {
                message,
                line: l,
                column: c,
                kind,
            } => {
                assert_eq!((l, c, kind), (line, column, ErrorKind::Input), "{message}");
                assert!(
                    message.contains("t = 0.5: the time span is empty")
                        && message.contains("give an end time other than the start time"),
                    "{message}"
                );
            }
            other => panic!("{other:?}"),
        }
    }
    // The start from the caller, the end from the model: the end is pointed at. (Both in
    // the model, `simulate from 3 to 3`, is the model checker's error.)
    let options = SimulationOptions {
        t_start: Some(10.0),
        ..SimulationOptions::default()
    };
    let text = mutant("canonical/pendulum.lag", "from 0 to 10", "from 0 to 10.0");
    match Analysis::from_text(&text).unwrap().settings(&options) {
        Err(Error::Located { line, column, .. }) => {
            assert_eq!((line, column), line_col(&text, "10.0"));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn an_unknown_method_in_the_model_points_at_its_name() {
    let text = mutant(
        "simple-pendulum.lag",
        "simulate from 0 to 10",
        "simulate from 0 to 10 method leapfrog",
    );
    match Analysis::from_text(&text)
        .unwrap()
        .settings(&SimulationOptions::default())
    {
        Err(Error::Located {
            message,
            line,
            column,
            kind,
        }) => {
            assert_eq!((line, column), line_col(&text, "leapfrog"));
            assert_eq!(kind, ErrorKind::Input);
            assert!(message.contains("unknown method `leapfrog`"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_sampled_run_keeps_a_bounded_even_sample_and_the_last_row() {
    let options = SimulationOptions {
        t_end: Some(200.0),
        ..SimulationOptions::default()
    };
    let analysis = pendulum();
    let all = run_kept(&mut analysis.simulation(&options).unwrap());
    assert!(all.rows.len() > 1000, "{}", all.rows.len());
    let sampled = run_sampled(&mut analysis.simulation(&options).unwrap(), 100);
    assert_eq!(sampled.ending, Ending::Finished);
    assert!(
        sampled.rows.len() <= 201 && sampled.rows.len() >= 100,
        "{}",
        sampled.rows.len()
    );
    // Every kept row is the full run's row at a multiple of one stride, then the last one.
    let index = |row: &Vec<f64>| all.rows.iter().position(|r| r == row).unwrap();
    let stride = index(&sampled.rows[1]);
    assert!(stride.is_power_of_two(), "{stride}");
    for (k, row) in sampled.rows[..sampled.rows.len() - 1].iter().enumerate() {
        assert_eq!(index(row), k * stride);
    }
    assert_eq!(sampled.rows.last(), all.rows.last());
}
