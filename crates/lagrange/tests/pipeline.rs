//! The pipeline does each piece of work once: `solve` derives the equations once, a sweep of
//! many runs derives once, a simulation derives no reaction it does not need, and values set
//! after the derivation (numbers, functions of time) reach every later result.

use std::path::{Path, PathBuf};

use lagrange::{parse_assignment, Analysis, Ending, SimulationOptions};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

fn options(t_end: f64) -> SimulationOptions {
    SimulationOptions {
        t_end: Some(t_end),
        ..SimulationOptions::default()
    }
}

#[test]
fn the_solution_derives_the_equations_once() {
    for name in [
        "seed/7.1-cart-pendulum.lag",
        "seed/7.4-inverted-pendulum.lag",
        "particle-on-sphere.lag",
        "cartesian-pendulum.lag",
    ] {
        let analysis = Analysis::from_file(&example(name)).unwrap();
        let solution = analysis.solution(None).unwrap();
        assert!(!solution.document.sections.is_empty(), "{name}");
        assert_eq!(analysis.derivations(), 1, "{name}");
        // Reactions: at most once (all of them; the contacts reuse them).
        assert!(analysis.reaction_derivations() <= 1, "{name}");
    }
}

#[test]
fn a_sweep_of_many_runs_derives_once() {
    let analysis = Analysis::from_file(&example("double-pendulum.lag")).unwrap();
    let names = vec!["theta1".to_owned()];
    let values: Vec<Vec<f64>> = (0..40).map(|k| vec![0.05 * f64::from(k)]).collect();
    let runs = analysis
        .sweep(&options(1.0), &names, &values, &|| {})
        .unwrap();
    assert_eq!(runs.len(), 40);
    assert_eq!(analysis.derivations(), 1);
    // Each run started where it was asked to: run k against a single run of its own.
    let mut single = Analysis::from_file(&example("double-pendulum.lag")).unwrap();
    single.set_value("theta1", 0.05 * 7.0).unwrap();
    let run = single.simulate(&options(1.0)).unwrap();
    let last = run.rows.last().unwrap();
    let swept = &runs[7].as_ref().unwrap().last;
    for (a, b) in last.iter().zip(swept) {
        assert!((a - b).abs() < 1e-12, "{last:?} vs {swept:?}");
    }
}

#[test]
fn a_sweep_table_has_one_row_per_run_and_ranges_read_the_models_values() {
    let analysis = Analysis::from_file(&example("double-pendulum.lag")).unwrap();
    // `l1` is a parameter of the model: a range's ends may be expressions of its values.
    let values = analysis.values().unwrap();
    let l1 = values.iter().find(|(n, _)| n == "l1").unwrap().1;
    let ranges = vec!["theta1=0..l1/10".to_owned()];
    let request = lagrange::SweepRequest {
        ranges: &ranges,
        samples: None,
        steps: 4,
        seed: 1,
    };
    let mut planned = 0;
    let table = analysis
        .sweep_table(&options(0.5), &request, &mut |n| planned = n, &|| {})
        .unwrap();
    assert_eq!((planned, table.runs, table.failed), (5, 5, 0));
    let lines: Vec<&str> = table.csv.lines().collect();
    assert_eq!(lines.len(), 6, "{}", table.csv);
    assert!(lines[0].starts_with("run,theta1,final_t,"), "{}", lines[0]);
    let last_value: f64 = lines[5].split(',').nth(1).unwrap().parse().unwrap();
    assert!((last_value - l1 / 10.0).abs() < 1e-15);
    assert_eq!(analysis.derivations(), 1);
    // Two ranges without samples cannot be a grid: an error, not a guess.
    let two = vec!["theta1=0..1".to_owned(), "theta2=0..1".to_owned()];
    let request = lagrange::SweepRequest {
        ranges: &two,
        ..request
    };
    assert!(analysis
        .sweep_table(&options(0.5), &request, &mut |_| {}, &|| {})
        .is_err());
}

#[test]
fn a_simulation_derives_no_reaction_it_does_not_need() {
    // The four-bar asks for the reactions of its loop constraints, which are two-sided: the
    // run does not need them (deriving them takes far longer than the run).
    let analysis = Analysis::from_file(&example("four-bar.lag")).unwrap();
    let run = analysis.simulate(&options(0.5)).unwrap();
    assert_eq!(run.ending, Ending::Finished);
    assert_eq!(analysis.reaction_derivations(), 0);
    assert!(analysis.one_sided_contacts().unwrap().is_empty());

    // A contact decides where the run stops: only the one-sided reactions are derived.
    let sphere = Analysis::from_file(&example("particle-on-sphere.lag")).unwrap();
    let run = sphere.simulate(&options(5.0)).unwrap();
    assert!(
        matches!(run.ending, Ending::ContactLost { .. }),
        "{:?}",
        run.ending
    );
    assert_eq!(sphere.reaction_derivations(), 1);
}

