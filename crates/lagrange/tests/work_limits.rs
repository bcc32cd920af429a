//! Issue 14: a derivation past a work limit of the symbolic core is a typed error that names
//! the model statement whose part outgrew it and can be raised; two `gravity` statements act
//! as their sum in every method (Lagrange I and Newton–Euler once disagreed, exit 4).

use lagrange::cas::WorkLimits;
use lagrange::{Analysis, ErrorKind};

/// A particle whose position is `l sin(q1 + … + qn)` (its kinetic energy has `2^(n−1)`
/// products per velocity component), and one particle moved by each coordinate alone (a
/// regular mass matrix).
fn long_angle_model(n: usize) -> String {
    let coordinates: Vec<String> = (1..=n).map(|i| format!("q{i}")).collect();
    let angle = coordinates.join(" + ");
    let mut text = format!(
        "coordinates {}\nparameters m = 1, l = 1\nframe N\npoint P = l*sin({angle})*N.x\n\
         particle P mass m\n",
        coordinates.join(", ")
    );
    for q in &coordinates {
        text.push_str(&format!("point R{q} = {q}*N.z\nparticle R{q} mass m\n"));
    }
    text
}

#[test]
fn a_derivation_past_a_limit_names_the_statement_and_can_be_raised() {
    let mut analysis = Analysis::from_text(&long_angle_model(6)).expect("a valid model");
    analysis.set_work_limits(WorkLimits::default().with_max_terms(100));
    let err = analysis
        .equations()
        .expect_err("2⁵ products per component, times 6 rates");
    assert!(err.work_limit().is_some(), "{err:?}");
    assert_eq!(err.kind(), ErrorKind::Mechanics);
    assert!(matches!(
        err,
        lagrange::Error::WorkLimit {
            at: Some((5, 1)),
            ..
        }
    ));
    let text = err.render("m.lag", Default::default());
    assert!(text.starts_with("error: m.lag:5:1: deriving the kinetic energy of particle `P`"));
    assert!(text.contains("max_terms"), "{text}");

    // Raised, the same analysis derives, and the result is right:
    // K = m l² (Σ q̇)² cos²(Σ q) / 2 + m Σ q̇² / 2.
    analysis.set_work_limits(WorkLimits::default());
    let equations = analysis.equations().unwrap_or_else(|e| panic!("{e}"));
    let k = equations.kinetic_energy();
    let at = |s: lagrange::cas::Symbol| {
        let n = s.name();
        Some(if n.starts_with('q') { 0.1 } else { 1.0 } + f64::from(s.order()) * 0.05)
    };
    let (angle, rate) = (6.0 * 0.1, 6.0 * 0.15);
    let expected = rate * rate * f64::cos(angle).powi(2) / 2.0 + 6.0 * 0.15 * 0.15 / 2.0;
    let value = k.eval(&at).expect("a number");
    assert!((value - expected).abs() < 1e-9, "{value} vs {expected}");
}

#[test]
fn a_reaction_or_equilibrium_search_past_a_limit_is_a_work_limit_error() {
    let model = format!(
        "{}reaction pin: hinge origin on P, {}\n",
        long_angle_model(6).replace("point P = l*", "point P = l*N.y + l*"),
        // Every particle the coordinates tie to P is released with it (issue 17: a load
        // through a shared coordinate is never silently left out).
        (1..=6)
            .map(|i| format!("Rq{i}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let mut analysis = Analysis::from_text(&model).expect("a valid model");
    analysis.set_work_limits(WorkLimits::default().with_max_terms(100));
    for err in [
        analysis
            .reactions()
            .map(|_| ())
            .expect_err("past the limit"),
        analysis
            .equilibria()
            .map(|_| ())
            .expect_err("past the limit"),
    ] {
        assert!(err.work_limit().is_some(), "{err:?}");
        assert_eq!(err.kind(), ErrorKind::Mechanics);
    }
}

#[test]
fn two_gravity_statements_act_as_their_sum_in_both_methods() {
    let one = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/simple-pendulum.lag"
    ))
    .expect("the example");
    let twice = one.replace("gravity -g*N.y", "gravity -g*N.y\ngravity -g*N.y");
    assert_ne!(one, twice);
    let doubled_g = one.replace("gravity -g*N.y", "gravity -2*g*N.y");
    let reactions = |text: &str| {
        let analysis = Analysis::from_text(text).expect("a valid model");
        let r = analysis
            .reactions()
            .expect("reactions")
            .expect("the model asks for one")
            .reactions[0]
            .clone();
        assert_eq!(
            r.agreement,
            lagrange::mechanics::Agreement::Exact,
            "{:?}",
            r.agreement
        );
        r.force.expect("a hinge transmits a force")
    };
    let (a, b) = (reactions(&twice), reactions(&doubled_g));
    for (x, y) in a.iter().zip(&b) {
        assert!(x.equals(*y), "{x:?} vs {y:?}");
    }
}
