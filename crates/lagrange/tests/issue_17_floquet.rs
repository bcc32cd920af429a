//! Issue 17: time-periodic systems (Kapitza's pendulum, Mathieu's equation) were refused
//! ("the rest equations depend on time") and no tool here gave their stability.
//!
//! Fix: Floquet analysis (`Analysis::floquet`): the period of the driving read off the
//! equations, the equilibria that hold at every t found, the variational equations (symbolic
//! Jacobian, compiled) integrated over one period to the monodromy matrix, whose eigenvalues
//! (the multipliers) decide. Checked here against what is known in closed form: Mathieu's
//! transition curves for small ε (δ = 1/4 ± ε/2 − ε²/8, δ = −ε²/2 + 7ε⁴/32), the constant-
//! coefficient limit ε = 0, Kapitza's criterion a²ω²/(2gℓ) > 1 for fast driving, and the
//! periodic orbit of a forced damped oscillator (found by shooting); and against a chart
//! computed by SciPy (tests/data/mathieu_scipy.csv, made by tools/scipy_reference/mathieu.sh).

use std::path::Path;

use lagrange::report::floquet::{Base, PeriodSource, Verdict};
use lagrange::{Analysis, Error, FloquetError, FloquetOptions, Range};

fn example(name: &str) -> Analysis {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    Analysis::from_file(&path).expect("a valid example")
}

/// Whether the first motion is stable (or marginally) at these values.
fn bounded(analysis: &mut Analysis, values: &[(&str, f64)]) -> bool {
    for (name, v) in values {
        analysis.set_value(name, *v).unwrap();
    }
    let floquet = analysis.floquet(&FloquetOptions::default()).unwrap();
    floquet.results.last().unwrap().verdict.bounded()
}

/// The value of `name` in `[low, high]` where the verdict changes, by bisection (the verdict
/// at `low` differs from the one at `high`).
fn boundary(analysis: &mut Analysis, name: &str, mut low: f64, mut high: f64) -> f64 {
    let at_low = bounded(analysis, &[(name, low)]);
    assert_ne!(
        at_low,
        bounded(analysis, &[(name, high)]),
        "no change in {low}..{high}"
    );
    for _ in 0..40 {
        let mid = 0.5 * (low + high);
        if bounded(analysis, &[(name, mid)]) == at_low {
            low = mid;
        } else {
            high = mid;
        }
    }
    0.5 * (low + high)
}

#[test]
fn mathieu_first_tongue_matches_its_small_eps_expansion() {
    let mut mathieu = example("mathieu.lag");
    for eps in [0.05, 0.1, 0.2] {
        mathieu.set_value("eps", eps).unwrap();
        let lower = boundary(&mut mathieu, "delta", 0.1, 0.25);
        let upper = boundary(&mut mathieu, "delta", 0.25, 0.45);
        let expected_lower = 0.25 - eps / 2.0 - eps * eps / 8.0;
        let expected_upper = 0.25 + eps / 2.0 - eps * eps / 8.0;
        // The next terms are O(ε³): ±ε³/32 in δ.
        let tolerance = eps.powi(3) / 16.0;
        assert!(
            (lower - expected_lower).abs() < tolerance,
            "ε = {eps}: lower edge {lower} against {expected_lower}"
        );
        assert!(
            (upper - expected_upper).abs() < tolerance,
            "ε = {eps}: upper edge {upper} against {expected_upper}"
        );
    }
}

#[test]
fn mathieu_zeroth_curve_matches_its_small_eps_expansion() {
    let mut mathieu = example("mathieu.lag");
    for eps in [0.1, 0.2, 0.4] {
        mathieu.set_value("eps", eps).unwrap();
        let found = boundary(&mut mathieu, "delta", -eps * eps, 0.0);
        let expected = -eps * eps / 2.0 + 7.0 * eps.powi(4) / 32.0;
        // The next term is −29 ε⁶/144.
        assert!(
            (found - expected).abs() < 0.3 * eps.powi(6),
            "ε = {eps}: {found} against {expected}"
        );
    }
}

#[test]
fn without_modulation_the_multipliers_are_those_of_the_oscillator() {
    let mut mathieu = example("mathieu.lag");
    mathieu.set_value("eps", 0.0).unwrap();
    mathieu.set_value("delta", 0.3).unwrap();
    let period = 2.0 * std::f64::consts::PI;
    let options = FloquetOptions {
        period: Some(period),
        ..FloquetOptions::default()
    };
    let result = &mathieu.floquet(&options).unwrap().results[0];
    assert_eq!(result.period_source, PeriodSource::Given);
    assert_eq!(result.verdict, Verdict::Marginal);
    // μ = exp(±i √δ T).
    let angle = 0.3_f64.sqrt() * period;
    for (re, im) in &result.multipliers {
        assert!(
            (re - angle.cos()).abs() < 1e-8,
            "{re} against {}",
            angle.cos()
        );
        assert!((im.abs() - angle.sin().abs()).abs() < 1e-8);
    }
}

