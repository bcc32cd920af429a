//! Issue 17: `lagrange linearize --periodic` on the command line — Kapitza's pendulum and
//! Mathieu's equation were refused ("the rest equations depend on time"); now their Floquet
//! multipliers and verdicts are printed (text and JSON), `--sweep` writes the stability chart
//! as CSV and `--plot` draws it, and what cannot be done is refused with the flag's name.

mod common;
use common::run;

#[test]
fn kapitza_upright_is_stable_and_slow_driving_makes_it_unstable() {
    let (ok, text, err) = run(&["linearize", "examples/kapitza-pendulum.lag", "--periodic"]);
    assert!(ok, "{err}");
    assert!(text.contains("period T = 0.020944 (the common period of the driving)"));
    assert!(text.contains("#1: equilibrium at every t: theta = 3.141593"));
    assert!(!text.contains("unstable"), "{text}");
    // a²ω²/(2gℓ) = 0.25 at ω = 100: the top falls.
    let (ok, text, _) = run(&[
        "linearize",
        "examples/kapitza-pendulum.lag",
        "--periodic",
        "--set",
        "omega=100",
        "--equilibrium",
        "1",
    ]);
    assert!(ok);
    assert!(
        text.contains("theta = 3.141593") && text.contains("unstable: |μ|"),
        "{text}"
    );
    assert!(!text.contains("#1"), "{text}");
}

#[test]
fn mathieu_json_has_the_documented_keys() {
    let (ok, text, err) = run(&[
        "linearize",
        "examples/mathieu.lag",
        "--periodic",
        "2*pi",
        "--format",
        "json",
    ]);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["schema"], 1);
    assert_eq!(v["period_source"], "given");
    let motion = &v["motions"][0];
    assert_eq!(motion["base"], "equilibrium");
    assert_eq!(motion["verdict"], "unstable");
    assert_eq!(motion["monodromy"].as_array().unwrap().len(), 2);
    let largest = motion["largest_multiplier"].as_f64().unwrap();
    assert!((largest - 1.853428).abs() < 1e-6, "{largest}");
    for key in ["multipliers", "exponents"] {
        assert_eq!(motion[key].as_array().unwrap().len(), 2);
        assert!(motion[key][0]["abs"].is_number());
    }
}

#[test]
fn a_sweep_writes_the_chart_and_its_plot() {
    let dir = std::env::temp_dir().join(format!("lagrange-floquet-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let plot = dir.join("ince-strutt.svg");
    let (ok, text, err) = run(&[
        "linearize",
        "examples/mathieu.lag",
        "--periodic",
        "--sweep",
        "delta=-0.5..1.5",
        "--sweep",
        "eps=0..1",
        "--steps",
        "8",
        "--plot",
        plot.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("delta,eps,verdict_0,max_abs_multiplier_0")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 81);
    // δ = 0.25, ε = 0.5: inside the first tongue; δ = 0.75, ε = 0.125: stable (marginally), between the first two tongues.
    let at = |d: &str, e: &str| rows.iter().find(|r| r[0] == d && r[1] == e).unwrap()[2];
    assert_eq!(at("0.25", "0.5"), "unstable");
    assert_eq!(at("0.75", "0.125"), "marginal");
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("stability chart"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn what_cannot_be_done_is_refused_with_the_flag() {
    let (ok, _, err) = run(&["linearize", "examples/simple-pendulum.lag", "--periodic"]);
    assert!(!ok);
    assert!(
        err.contains("--periodic") && err.contains("do not depend on time"),
        "{err}"
    );
    let (ok, _, err) = run(&["linearize", "examples/mathieu.lag", "--periodic=-1"]);
    assert!(!ok);
    assert!(err.contains("positive"), "{err}");
    let (ok, _, err) = run(&[
        "linearize",
        "examples/mathieu.lag",
        "--periodic",
        "--sweep",
        "nope=0..1",
    ]);
    assert!(!ok);
    assert!(err.contains("nope"), "{err}");
    let (ok, _, err) = run(&[
        "equilibria",
        "examples/simple-pendulum.lag",
        "--sweep",
        "g=1..2",
        "--sweep",
        "l=1..2",
    ]);
    assert!(!ok);
    assert!(err.contains("--sweep"), "{err}");
}
