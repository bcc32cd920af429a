//! Issue 15: reactions came as final expressions only, with no working, where a course
//! solution shows the released coordinate (or the multiplier), the Lagrange equation that
//! gives the reaction, then the result. `Analysis::reaction_working` now gives those
//! equations, with the accelerations still in them, and the solution prints them before each
//! result (or one line when they would fill pages).
//!
//! Checked exactly: the pendulum's released equations are `m a_P` less the weight; with θ̈ of
//! the equation of motion put in they are the reaction itself. The knife edge's multiplier
//! equations are `m ẍ = λ sin θ`, `m ÿ = −λ cos θ`; the seed's gears, whose constraint was
//! used to eliminate φ₂, get `Q^R_φ₁ = I₁ φ̈₁ − C + R₁ F` and `Q^R_φ₂ = r I₂ φ̈₁`.

use std::path::Path;

use cas::Expr;
use lagrange::report::reaction_working::Working;
use lagrange::Analysis;

const PENDULUM: &str = "\
coordinates theta
parameters  m = 1, l = 1, g = 9.81
frame N
point P = l*sin(theta)*N.x - l*cos(theta)*N.y
particle P mass m
gravity -g*N.y
reaction pivot: hinge origin on P
";

fn seed(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/seed")
        .join(name);
    std::fs::read_to_string(path).expect("the seed model")
}

#[test]
fn the_pendulum_hinge_is_worked_from_its_released_equations() {
    let analysis = Analysis::from_text(PENDULUM).expect("the model checks");
    let working = analysis.reaction_working();
    let Some(Some(Working::Released { point, equations })) = working.first() else {
        panic!("a release's working: {working:?}");
    };
    assert_eq!(point, "origin");
    let axes: Vec<&str> = equations.iter().map(|(a, _, _)| a.as_str()).collect();
    assert_eq!(axes, ["x", "y"], "the z equation is 0 = 0 and left out");
    let (m, g, l) = (Expr::symbol("m"), Expr::symbol("g"), Expr::symbol("l"));
    let theta = Expr::coordinate("theta");
    let (rate, accel) = (Expr::rate("theta", 1), Expr::rate("theta", 2));
    let x = m * l * (accel * theta.cos() - rate.powi(2) * theta.sin());
    let y = m * l * (accel * theta.sin() + rate.powi(2) * theta.cos()) + m * g;
    assert!(equations[0].2.equals(x), "{}", equations[0].2);
    assert!(equations[1].2.equals(y), "{}", equations[1].2);
    // With θ̈ = −(g/ℓ) sin θ they are the reaction's components.
    let force = analysis
        .reactions()
        .expect("reactions")
        .and_then(|r| r.reactions.first())
        .and_then(|r| r.force)
        .expect("the hinge force");
    let motion = [(accel, -(g / l) * theta.sin())];
    for (k, (_, _, e)) in equations.iter().enumerate() {
        assert!(e.subs(&motion).equals(force[k]), "{k}: {e}");
    }
    let text = analysis
        .solution(None)
        .expect("solution")
        .document
        .to_text();
    assert!(
        text.contains("Working: released, the point origin moves"),
        "{text}"
    );
    assert!(text.contains("R_pivot · x̂ = "), "{text}");
}

#[test]
fn the_knife_edge_is_worked_from_its_multiplier_equations() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knife-edge.lag");
    let text = std::fs::read_to_string(path).expect("the example");
    let analysis = Analysis::from_text(&text).expect("the model checks");
    let working = analysis.reaction_working();
    let Some(Some(Working::Multiplier { equations })) = working.first() else {
        panic!("a multiplier's working: {working:?}");
    };
    let m = Expr::symbol("m");
    let theta = Expr::coordinate("theta");
    let lambda = Expr::symbol("lambda");
    let find = |q: &str| {
        equations
            .iter()
            .find(|(name, _, _)| name == q)
            .map(|(_, l, r)| (*l, *r))
            .expect("the coordinate's equation")
    };
    let (lhs, rhs) = find("x");
    assert!(lhs.equals(m * Expr::rate("x", 2)), "{lhs}");
    assert!(rhs.equals(lambda * theta.sin()), "{rhs}");
    let (lhs, rhs) = find("y");
    assert!(lhs.equals(m * Expr::rate("y", 2)), "{lhs}");
    assert!(rhs.equals(-(lambda * theta.cos())), "{rhs}");
    let document = analysis.solution(None).expect("solution").document;
    let text = document.to_text();
    assert!(text.contains("kept with its multiplier λ"), "{text}");
    assert!(document.to_latex().contains(r"\lambda \sin \theta"));
}

#[test]
fn the_gears_are_worked_without_their_mesh() {
    let analysis = Analysis::from_text(&seed("7.3-gears-pendulum.lag")).expect("the model");
    let working = analysis.reaction_working();
    let Some(Some(Working::Freed { equations })) = working.first() else {
        panic!("a freed constraint's working: {working:?}");
    };
    let s = Expr::symbol;
    let accel = Expr::rate("phi1", 2);
    let find = |q: &str| {
        equations
            .iter()
            .find(|(name, _)| name == q)
            .map(|(_, e)| *e)
            .expect("the coordinate's equation")
    };
    let phi1 = s("I1") * accel - s("C") + s("R1") * s("F");
    assert!(find("phi1").equals(phi1), "{}", find("phi1"));
    let phi2 = s("I2") * s("R1") / s("R2") * accel;
    assert!(find("phi2").equals(phi2), "{}", find("phi2"));
    // θ carries no generalized reaction: the report leaves its equation out.
    let text = analysis
        .solution(None)
        .expect("solution")
        .document
        .to_text();
    let from = text
        .find("Working: the constraint is integrable")
        .expect(&text);
    let part = &text[from..];
    let part = &part[..part.find("With the accelerations").expect(part)];
    assert!(part.contains("Q^R_φ1") && part.contains("Q^R_φ2"), "{part}");
    assert!(!part.contains("Q^R_θ"), "{part}");
}

#[test]
fn a_working_past_a_page_is_one_line() {
    let analysis = Analysis::from_text(&seed("7.2-rolling-cone.lag")).expect("the model checks");
    let text = analysis
        .solution(None)
        .expect("solution")
        .document
        .to_text();
    let from = text.find("roll — rolling at A").expect(&text);
    let part = &text[from..];
    assert!(
        part.contains("Working: released") || part.contains("would fill pages"),
        "{part}"
    );
}