#[test]
fn mathieu_chart_agrees_with_scipy() {
    let data = include_str!("data/mathieu_scipy.csv");
    let mathieu = example("mathieu.lag");
    let ranges = [
        Range {
            name: "delta".into(),
            low: -0.5,
            high: 1.5,
        },
        Range {
            name: "eps".into(),
            low: 0.0,
            high: 1.0,
        },
    ];
    // 41 × 21 points, as the SciPy script computes them.
    let mut rows = data
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>());
    let chart = mathieu
        .floquet_chart(&FloquetOptions::default(), &ranges, 20)
        .unwrap();
    // The chart has steps + 1 = 21 values per name; the data 41 δ × 21 ε: compare where the
    // grids meet (every other δ).
    let mut compared = 0;
    for point in &chart.points {
        let (delta, eps) = (point.values[0], point.values[1]);
        let row = rows
            .by_ref()
            .find(|r| {
                (r[0].parse::<f64>().unwrap() - delta).abs() < 1e-9
                    && (r[1].parse::<f64>().unwrap() - eps).abs() < 1e-9
            })
            .unwrap_or_else(|| panic!("no SciPy row at δ = {delta}, ε = {eps}"));
        let trace: f64 = row[2].parse().unwrap();
        let largest: f64 = row[3].parse().unwrap();
        let (verdict, mu) = point.verdicts[0].expect("x = 0 at every point");
        assert!(
            (mu - largest).abs() < 1e-6 * largest,
            "δ = {delta}, ε = {eps}: |μ| {mu} against SciPy's {largest}"
        );
        // On a transition curve (|tr Φ| = 2) the verdict is the tolerance's to make.
        if (trace.abs() - 2.0).abs() > 1e-4 {
            assert_eq!(
                verdict.bounded(),
                row[4] == "stable",
                "δ = {delta}, ε = {eps}"
            );
            compared += 1;
        }
    }
    assert!(compared > 400, "{compared} points compared");
}

#[test]
fn kapitza_boundary_converges_to_the_criterion_for_fast_driving() {
    let mut kapitza = example("kapitza-pendulum.lag");
    let (g, l) = (9.81, 0.2);
    let mut errors = Vec::new();
    for ratio in [0.2, 0.1, 0.05] {
        // ε = a/ℓ; the criterion a²ω²/(2gℓ) = 1 gives ω_c; bracket it.
        let a = ratio * l;
        kapitza.set_value("a", a).unwrap();
        let predicted = (2.0 * g * l).sqrt() / a;
        let omega = boundary(&mut kapitza, "omega", 0.8 * predicted, 1.5 * predicted);
        let criterion = a * a * omega * omega / (2.0 * g * l);
        errors.push(criterion - 1.0);
        // Mathieu's zeroth curve to ε⁴: the criterion at the boundary is 1 + 7ε²/16 + O(ε⁴).
        let expected = 1.0 + 7.0 * ratio * ratio / 16.0;
        assert!(
            (criterion - expected).abs() < ratio.powi(4),
            "a/ℓ = {ratio}: a²ω²/(2gℓ) = {criterion} at the boundary, against {expected}"
        );
    }
    assert!(
        errors.windows(2).all(|w| w[1] < w[0] && w[1] > 0.0),
        "{errors:?}"
    );
    assert!(errors[2] < 2e-3, "{errors:?}");
}

#[test]
fn kapitza_upright_is_stable_when_driven_fast_and_hanging_stays_stable() {
    let kapitza = example("kapitza-pendulum.lag");
    let floquet = kapitza.floquet(&FloquetOptions::default()).unwrap();
    let results = &floquet.results;
    assert_eq!(results.len(), 2);
    assert_eq!(results[0].period_source, PeriodSource::Driving);
    assert!((results[0].period - 2.0 * std::f64::consts::PI / 300.0).abs() < 1e-12);
    assert!(results.iter().all(|r| r.base == Base::Equilibrium));
    assert!(results[0].state[0].abs() < 1e-12);
    assert!((results[1].state[0] - std::f64::consts::PI).abs() < 1e-9);
    assert!(results.iter().all(|r| r.verdict == Verdict::Marginal));
    // The slow oscillation about the top: ω² ≈ a²ω²/(2ℓ²) − g/ℓ (Kapitza's effective
    // potential), within the method's O(ε²) error.
    let (a, l, g, w) = (0.01_f64, 0.2, 9.81, 300.0);
    let slow = (a * a * w * w / (2.0 * l * l) - g / l).sqrt();
    let (re, im) = results[1].multipliers[0];
    let found = im.atan2(re).abs() / results[1].period;
    assert!((found - slow).abs() < 0.02 * slow, "{found} against {slow}");
}

