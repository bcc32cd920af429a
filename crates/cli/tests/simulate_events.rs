//! `lagrange simulate --record-when` and `--summary`: the recorded zero crossings of a
//! pendulum against its exact period, both directions, together with `--stop-when`, a
//! column-pointing error for an unknown name, and the JSON summary of finished, stopped and
//! failed runs.

use std::path::PathBuf;

mod common;
use common::{lagrange, stderr};

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lagrange-events-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    dir.join(name)
}

/// `(event, direction, [t, q…, q̇…])` rows of an events CSV.
fn crossings(path: &PathBuf) -> (String, Vec<(String, String, Vec<f64>)>) {
    let text = std::fs::read_to_string(path).expect("the events file");
    let mut lines = text.lines();
    let header = lines.next().expect("a header").to_owned();
    let rows = lines
        .map(|line| {
            let fields: Vec<&str> = line.split(',').collect();
            let numbers = fields[2..]
                .iter()
                .map(|x| x.parse().expect("a number"))
                .collect();
            (fields[0].to_owned(), fields[1].to_owned(), numbers)
        })
        .collect();
    (header, rows)
}

fn summary(path: &PathBuf) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("the summary")).expect("JSON")
}

/// The period of a pendulum of length 1 released from rest at `theta0`:
/// `4 K(sin(θ₀/2)) / √g`, with `K(k) = π / (2 AGM(1, √(1 − k²)))`.
fn exact_period(theta0: f64, g: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (theta0 / 2.0).cos());
    for _ in 0..10 {
        (a, b) = ((a + b) / 2.0, (a * b).sqrt());
    }
    let k = std::f64::consts::PI / (2.0 * a);
    4.0 * k / g.sqrt()
}

