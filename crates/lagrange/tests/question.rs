//! A whole question about rest states answered by the library (`Analysis::answer`): the same
//! text as the calls it stands for, sweeps and Floquet analyses from one entry point, and every
//! refusal typed with the part of the question at fault (no option names of any front end).

use std::path::Path;

use lagrange::{
    Analysis, EquilibriumQuestion, Error, Misuse, QuestionPart, ResultFormat, Search, Written,
};

fn example(name: &str) -> Analysis {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    Analysis::from_file(&path).expect("the example reads")
}

fn list(items: &[&str]) -> Vec<String> {
    items.iter().map(|s| (*s).to_string()).collect()
}

#[test]
fn the_equilibria_question_gives_the_equilibria_written() {
    let analysis = example("simple-pendulum.lag");
    let question = EquilibriumQuestion {
        steps: 20,
        ..EquilibriumQuestion::default()
    };
    let answer = analysis.answer(&question).unwrap();
    let direct = analysis.equilibria_with(&Search::default()).unwrap();
    assert_eq!(answer.text, direct.written(ResultFormat::Text));
    assert_eq!(answer.figure, None);
}

#[test]
fn a_linearization_with_a_deviation_gives_the_free_response() {
    let analysis = example("simple-pendulum.lag");
    let initial = list(&["theta=0.01"]);
    let question = EquilibriumQuestion {
        format: ResultFormat::Json,
        linearize: Some(&initial),
        only: Some(0),
        ..EquilibriumQuestion::default()
    };
    let answer = analysis.answer(&question).unwrap();
    let json: serde_json::Value = serde_json::from_str(&answer.text).unwrap();
    let text = json.to_string();
    assert!(text.contains("free_response"), "{text}");
}

#[test]
fn a_sweep_is_answered_at_every_step_and_its_diagram_drawn() {
    let analysis = example("bead-on-rotating-hoop.lag");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("question-sweep");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let plot = dir.join("bifurcation.svg");
    let sweeps = list(&["Omega=0..10"]);
    let question = EquilibriumQuestion {
        format: ResultFormat::Json,
        sweeps: &sweeps,
        steps: 4,
        plot: Some(&plot),
        ..EquilibriumQuestion::default()
    };
    let answer = analysis.answer(&question).unwrap();
    assert_eq!(answer.figure.as_deref(), Some(plot.as_path()));
    assert!(std::fs::read_to_string(&plot).unwrap().starts_with("<svg"));
    let json: serde_json::Value = serde_json::from_str(&answer.text).unwrap();
    let steps = json["sweep"].as_array().expect("a step list");
    assert_eq!(steps.len(), 5, "{json}");
}

#[test]
fn parts_that_do_not_go_together_are_refused_by_part() {
    let analysis = example("kapitza-pendulum.lag");
    let ranges = list(&["x=-1..1"]);
    let question = EquilibriumQuestion {
        ranges: &ranges,
        periodic: Some(""),
        ..EquilibriumQuestion::default()
    };
    let error = analysis.answer(&question).unwrap_err();
    assert_eq!(error.part, Some(QuestionPart::Range));
    let Error::Misuse(misuse) = &*error.error else {
        panic!("a misuse, not {:?}", error.error)
    };
    assert_eq!(
        *misuse,
        Misuse::NotWith {
            part: QuestionPart::Range,
            with: QuestionPart::Periodic
        }
    );
    // The library names parts in words; a front end names them by its options.
    assert_eq!(
        misuse.to_string(),
        "a search range does not go with a Floquet analysis"
    );
    let named = misuse.sentence(|part| format!("<{part:?}>"));
    assert_eq!(named, "<Range> does not go with <Periodic>");
}

#[test]
fn a_plot_without_a_sweep_and_a_third_sweep_are_refused() {
    let analysis = example("simple-pendulum.lag");
    let plot = Path::new("never-written.svg");
    let question = EquilibriumQuestion {
        plot: Some(plot),
        ..EquilibriumQuestion::default()
    };
    let error = analysis.answer(&question).unwrap_err();
    assert_eq!(error.part, Some(QuestionPart::Plot));
    assert!(!plot.exists());
    let sweeps = list(&["g=1..2", "m=1..2"]);
    let question = EquilibriumQuestion {
        sweeps: &sweeps,
        ..EquilibriumQuestion::default()
    };
    let error = analysis.answer(&question).unwrap_err();
    assert!(matches!(
        *error.error,
        Error::Misuse(Misuse::TooManySweeps { most: 1 })
    ));
}

#[test]
fn a_value_that_does_not_read_is_refused_at_its_part() {
    let analysis = example("simple-pendulum.lag");
    let steady = list(&["nonsense"]);
    let question = EquilibriumQuestion {
        steady: &steady,
        ..EquilibriumQuestion::default()
    };
    let error = analysis.answer(&question).unwrap_err();
    assert_eq!(error.part, Some(QuestionPart::Steady));
    assert!(matches!(*error.error, Error::Assignment(_)), "{error:?}");
    let index = EquilibriumQuestion {
        only: Some(7),
        linearize: Some(&[]),
        ..EquilibriumQuestion::default()
    };
    let error = analysis.answer(&index).unwrap_err();
    assert_eq!(error.part, Some(QuestionPart::Only));
    assert!(matches!(
        *error.error,
        Error::NoSuchEquilibrium { index: 7, .. }
    ));
}

#[test]
fn a_floquet_analysis_is_answered_and_a_missing_motion_refused() {
    let analysis = example("kapitza-pendulum.lag");
    let question = EquilibriumQuestion {
        periodic: Some(""),
        ..EquilibriumQuestion::default()
    };
    let answer = analysis.answer(&question).unwrap();
    assert!(answer.text.contains("multipliers"), "{}", answer.text);
    let question = EquilibriumQuestion {
        periodic: Some(""),
        only: Some(99),
        ..EquilibriumQuestion::default()
    };
    let error = analysis.answer(&question).unwrap_err();
    assert!(matches!(
        *error.error,
        Error::Misuse(Misuse::NoSuchMotion { index: 99, .. })
    ));
}
