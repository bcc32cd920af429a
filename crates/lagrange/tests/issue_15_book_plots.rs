//! Issue 15: the solution's simulation figure dropped the model's `output` quantities (7.4's
//! `tip_height`), and where an input torque did work it reported a "relative energy error" of
//! 30 %: the work, not the integrator's error. The figure now has a panel for the outputs, with
//! their unit where the geometry gives it, and when inputs do work the energy panel and the
//! section's sentence give the balance `E − E₀ − W` (W the integral of the inputs' power along
//! the dense output), which stays at the integrator's accuracy.

use std::path::{Path, PathBuf};

use lagrange::{Analysis, Figures};

const DRIVEN: &str = "\
coordinates theta
parameters  m = 1, l = 1, g = 9.81
inputs      C = 2*sin(3*t)
frame N
point P = l*sin(theta)*N.x - l*cos(theta)*N.y
particle P mass m
gravity -g*N.y
generalized force C on theta
initial theta = 0.1
simulate to 10
";

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lagrange-i15-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    dir
}

/// The number after `what` in `text`.
fn number_after(text: &str, what: &str) -> f64 {
    let from = text
        .find(what)
        .unwrap_or_else(|| panic!("no `{what}` in {text}"))
        + what.len();
    let word: String = text[from..]
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | '-' | '−' | '+'))
        .collect();
    word.replace('−', "-")
        .parse()
        .unwrap_or_else(|_| panic!("`{word}` after `{what}`"))
}

#[test]
fn the_work_of_an_input_torque_is_balanced_not_an_error() {
    let analysis = Analysis::from_text(DRIVEN).expect("the model checks");
    let dir = scratch("driven");
    let figures = Figures {
        directory: dir.clone(),
        stem: "driven".into(),
        extension: "svg",
    };
    let text = analysis
        .solution(Some(&figures))
        .expect("solution")
        .document
        .to_text()
        .replace('\n', " ");
    let balance = number_after(&text, "the energy balance (E − E₀ − W)/|E₀| is");
    let changed = number_after(&text, "the energy itself changed by");
    assert!(balance.abs() < 1e-6, "balance {balance}");
    assert!(changed.abs() > 1e-2, "the torque does work: {changed}");
    let svg = std::fs::read_to_string(dir.join("driven-motion.svg")).expect("the plot");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(svg.contains("energy balance"), "the panel's caption");
    assert!(!svg.contains("relative energy error"));
    assert!(text.contains("phase portraits and energy balance of the run"));
}

#[test]
fn without_inputs_the_energy_error_stays() {
    let text = DRIVEN
        .replace("inputs      C = 2*sin(3*t)\n", "")
        .replace("generalized force C on theta\n", "");
    let analysis = Analysis::from_text(&text).expect("the model checks");
    let text = analysis
        .solution(None)
        .expect("solution")
        .document
        .to_text()
        .replace('\n', " ");
    assert!(number_after(&text, "Relative energy error").abs() < 1e-6);
    assert!(!text.contains("energy balance"));
}

#[test]
fn the_tip_height_has_a_panel_with_its_unit_and_the_state_is_mathematics() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/seed/7.4-inverted-pendulum.lag");
    let text = std::fs::read_to_string(path).expect("the seed model");
    let analysis = Analysis::from_text(&text).expect("the model checks");
    let dir = scratch("tip");
    let figures = Figures {
        directory: dir.clone(),
        stem: "tip".into(),
        extension: "svg",
    };
    let document = analysis
        .solution(Some(&figures))
        .expect("solution")
        .document;
    let svg = std::fs::read_to_string(dir.join("tip-motion.svg")).expect("the plot");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        svg.contains("tip_height (m)"),
        "the output's axis and legend"
    );
    let markdown = document.to_markdown();
    assert!(
        markdown.contains("the model's outputs (tip_height)"),
        "{markdown}"
    );
    // Every state value is typeset: θ̇ as well as ẋ and x.
    let line = markdown
        .lines()
        .find(|l| l.starts_with("At $t = "))
        .unwrap_or_else(|| panic!("the final state: {markdown}"));
    assert!(line.contains(r"$\dot{\theta} = "), "{line}");
    assert!(
        line.contains("$x = ") && line.contains(r"$\dot{x} = "),
        "{line}"
    );
    assert!(!line.contains("theta_d"), "{line}");
}