#[test]
fn recorded_crossings_of_a_pendulum_follow_its_exact_period() {
    let events = temp("pendulum.csv");
    let json = temp("pendulum.json");
    let o = lagrange(&[
        "simulate",
        "examples/simple-pendulum.lag",
        "--t-end",
        "10",
        "--rtol",
        "1e-10",
        "--atol",
        "1e-12",
        "--record-when",
        "theta",
        "--record-when",
        "theta_d",
        "--events",
        events.to_str().expect("a path"),
        "--summary",
        json.to_str().expect("a path"),
        "--out",
        temp("run.csv").to_str().expect("a path"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (header, rows) = crossings(&events);
    assert_eq!(header, "event,direction,t,theta,theta_d");
    let period = exact_period(0.5, 9.81);
    // θ = 0 at (2k + 1) T/4, falling for even k; θ̇ = 0 at k T/2 (k ≥ 1; t = 0 is the start,
    // not a crossing), rising for odd k (θ at its lowest).
    let theta: Vec<_> = rows.iter().filter(|r| r.0 == "theta").collect();
    let rate: Vec<_> = rows.iter().filter(|r| r.0 == "theta_d").collect();
    assert_eq!(
        theta.len(),
        ((10.0 / period - 0.25) * 2.0).floor() as usize + 1
    );
    assert_eq!(rate.len(), (10.0 / period * 2.0).floor() as usize);
    assert!(theta.len() >= 9, "several periods: {}", theta.len());
    for (k, (_, direction, row)) in theta.iter().enumerate() {
        let exact = (2 * k + 1) as f64 * period / 4.0;
        assert!(
            (row[0] - exact).abs() < 1e-8,
            "θ crossing {k}: {} vs {exact}",
            row[0]
        );
        assert_eq!(direction, if k % 2 == 0 { "falling" } else { "rising" });
        assert!(row[1].abs() < 1e-9, "θ = {} at its crossing", row[1]);
        // Through the bottom at full speed: ½θ̇² = g(1 − cos θ₀).
        let speed = (2.0 * 9.81 * (1.0 - 0.5f64.cos())).sqrt();
        assert!((row[2].abs() - speed).abs() < 1e-7, "{row:?}");
    }
    for (k, (_, direction, row)) in rate.iter().enumerate() {
        let exact = (k + 1) as f64 * period / 2.0;
        assert!(
            (row[0] - exact).abs() < 1e-8,
            "θ̇ crossing {k}: {} vs {exact}",
            row[0]
        );
        assert_eq!(direction, if k % 2 == 0 { "rising" } else { "falling" });
        assert!((row[1].abs() - 0.5).abs() < 1e-8, "{row:?}");
    }
    // In time order.
    assert!(rows.windows(2).all(|w| w[0].2[0] <= w[1].2[0]));
    let err = stderr(&o);
    assert!(
        err.contains(&format!(
            "recorded {} crossings: `theta` falling at t = 0.5094",
            rows.len()
        )),
        "{err}"
    );

    let s = summary(&json);
    assert_eq!(s["schema"], 1);
    // No method named: at rtol 1e-10 the default is dop853 (issue 20).
    assert_eq!(s["method"], "dop853");
    assert_eq!(s["rtol"], 1e-10);
    assert_eq!(s["atol"], 1e-12);
    assert_eq!(s["t_start"], 0.0);
    assert_eq!(s["t_end"], 10.0);
    assert_eq!(s["t_reached"], 10.0);
    assert_eq!(s["outcome"]["kind"], "finished");
    let events = s["events"].as_array().expect("events");
    assert_eq!(events.len(), rows.len());
    assert_eq!(events[0]["event"], "theta");
    assert_eq!(events[0]["direction"], "falling");
    // serde_json reads floats to within an ulp, not always exactly.
    let close = |v: &serde_json::Value, x: f64| {
        (v.as_f64().expect("a number") - x).abs() <= 1e-15 * x.abs().max(1.0)
    };
    assert!(close(&events[0]["t"], rows[0].2[0]));
    assert!(close(&events[0]["state"]["theta_d"], rows[0].2[2]));
    // The numbers agree with the summary line on stderr.
    let steps = s["steps"].as_u64().expect("steps");
    let evaluations = s["rhs_evaluations"].as_u64().expect("evaluations");
    assert!(err.contains(&format!(
        "{steps} steps ({} rejected), {evaluations} evaluations",
        s["rejected_steps"]
    )));
    assert!(evaluations >= 6 * steps && steps > 100);
    let energy = s["final_energy_error"].as_f64().expect("a number");
    assert!(energy.abs() < 1e-8 && energy != 0.0, "{energy}");
    assert_eq!(s["max_constraint_drift"], 0.0);
    assert!(s["wall_time_s"].as_f64().expect("a number") > 0.0);
}

#[test]
fn crossings_stop_with_the_stop_event_and_bad_names_point_at_their_column() {
    let events = temp("stopped.csv");
    let json = temp("stopped.json");
    let o = lagrange(&[
        "simulate",
        "examples/simple-pendulum.lag",
        "--t-end",
        "10",
        "--record-when",
        "theta",
        "--stop-when",
        "t - 3",
        "--events",
        events.to_str().expect("a path"),
        "--summary",
        json.to_str().expect("a path"),
        "--out",
        temp("stopped-run.csv").to_str().expect("a path"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (_, rows) = crossings(&events);
    // θ = 0 at T/4, 3T/4, 5T/4 before t = 3 (T ≈ 2.04).
    assert_eq!(rows.len(), 3);
    assert!(rows.iter().all(|r| r.2[0] < 3.0));
    let s = summary(&json);
    assert_eq!(s["outcome"]["kind"], "event");
    assert_eq!(s["outcome"]["event"], "t - 3");
    assert!((s["outcome"]["t"].as_f64().expect("t") - 3.0).abs() < 1e-12);
    assert_eq!(s["t_reached"], s["outcome"]["t"]);

    let o = lagrange(&[
        "simulate",
        "examples/simple-pendulum.lag",
        "--record-when",
        "theta",
        "--record-when",
        "sin(theta) + omega*t",
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(
        err.contains("--record-when: unknown name `omega` at column 14")
            && err.contains("t, theta, theta_d"),
        "{err}"
    );
    let o = lagrange(&[
        "simulate",
        "examples/simple-pendulum.lag",
        "--stop-when",
        "thet",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("--stop-when: unknown name `thet` at column 1"),
        "{}",
        stderr(&o)
    );
    let o = lagrange(&[
        "simulate",
        "examples/simple-pendulum.lag",
        "--record-when",
        "theta +* 1",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("at column 8"), "{}", stderr(&o));
}

#[test]
fn the_summary_of_a_failed_run_says_when_and_why() {
    // The mass matrix 4 m x² vanishes at x = 0, which the motion reaches at t = 1/2.
    let model = temp("singular.lag");
    std::fs::write(
        &model,
        "coordinates x\nparameters m = 1\nframe N\npoint P = x^2*N.x\nparticle P mass m\n\
         initial x = 1, x' = -1\nsimulate to 2\n",
    )
    .expect("the model is written");
    let json = temp("failed.json");
    let o = lagrange(&[
        "simulate",
        model.to_str().expect("a path"),
        "--summary",
        json.to_str().expect("a path"),
        "--out",
        temp("failed.csv").to_str().expect("a path"),
    ]);
    assert_eq!(o.status.code(), Some(3));
    let s = summary(&json);
    assert_eq!(s["outcome"]["kind"], "failed");
    let t = s["outcome"]["t"].as_f64().expect("t");
    assert!((t - 0.5).abs() < 1e-6, "{t}");
    let reason = s["outcome"]["reason"].as_str().expect("a reason");
    assert!(!reason.starts_with("at t"), "{reason}");
    assert!(s["rows"].as_u64().expect("rows") > 10);
    assert_eq!(s["events"], serde_json::json!([]));
}
