//! Issue 20: `lagrange solve` took up to 1.9·10⁹ instructions on an example (spring-chain),
//! most of it work done twice: the same partial derivatives worked out again for every
//! question the equilibrium search asks (now remembered per process), a released system
//! derived once for a reaction and again for its working (now the reaction keeps its
//! released equations, `mechanics::Reaction::released_equations`), every released
//! coordinate's residual put on the motion where a release needs only its own.
//!
//! Checked here: the working a solution prints is the same whether it comes from the
//! reactions already derived or from a derivation of its own, equation by equation; and a
//! release's reaction, now computed from its own residuals only, is still the one Lagrange's
//! equations give (the pendulum's hinge: `m a_P − m g`).

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

fn example(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    std::fs::read_to_string(path).expect("the example")
}

/// Each release's point, then its `(axis, equation)` pairs in order.
type Released = Vec<(String, Vec<(String, Expr)>)>;

/// Each release's equations.
fn released(working: &[Option<Working>]) -> Released {
    working
        .iter()
        .filter_map(|w| match w {
            Some(Working::Released { point, equations }) => Some((
                point.clone(),
                equations.iter().map(|(a, _, e)| (a.clone(), *e)).collect(),
            )),
            _ => None,
        })
        .collect()
}

/// The working of `text` derived on its own, and after the reactions were derived.
fn both_ways(text: &str) -> [Released; 2] {
    let alone = Analysis::from_text(text).expect("the model checks");
    let derived_alone = released(&alone.reaction_working());
    let after = Analysis::from_text(text).expect("the model checks");
    assert!(after.reactions().expect("reactions").is_some());
    [derived_alone, released(&after.reaction_working())]
}

#[test]
fn the_working_is_the_same_from_the_reactions_as_derived_anew() {
    for text in [PENDULUM.to_owned(), example("double-pendulum.lag")] {
        let [alone, reused] = both_ways(&text);
        assert!(!alone.is_empty(), "a release's working");
        assert_eq!(alone.len(), reused.len());
        for ((p, a), (q, b)) in alone.iter().zip(&reused) {
            assert_eq!(p, q);
            assert_eq!(a.len(), b.len(), "{p}");
            for ((x, e), (y, f)) in a.iter().zip(b) {
                assert_eq!(x, y);
                assert!(e.equals(*f), "{p} {x}: {e} against {f}");
            }
        }
    }
}

#[test]
fn a_hinge_reaction_from_its_own_residuals_is_the_mass_times_acceleration_less_the_weight() {
    let analysis = Analysis::from_text(PENDULUM).expect("the model checks");
    let force = analysis
        .reactions()
        .expect("reactions")
        .and_then(|r| r.reactions.first())
        .and_then(|r| r.force)
        .expect("the hinge force");
    let (m, g, l) = (Expr::symbol("m"), Expr::symbol("g"), Expr::symbol("l"));
    let theta = Expr::coordinate("theta");
    let rate = Expr::rate("theta", 1);
    let accel = -(g / l) * theta.sin();
    let x = m * l * (accel * theta.cos() - rate.powi(2) * theta.sin());
    let y = m * l * (accel * theta.sin() + rate.powi(2) * theta.cos()) + m * g;
    assert!(force[0].equals(x), "{}", force[0]);
    assert!(force[1].equals(y), "{}", force[1]);
    assert!(force[2].is_zero(), "{}", force[2]);
}
