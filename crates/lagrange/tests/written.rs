//! Runs written out (`lagrange::written`): the files a run asks for are created before it
//! starts, the CSV streams to its file or the writer given, the crossings, summary and plot
//! follow; a sweep refuses what describes one run and writes one table; no output is ever
//! the model file. Each mistake is a typed error of its kind (input, output), with no flag
//! name in it.

use std::io::Write;
use std::path::{Path, PathBuf};

use lagrange::{
    check_output, Analysis, Ending, Error, ErrorKind, OneRunOnly, RunFiles, SimulationOptions,
    SweepRequest,
};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// A fresh directory of its own under the target directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("written-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn options(t_end: f64) -> SimulationOptions {
    SimulationOptions {
        t_end: Some(t_end),
        ..SimulationOptions::default()
    }
}

/// A writer that refuses every byte, as a full disk does.
struct Full;

impl Write for Full {
    fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
        Err(std::io::Error::other("no space left on device"))
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[test]
fn a_run_writes_its_csv_events_summary_and_plot() {
    let dir = scratch("run");
    let model = example("simple-pendulum.lag");
    let analysis = Analysis::from_file(&model).unwrap();
    let files = RunFiles {
        model: model.clone(),
        csv: Some(dir.join("run.csv")),
        events: Some(dir.join("events.csv")),
        summary: Some(dir.join("summary.json")),
        plot: Some(dir.join("run.svg")),
        max_bytes: None,
    };
    let options = SimulationOptions {
        record_when: vec!["theta".into()],
        ..options(3.0)
    };
    let prepared = analysis.prepare_run(&options, files.clone()).unwrap();
    // Created before the run: a bad path would have failed here.
    for path in files.outputs().take(3) {
        assert!(path.exists(), "{}", path.display());
    }
    let mut out = Vec::new();
    let written = prepared.run(&mut out, &mut |_| {}).unwrap();
    // The CSV went to its file, not to the writer.
    assert!(out.is_empty());
    let csv = std::fs::read_to_string(dir.join("run.csv")).unwrap();
    assert!(
        csv.starts_with("t,theta,theta_d,energy_error,constraint_drift,pivot_x,pivot_y,pivot_z\n"),
        "{csv}"
    );
    assert_eq!(csv.lines().count() as u64, written.streamed.tally.rows + 1);
    // The pendulum swings through θ = 0: each crossing is a row of events, counted in the line.
    let crossings = written.streamed.tally.crossings.len();
    assert!(crossings >= 2, "{crossings}");
    let events = std::fs::read_to_string(dir.join("events.csv")).unwrap();
    assert_eq!(events.lines().count(), crossings + 1, "{events}");
    let line = written.crossings_line.as_deref().unwrap();
    assert!(
        line.starts_with(&format!("recorded {crossings} crossings")),
        "{line}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["outcome"]["kind"], "finished");
    assert_eq!(summary["rows"], written.streamed.tally.rows);
    assert_eq!(summary["model"], model.display().to_string());
    let svg = std::fs::read_to_string(dir.join("run.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("simple-pendulum"));
    assert!(written
        .summary_line
        .starts_with("dop853: t = 3.000000 of 3, "));
    assert_eq!(written.written, files.outputs().collect::<Vec<_>>());
    assert_eq!(written.streamed.ending, Ending::Finished);
}

#[test]
fn without_a_csv_file_the_rows_go_to_the_writer_and_a_full_one_is_an_output_error() {
    let analysis = Analysis::from_file(&example("simple-pendulum.lag")).unwrap();
    let files = RunFiles {
        model: example("simple-pendulum.lag"),
        ..RunFiles::default()
    };
    let mut out = Vec::new();
    let mut fractions = Vec::new();
    let written = analysis
        .prepare_run(&options(1.0), files.clone())
        .unwrap()
        .run(&mut out, &mut |f| fractions.push(f))
        .unwrap();
    let text = String::from_utf8(out).unwrap();
    assert_eq!(text.lines().count() as u64, written.streamed.tally.rows + 1);
    assert!(written.written.is_empty() && written.crossings_line.is_none());
    // Progress is the fraction of the span, rising from 0 to 1.
    assert_eq!(fractions.first(), Some(&0.0));
    assert_eq!(fractions.last(), Some(&1.0));
    assert!(fractions.windows(2).all(|w| w[0] <= w[1]));
    let error = analysis
        .prepare_run(&options(1.0), files)
        .unwrap()
        .run(&mut Full, &mut |_| {})
        .unwrap_err();
    assert!(
        matches!(&error, Error::Write { what, .. } if what == "the CSV"),
        "{error}"
    );
    assert_eq!(error.kind(), ErrorKind::Output);
}

#[test]
fn a_bad_plot_name_or_path_is_refused_before_the_run() {
    let dir = scratch("refused");
    let analysis = Analysis::from_file(&example("simple-pendulum.lag")).unwrap();
    let files = RunFiles {
        plot: Some(dir.join("run.pdf")),
        csv: Some(dir.join("run.csv")),
        ..RunFiles::default()
    };
    let error = analysis.prepare_run(&options(1.0), files).unwrap_err();
    assert!(error.to_string().contains(".svg or .png"), "{error}");
    assert_eq!(error.kind(), ErrorKind::Input);
    assert!(
        !dir.join("run.csv").exists(),
        "nothing is created for a refused run"
    );
    let files = RunFiles {
        summary: Some(dir.join("no-such-directory/summary.json")),
        ..RunFiles::default()
    };
    let error = analysis.prepare_run(&options(1.0), files).unwrap_err();
    assert!(matches!(error, Error::Create { .. }), "{error}");
    assert_eq!(error.kind(), ErrorKind::Input);
    assert!(!error.to_string().contains("--"), "no flag name: {error}");
}

#[test]
fn a_sweep_refuses_what_describes_one_run_and_writes_one_table() {
    let dir = scratch("sweep");
    let analysis = Analysis::from_file(&example("double-pendulum.lag")).unwrap();
    let ranges = vec!["theta1=0..1".to_owned()];
    let request = SweepRequest {
        ranges: &ranges,
        samples: None,
        steps: 3,
        seed: 1,
    };
    let refused = [
        (
            RunFiles {
                plot: Some(dir.join("p.svg")),
                ..RunFiles::default()
            },
            options(0.2),
            OneRunOnly::Plot,
        ),
        (
            RunFiles::default(),
            SimulationOptions {
                record_when: vec!["theta1".into()],
                ..options(0.2)
            },
            OneRunOnly::Crossings,
        ),
        (
            RunFiles {
                summary: Some(dir.join("s.json")),
                ..RunFiles::default()
            },
            options(0.2),
            OneRunOnly::Summary,
        ),
    ];
    for (files, options, what) in refused {
        let mut out = Vec::new();
        let error = analysis
            .write_sweep(&options, &request, &files, &mut out, &mut |_| {}, &|| {})
            .unwrap_err();
        assert!(
            matches!(error, Error::OneRunOnly(w) if w == what),
            "{error}"
        );
        assert_eq!(error.kind(), ErrorKind::Input);
        assert!(
            out.is_empty() && analysis.derivations() == 0,
            "refused before any work"
        );
    }
    let files = RunFiles {
        csv: Some(dir.join("sweep.csv")),
        ..RunFiles::default()
    };
    let mut out = Vec::new();
    let table = analysis
        .write_sweep(
            &options(0.2),
            &request,
            &files,
            &mut out,
            &mut |_| {},
            &|| {},
        )
        .unwrap();
    assert!(out.is_empty());
    let csv = std::fs::read_to_string(dir.join("sweep.csv")).unwrap();
    assert_eq!(csv, table.csv);
    assert_eq!(csv.lines().count(), 5);
    let line = table.summary_line();
    assert!(line.starts_with("4 runs on ") && line.contains("(1 derivation), 0 failed"));
}

#[test]
fn no_output_is_the_model_file() {
    let dir = scratch("check");
    let model = dir.join("m.lag");
    std::fs::write(&model, "coordinates x\n").unwrap();
    let error = check_output(&model, &model).unwrap_err();
    assert!(
        error.to_string().contains("never writes over its input"),
        "{error}"
    );
    assert_eq!(error.kind(), ErrorKind::Input);
    // The same file by another path is the same file.
    let other = dir.join(".").join("m.lag");
    assert!(check_output(&other, &model).is_err());
    assert!(!check_output(&dir.join("new.csv"), &model).unwrap());
    std::fs::write(dir.join("old.csv"), "").unwrap();
    assert!(check_output(&dir.join("old.csv"), &model).unwrap());
}

#[test]
fn values_ranges_and_deviations_read_the_models_values() {
    let analysis = Analysis::from_file(&example("double-pendulum.lag")).unwrap();
    let l1 = analysis
        .values()
        .unwrap()
        .into_iter()
        .find(|(n, _)| n == "l1");
    let l1 = l1.unwrap().1;
    assert_eq!(
        analysis.read_number("theta1=2*l1").unwrap(),
        ("theta1".into(), 2.0 * l1)
    );
    let range = analysis.read_range("theta1=-l1..pi").unwrap();
    assert_eq!((range.low, range.high), (-l1, std::f64::consts::PI));
    assert!(analysis.read_range("theta1=1..0").is_err());
    let coordinates = vec!["theta1".to_owned(), "theta2".to_owned()];
    let items = vec!["theta2=0.1".to_owned(), "theta1'=l1".to_owned()];
    let (dq, dv) = analysis.read_deviations(&items, &coordinates).unwrap();
    assert_eq!((dq, dv), (vec![0.0, 0.1], vec![l1, 0.0]));
    assert!(analysis
        .read_deviations(&["x=1".to_owned()], &coordinates)
        .is_err());
}

#[test]
fn reactions_print_as_text_and_json() {
    // The pendulum asks for the pivot's force: by both methods, and they agree.
    let analysis = Analysis::from_file(&example("simple-pendulum.lag")).unwrap();
    let reactions = analysis.reactions().unwrap().unwrap();
    assert!(!reactions.disagree());
    assert!(
        reactions.to_text().contains("pivot"),
        "{}",
        reactions.to_text()
    );
    let json = reactions.to_json();
    assert_eq!(json["reactions"][0]["name"], "pivot", "{json}");
}