#[test]
fn a_forced_damped_oscillator_has_a_periodic_orbit_found_by_shooting() {
    let text = "coordinates x
parameters k = 4, c = 0.3, F = 1.5, W = 1.3
frame N
point P = x*N.x
particle P mass 1
generalized force -k*x - c*x' + F*cos(W*t) on x
";
    let analysis = Analysis::from_text(text).unwrap();
    let floquet = analysis.floquet(&FloquetOptions::default()).unwrap();
    let result = &floquet.results[0];
    assert_eq!(result.base, Base::Orbit);
    let (k, c, f, w) = (4.0_f64, 0.3_f64, 1.5_f64, 1.3_f64);
    // x = Re(X e^{iWt}), X = F / (k − W² + i c W).
    let (dr, di) = (k - w * w, c * w);
    let d2 = dr * dr + di * di;
    let (xr, xi) = (f * dr / d2, -f * di / d2);
    assert!((result.state[0] - xr).abs() < 1e-8, "{:?}", result.state);
    assert!(
        (result.state[1] + w * xi).abs() < 1e-8,
        "{:?}",
        result.state
    );
    // μ = exp(λ T), λ = −c/2 ± i √(k − c²/4).
    let period = 2.0 * std::f64::consts::PI / w;
    let modulus = (-c / 2.0 * period).exp();
    for (re, im) in &result.multipliers {
        assert!((re.hypot(*im) - modulus).abs() < 1e-8);
    }
    assert_eq!(result.verdict, Verdict::Stable);
}

#[test]
fn the_period_is_the_common_one_of_the_driving_or_refused() {
    let model = |force: &str| {
        format!(
            "coordinates x\nparameters k = 2\nframe N\npoint P = x*N.x\nparticle P mass 1\n\
             generalized force -k*x + {force} on x\n"
        )
    };
    let two = Analysis::from_text(&model("cos(2*t) + sin(3*t)")).unwrap();
    let floquet = two.floquet(&FloquetOptions::default()).unwrap();
    assert!((floquet.results[0].period - 2.0 * std::f64::consts::PI).abs() < 1e-12);
    let thirds = Analysis::from_text(&model("cos(t/2) + sin(t/3)")).unwrap();
    let floquet = thirds.floquet(&FloquetOptions::default()).unwrap();
    assert!((floquet.results[0].period - 12.0 * std::f64::consts::PI).abs() < 1e-9);
    let incommensurate = Analysis::from_text(&model("cos(t) + cos(sqrt(2)*t)")).unwrap();
    let refused = incommensurate
        .floquet(&FloquetOptions::default())
        .unwrap_err();
    assert!(matches!(
        refused,
        Error::Floquet(FloquetError::NoCommonPeriod { .. })
    ));
    let growing = Analysis::from_text(&model("t*cos(t)")).unwrap();
    let refused = growing.floquet(&FloquetOptions::default()).unwrap_err();
    assert!(matches!(
        refused,
        Error::Floquet(FloquetError::NotPeriodic { .. })
    ));
    let chirp = Analysis::from_text(&model("cos(t^2)")).unwrap();
    let refused = chirp.floquet(&FloquetOptions::default()).unwrap_err();
    assert!(matches!(
        refused,
        Error::Floquet(FloquetError::NotPeriodic { .. })
    ));
    assert!(refused.to_string().contains("not periodic"));
    // Without time in the equations there is no period to find: it must be given.
    let autonomous = Analysis::from_text(&model("0")).unwrap();
    let refused = autonomous.floquet(&FloquetOptions::default()).unwrap_err();
    assert!(matches!(refused, Error::Floquet(FloquetError::Autonomous)));
    let options = FloquetOptions {
        period: Some(1.0),
        ..FloquetOptions::default()
    };
    let given = autonomous.floquet(&options).unwrap();
    assert_eq!(given.results[0].period_source, PeriodSource::Given);
}

#[test]
fn solve_gives_a_floquet_section_for_periodic_models() {
    let section = |name: &str| {
        let solution = example(name).solution(None).unwrap();
        let found = solution
            .document
            .sections
            .iter()
            .find(|s| s.title.starts_with("Floquet analysis"))
            .cloned();
        found.unwrap_or_else(|| panic!("{name}: no Floquet section"))
    };
    let mathieu = format!("{:?}", section("mathieu.lag").blocks);
    // δ = 1/4, ε = 0.2: inside the first tongue, μ = −1.853428 (as `linearize --periodic`).
    assert!(
        mathieu.contains("-1.853428") && mathieu.contains("unstable"),
        "{mathieu}"
    );
    let kapitza = format!("{:?}", section("kapitza-pendulum.lag").blocks);
    assert!(kapitza.contains("theta = 3.141593"), "{kapitza}");
    assert!(!kapitza.contains("\"unstable\""), "{kapitza}");
    // A model whose equations do not depend on time gets no such section.
    let pendulum = example("simple-pendulum.lag").solution(None).unwrap();
    assert!(pendulum
        .document
        .sections
        .iter()
        .all(|s| !s.title.starts_with("Floquet")));
}