#[test]
fn an_input_set_to_a_function_of_time_drives_the_run() {
    // x'' + 4x = sin t from rest: x = sin(t)/3 − sin(2t)/6.
    let text = "coordinates x
parameters m = 1, k = 4
inputs F = 0
frame N
point P = x*N.x
particle P mass m
spring k from origin to P
force F*N.x at P
";
    let mut analysis = Analysis::from_text(text).unwrap();
    analysis.equations().unwrap();
    analysis
        .set(&parse_assignment("F=sin(t)").unwrap())
        .unwrap();
    let mut opts = options(3.0);
    opts.rtol = Some(1e-11);
    opts.atol = Some(1e-12);
    let run = analysis.simulate(&opts).unwrap();
    for row in &run.rows {
        let t = row[0];
        let exact = t.sin() / 3.0 - (2.0 * t).sin() / 6.0;
        assert!(
            (row[1] - exact).abs() < 1e-8,
            "x({t}) = {} vs {exact}",
            row[1]
        );
    }
    assert_eq!(analysis.derivations(), 1);
    // Equilibria hold inputs constant: a function of time is refused, with the input named.
    let error = analysis.equilibria().unwrap_err();
    assert!(error.to_string().contains("`F`"), "{error}");
}

#[test]
fn values_set_later_reach_the_equilibria_and_the_report() {
    let mut analysis = Analysis::from_file(&example("seed/7.4-inverted-pendulum.lag")).unwrap();
    let before = analysis.equilibria().unwrap().set.equilibria.len();
    analysis.set(&parse_assignment("g=2*pi").unwrap()).unwrap();
    let after = analysis.equilibria().unwrap();
    assert_eq!(after.set.equilibria.len(), before);
    let g = analysis
        .values()
        .unwrap()
        .into_iter()
        .find(|(n, _)| n == "g")
        .map(|(_, v)| v);
    assert_eq!(g, Some(2.0 * std::f64::consts::PI));
    assert_eq!(analysis.derivations(), 1);
    // An unknown name is the user's mistake, with what can be set.
    let error = analysis
        .set(&parse_assignment("nope=1").unwrap())
        .unwrap_err();
    assert_eq!(error.kind(), lagrange::ErrorKind::Input);
    assert!(error.to_string().contains("theta_d"), "{error}");
}

#[test]
fn a_bad_setting_in_the_model_points_at_its_line_and_column() {
    let text = "coordinates x
parameters m = 1, k = 4, tol = 1e-10
frame N
point P = x*N.x
particle P mass m
spring k from origin to P
simulate to 2 atol tol
";
    let mut analysis = Analysis::from_text(text).unwrap();
    // Set to 0 later, so the checker could not see it: the error still points at the model.
    analysis.set_value("tol", 0.0).unwrap();
    let error = analysis
        .simulate(&SimulationOptions::default())
        .unwrap_err();
    match &error {
        lagrange::Error::Located { line, column, .. } => assert_eq!((*line, *column), (7, 20)),
        other => panic!("not located: {other}"),
    }
    assert!(error.to_string().contains("atol"), "{error}");
    // The same value given by the caller is the caller's: no model location.
    let options = SimulationOptions {
        atol: Some(-1.0),
        ..SimulationOptions::default()
    };
    let error = analysis.simulate(&options).unwrap_err();
    assert!(matches!(error, lagrange::Error::Simulation(_)), "{error}");
}

#[test]
fn reactions_too_large_for_a_closed_form_are_refused_and_the_solution_stands() {
    // Insisting on the closed form (by default the four-bar's reactions are evaluated
    // numerically: tests/issue_17_numeric_reactions.rs).
    let mut analysis = Analysis::from_file(&example("four-bar.lag")).unwrap();
    analysis.set_reaction_route(lagrange::ReactionRoute::ClosedForm);
    let error = analysis.reactions().unwrap_err();
    assert!(
        matches!(
            error,
            lagrange::Error::Reactions(lagrange::mechanics::ReactionError::TooLarge { .. })
        ),
        "{error}"
    );
    assert_eq!(error.kind(), lagrange::ErrorKind::Mechanics);
    // The solution keeps everything else and says why the reactions are missing.
    let solution = analysis.solution(None).unwrap();
    let text = solution.document.to_text();
    assert!(
        text.contains("Not derived: the reactions are too large"),
        "{text}"
    );
    assert_eq!(analysis.derivations(), 1);
}

#[test]
fn a_division_by_zero_in_the_model_is_an_error_at_its_divisor() {
    // Each was a silent `1/0²` in the kinetic energy, exit 0 (issue 14).
    for (position, column) in [
        ("l/0*sin(theta)*N.x - l*cos(theta)*N.y", 13),
        ("l/(2 - 2)*sin(theta)*N.x - l*cos(theta)*N.y", 13),
        ("l*(theta - theta)^-1*N.x - l*cos(theta)*N.y", 13),
    ] {
        let text = format!(
            "coordinates theta\nparameters m = 1, l = 1, g = 9.81\nframe N\npoint P = {position}\nparticle P mass m\ngravity -g*N.y\n"
        );
        let error = Analysis::from_text(&text)
            .and_then(|a| a.equations().map(|_| ()))
            .expect_err(position);
        assert_eq!(error.kind(), lagrange::ErrorKind::Input, "{position}");
        let rendered = error.render("m.lag", lagrange::model::RenderOptions::default());
        assert!(rendered.contains("division by zero"), "{rendered}");
        assert!(
            rendered.contains(&format!("4:{column}")),
            "{position}: {rendered}"
        );
    }
}
