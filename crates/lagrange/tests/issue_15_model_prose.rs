//! Issue 15: a teacher publishes `lagrange solve`'s report as it is, so the model must be able
//! to say in words what the report is about. Before, the title was the first sentence of the
//! file's opening comment ("Exercise 7.x of the seed: …"), there was no problem statement, and
//! the modelling decisions and the source's own mistakes (7.3's gear sign, its mass written
//! `m` and `m₁`, 7.2's `I_y = I_z`) lived only in `.lag` comments that no report showed.
//! `title`, `problem` and `note` statements now carry them into every format.

use lagrange::Analysis;

const MODEL: &str = r#"
# An opening comment that is no longer the title.
title "A pendulum — as the course writes it"
problem "A bob of mass m hangs on a rod of length ℓ." \
        "Find its equation of motion."
problem "Then find its equilibria."
note "The rod is massless & rigid (100%)."
note "θ = 0 hangs down."
coordinates theta
parameters m = 1, l = 1, g = 9.81
frame N
point P = l*sin(theta)*N.x - l*cos(theta)*N.y
particle P mass m
gravity -g*N.y
"#;

fn solution() -> report::document::Document {
    let analysis = Analysis::from_text(MODEL).expect("the model checks");
    analysis.solution(None).expect("a solution").document
}

#[test]
fn the_title_problem_and_notes_appear_in_every_format() {
    let document = solution();
    assert_eq!(document.title, "A pendulum — as the course writes it");
    let titles: Vec<&str> = document.sections.iter().map(|s| s.title.as_str()).collect();
    assert_eq!(titles[..3], ["Problem", "Notes on the model", "The system"]);

    let text = document.to_text();
    assert!(
        text.starts_with("A pendulum — as the course writes it\n═"),
        "{text}"
    );
    assert!(text.contains("Problem\n───────\nA bob of mass m hangs on a rod of length ℓ. Find its equation of motion.\n\nThen find"), "{text}");
    assert!(
        text.contains("• The rod is massless & rigid (100%).\n• θ = 0 hangs down."),
        "{text}"
    );

    let md = document.to_markdown();
    assert!(
        md.starts_with("# A pendulum — as the course writes it\n\n## Problem\n\nA bob of mass m hangs on a rod of length $\\ell$."),
        "{md}"
    );
    assert!(
        md.contains(
            "## Notes on the model\n\n- The rod is massless & rigid (100%).\n- $\\theta = 0$ hangs down.\n"
        ),
        "{md}"
    );

    let tex = document.to_latex();
    assert!(
        tex.contains("\\title{A pendulum --- as the course writes it}"),
        "{tex}"
    );
    assert!(tex.contains("\\begin{itemize}\n\\item The rod is massless \\& rigid (100\\%).\n\\item $\\theta = 0$ hangs down.\n\\end{itemize}"), "{tex}");

    let json = document.to_json();
    assert_eq!(json["title"], "A pendulum — as the course writes it");
    assert_eq!(
        json["sections"][0]["blocks"][1]["text"],
        "Then find its equilibria."
    );
    assert_eq!(json["sections"][1]["blocks"][0]["kind"], "list");
    assert_eq!(
        json["sections"][1]["blocks"][0]["items"][1],
        "θ = 0 hangs down."
    );
}

#[test]
fn without_a_title_the_opening_comment_still_titles_the_report() {
    let model = MODEL.replace("title \"A pendulum — as the course writes it\"\n", "");
    let analysis = Analysis::from_text(&model).expect("the model checks");
    assert_eq!(
        analysis.title(),
        "An opening comment that is no longer the title"
    );
}

/// The codes of the model's mistakes.
fn codes(text: &str) -> Vec<&'static str> {
    match Analysis::from_text(text) {
        Err(lagrange::Error::Model(errors)) => {
            errors.diagnostics.iter().map(|d| d.kind.code()).collect()
        }
        other => panic!("expected model errors, got {other:?}"),
    }
}

#[test]
fn a_second_title_and_an_unclosed_text_are_errors() {
    assert_eq!(codes(&format!("{MODEL}title \"again\"\n")), ["E316"]);
    let open = MODEL.replace("note \"θ = 0 hangs down.\"", "note \"θ = 0 hangs down.");
    assert_eq!(codes(&open), ["E010"]);
    assert_eq!(codes(&format!("{MODEL}note 3\n")), ["E002"]);
}

#[test]
fn every_seed_exercise_has_a_title_a_problem_and_notes() {
    let seed = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/seed");
    for n in 1..=4 {
        let path = std::fs::read_dir(&seed)
            .expect("examples/seed")
            .flatten()
            .map(|e| e.path())
            .find(|p| {
                p.extension().is_some_and(|e| e == "lag")
                    && p.file_name()
                        .is_some_and(|f| f.to_string_lossy().starts_with(&format!("7.{n}-")))
            })
            .expect("the exercise's model");
        let analysis = Analysis::from_file(&path).expect("the seed model checks");
        assert!(
            analysis.title().starts_with(&format!("Exercise 7.{n} — ")),
            "{}",
            analysis.title()
        );
        let prose = analysis.source().expect("a source").model.prose();
        assert!(
            !prose.problem.is_empty() && !prose.notes.is_empty(),
            "7.{n}"
        );
    }
    // The source's own mistakes are said in the report, not only in comments.
    let gears = Analysis::from_file(&seed.join("7.3-gears-pendulum.lag")).expect("7.3");
    let notes = gears
        .source()
        .expect("a source")
        .model
        .prose()
        .notes
        .join(" ");
    assert!(
        notes.contains("counter-rotate") && notes.contains("m in U") && notes.contains("Q_θ = −C"),
        "{notes}"
    );
    let cone = Analysis::from_file(&seed.join("7.2-rolling-cone.lag")).expect("7.2");
    let notes = cone
        .source()
        .expect("a source")
        .model
        .prose()
        .notes
        .join(" ");
    assert!(notes.contains("I_y = I_z"), "{notes}");
}
