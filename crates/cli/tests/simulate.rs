//! `lagrange simulate`, run for real: the CSV's header and rows, `--set`, `--stop-when`,
//! plots, and the messages and exit codes of bad input and of a run that blows up.

use std::path::PathBuf;

mod common;
use common::{lagrange, stderr, stdout};

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn rows(csv: &str) -> Vec<Vec<f64>> {
    csv.lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect()
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lagrange-simulate-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn writes_the_csv_with_header_rows_and_summary() {
    let o = lagrange(&[
        "simulate",
        "examples/double-pendulum.lag",
        "--t-end",
        "2",
        "--output-step",
        "0.5",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    // The run's columns, then the reactions the model names (docs/reactions.md).
    assert_eq!(
        out.lines().next(),
        Some("t,theta1,theta2,theta1_d,theta2_d,energy_error,constraint_drift,top_x,top_y,top_z,middle_x,middle_y,middle_z")
    );
    let data = rows(&out);
    let times: Vec<f64> = data.iter().map(|r| r[0]).collect();
    assert_eq!(times, [0.0, 0.5, 1.0, 1.5, 2.0]);
    // The model's initial values.
    assert_eq!(&data[0][1..5], &[1.0, 0.0, 0.0, 0.5]);
    assert!(data.iter().all(|r| r[5].abs() < 1e-7 && r[6] == 0.0));
    let summary = text(&o.stderr);
    assert!(
        summary.starts_with("dop853: t = 2.000000 of 2, ") && summary.contains(" rejected), "),
        "{summary}"
    );
    assert!(summary.contains("evaluations") && summary.contains("final energy error"));
}

#[test]
fn set_overrides_parameters_and_initial_values() {
    let o = lagrange(&[
        "simulate",
        "examples/simple-pendulum.lag",
        "--t-end",
        "1",
        "--output-step",
        "1",
        "--set",
        "theta=0.01",
        "--set",
        "g=4*pi**2",
        "--set",
        "theta_d=0",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let data = rows(&text(&o.stdout));
    assert_eq!(data[0][1], 0.01);
    // l = 1, g = 4π²: the small-amplitude period is 1 s, so θ is back near 0.01.
    assert!((data[1][1] - 0.01).abs() < 1e-5, "{:?}", data[1]);

    let o = lagrange(&["simulate", "examples/simple-pendulum.lag", "--set", "k=1"]);
    assert_eq!(o.status.code(), Some(1));
    let err = text(&o.stderr);
    assert!(
        err.contains("`k` is not a parameter") && err.contains("theta_d"),
        "{err}"
    );
}

#[test]
fn stop_when_ends_the_run_at_the_crossing() {
    // From rest at θ = 0.5 the pendulum first passes θ = 0 after a quarter period.
    let o = lagrange(&[
        "simulate",
        "examples/simple-pendulum.lag",
        "--stop-when",
        "theta",
        "--rtol",
        "1e-10",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let data = rows(&text(&o.stdout));
    let last = data.last().unwrap();
    assert!(last[1].abs() < 1e-8, "{last:?}");
    // Quarter period K(sin ¼)/√g of a 0.5 rad pendulum with g = 9.81, l = 1: 0.509467 s
    // (complete elliptic integral K by its series to k⁸).
    assert!((last[0] - 0.509_467).abs() < 2e-6, "{last:?}");
    assert!(text(&o.stderr).contains("stopped at t = "));
}

#[test]
fn plots_svg_and_png_and_refuses_other_names() {
    for name in ["run.svg", "run.png"] {
        let path = temp(name);
        let csv = temp("run.csv");
        let o = lagrange(&[
            "simulate",
            "examples/cartesian-pendulum.lag",
            "--t-end",
            "1",
            "--out",
            csv.to_str().unwrap(),
            "--plot",
            path.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let bytes = std::fs::read(&path).unwrap();
        if name.ends_with("svg") {
            assert!(text(&bytes).contains("<svg") && text(&bytes).contains("constraint drift"));
        } else {
            assert_eq!(&bytes[1..4], b"PNG");
        }
    }
    let o = lagrange(&[
        "simulate",
        "examples/simple-pendulum.lag",
        "--plot",
        "run.pdf",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains(".svg or .png"));
}

#[test]
fn a_blow_up_stops_with_its_time_and_keeps_the_rows() {
    // The mass matrix 4 m x² vanishes at x = 0, which the motion reaches at t = 1/2.
    let model = temp("singular.lag");
    std::fs::write(
        &model,
        "coordinates x\nparameters m = 1\nframe N\npoint P = x^2*N.x\nparticle P mass m\n\
         initial x = 1, x' = -1\nsimulate to 2\n",
    )
    .unwrap();
    let o = lagrange(&["simulate", model.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(3));
    let err = text(&o.stderr);
    assert!(
        err.contains("error: the simulation stopped at t = 0.5"),
        "{err}"
    );
    assert!(err.contains("rows computed up to then were written"));
    let data = rows(&text(&o.stdout));
    assert!(data.len() > 10);
    assert!(data.iter().all(|r| r[0] < 0.5 + 1e-6));
}

#[test]
fn missing_values_and_bad_settings_are_clear_errors() {
    let model = temp("no-value.lag");
    std::fs::write(
        &model,
        "coordinates x\nparameters m, k = 1\nframe N\npoint P = x*N.x\nparticle P mass m\n\
         spring k from origin to P\ninitial x = 1\n",
    )
    .unwrap();
    let o = lagrange(&["simulate", model.to_str().unwrap(), "--t-end", "1"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("no value for `m`"),
        "{}",
        text(&o.stderr)
    );
    let o = lagrange(&["simulate", model.to_str().unwrap()]);
    assert!(text(&o.stderr).contains("no end time"));
    let o = lagrange(&[
        "simulate",
        "examples/cartesian-pendulum.lag",
        "--method",
        "gauss",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("does not handle constraints"));
    let o = lagrange(&["simulate", "examples/simple-pendulum.lag", "--rtol=-1"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("invalid setting `rtol`"));
}

#[test]
fn a_runaway_pendulum_stops_with_exit_3_keeping_its_rows_and_saying_why() {
    // Issue 14: `g = 1e300` used to write 4.7 GB of CSV in a minute.
    let dir = std::env::temp_dir().join(format!("lagrange-runaway-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let (csv, summary) = (dir.join("run.csv"), dir.join("summary.json"));
    let o = lagrange(&[
        "simulate",
        "examples/simple-pendulum.lag",
        "--set",
        "g=1e300",
        "--t-end",
        "1",
        "--out",
        csv.to_str().expect("a path"),
        "--summary",
        summary.to_str().expect("a path"),
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(err.contains("step size fell"), "{err}");
    let text = std::fs::read_to_string(&csv).expect("the rows so far");
    let rows = text.lines().count() - 1;
    assert!((1..1000).contains(&rows), "{rows} rows");
    assert!(
        text.lines()
            .nth(1)
            .is_some_and(|l| l.starts_with("0.0,0.5,")),
        "{text}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary).expect("the summary"))
            .expect("JSON");
    assert_eq!(json["outcome"]["kind"], "failed", "{json}");
    assert_eq!(json["outcome"]["failure"], "step_collapse", "{json}");
    assert!(json["outcome"]["numbers"]["h"]
        .as_f64()
        .is_some_and(|h| h < 1e-12));
    // A row limit from the command line: the same exit, the rows up to it.
    let o = lagrange(&[
        "simulate",
        "examples/simple-pendulum.lag",
        "--max-rows",
        "7",
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert_eq!(stdout(&o).lines().count(), 1 + 7);
    assert!(stderr(&o).contains("--max-rows"), "{}", stderr(&o));
}

/// An example model with `from` replaced by `to`, written to a temporary file.
fn mutant(example: &str, from: &str, to: &str) -> PathBuf {
    let text = std::fs::read_to_string(common::root().join("examples").join(example)).unwrap();
    assert!(text.contains(from));
    let path = temp(&format!("mutant-{}", example.replace('/', "-")));
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path
}

#[test]
fn limits_refusals_and_runaways_from_the_fuzzer_have_their_exit_codes() {
    // Rows beyond the row limit from the model's settings: refused at the `step`, exit 1.
    let model = mutant(
        "damped-oscillator.lag",
        "simulate from 0 to 30 step 0.01",
        "simulate from 0 to 1e308 step 0.01",
    );
    let o = lagrange(&["simulate", model.to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains(".lag:17:31: ") && err.contains("row limit"),
        "{err}"
    );
    // The same from the flags: no line, the flag named.
    let o = lagrange(&[
        "simulate",
        "examples/simple-pendulum.lag",
        "--t-end",
        "1e9",
        "--output-step",
        "1",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("(--max-rows N)"), "{err}");
    // The start time from the model equal to --t-end: exit 1 at the model's `from`.
    let model = mutant(
        "canonical/pendulum.lag",
        "simulate from 0 to 10",
        "simulate from 0.5 to 10",
    );
    let o = lagrange(&["simulate", model.to_str().unwrap(), "--t-end", "0.5"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains(".lag:15:15: ") && err.contains("span is empty"),
        "{err}"
    );
    // The byte limit: exit 3, the CSV within it, the flag named.
    let o = lagrange(&[
        "simulate",
        "examples/simple-pendulum.lag",
        "--t-end",
        "1000",
        "--max-bytes",
        "5000",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(
        o.stdout.len() <= 5000 && o.stdout.len() > 4000,
        "{}",
        o.stdout.len()
    );
    assert!(err.contains("--max-bytes N"), "{err}");
    // An end time of 1e29: `solve` finishes (exit 0) and says why its run stopped;
    // `simulate` stops at once, exit 3.
    let model = mutant(
        "simple-pendulum.lag",
        "simulate from 0 to 10",
        "simulate from 0 to 1e29",
    );
    let o = lagrange(&["solve", model.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("The run stopped at t = 0: the step size fell"),
        "{}",
        stdout(&o)
    );
    let o = lagrange(&["simulate", model.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert_eq!(stdout(&o).lines().count(), 2);
}
