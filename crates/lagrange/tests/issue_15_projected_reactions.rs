//! Issue 15: reactions came in inertial components only, so a rod's tension or a force in a
//! body's frame had to be projected by hand. A `reaction` statement now takes `… along n` or
//! `… in frame R`, and the report gives the projected components and their values at the
//! equilibria. The pendulum's rod tension is `m g cos θ + m ℓ θ̇²` exactly; 7.4's hinge force in
//! the rod's frame is the same vector in another basis.

use std::path::Path;

use cas::Expr;
use lagrange::Analysis;

const PENDULUM: &str = "\
coordinates theta
parameters  m = 1, l = 1, g = 9.81
frame N
point P = l*sin(theta)*N.x - l*cos(theta)*N.y
particle P mass m
gravity -g*N.y
reaction rod: hinge origin on P along origin - P
";

#[test]
fn the_rod_tension_of_the_pendulum_is_exact() {
    let analysis = Analysis::from_text(PENDULUM).expect("the model checks");
    let projected = analysis.projected_reactions().expect("projected");
    assert_eq!(projected.len(), 1);
    let p = &projected[0];
    assert_eq!(p.name, "rod");
    assert_eq!(p.components.len(), 1);
    let (m, g, l) = (Expr::symbol("m"), Expr::symbol("g"), Expr::symbol("l"));
    let theta = Expr::coordinate("theta");
    let tension = m * g * theta.cos() + m * l * Expr::rate("theta", 1).powi(2);
    assert!(
        p.components[0].1.equals(tension),
        "{} ≠ {tension}",
        p.components[0].1
    );
    // Hanging down the rod pulls with m g; upside down it pushes with m g.
    let mut at_rest: Vec<f64> = p
        .at_equilibria
        .iter()
        .map(|v| v.as_ref().map_or(f64::NAN, |v| v[0]))
        .collect();
    at_rest.sort_by(f64::total_cmp);
    assert_eq!(at_rest.len(), 2);
    assert!((at_rest[0] + 9.81).abs() < 1e-9 && (at_rest[1] - 9.81).abs() < 1e-9);

    let text = analysis
        .solution(None)
        .expect("solution")
        .document
        .to_text();
    assert!(text.contains("rod along origin - P"), "{text}");
    assert!(text.contains("R_rod · ê = m (ℓ θ̇² + g cos θ)"), "{text}");
}

#[test]
fn the_inverted_pendulum_hinge_force_in_the_rod_frame_is_the_same_vector() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/seed/7.4-inverted-pendulum.lag");
    let text = std::fs::read_to_string(path).expect("the seed model");
    let text = text.replace(
        "reaction hinge_A: hinge A on rod\n",
        "reaction hinge_A: hinge A on rod in frame B\n",
    );
    let analysis = Analysis::from_text(&text).expect("the model checks");
    let projected = analysis.projected_reactions().expect("projected");
    let p = &projected[0];
    let labels: Vec<&str> = p.components.iter().map(|(l, _)| l.as_str()).collect();
    assert_eq!(labels, ["B.x", "B.y", "B.z"]);
    let force = analysis
        .reactions()
        .expect("reactions")
        .and_then(|r| r.reactions.iter().find(|r| r.name == "hinge_A"))
        .and_then(|r| r.force)
        .expect("the hinge force");
    // A change of basis keeps the length: Σ (R · e_i)² = R · R, exactly.
    let squares = |v: &[Expr]| Expr::add_all(v.iter().map(|c| *c * *c));
    let components: Vec<Expr> = p.components.iter().map(|(_, c)| *c).collect();
    assert!(squares(&components).equals(squares(&force)));
    assert!(components[2].is_zero());
    // B = N rotated θ about z: R · B.x = R_x cos θ + R_y sin θ.
    let theta = Expr::coordinate("theta");
    assert!(components[0].equals(force[0] * theta.cos() + force[1] * theta.sin()));
    let solution = analysis.solution(None).expect("solution").document;
    assert!(solution.to_text().contains("hinge_A in frame B"));
    assert!(solution
        .to_latex()
        .contains(r"\vec{R}_{\mathrm{hinge\_A}} \cdot \hat{x}_{\mathrm{B}}"));
}

#[test]
fn an_unknown_frame_is_an_error_of_the_model() {
    let text = PENDULUM.replace("along origin - P", "in frame Q");
    assert!(Analysis::from_text(&text).is_err());
    let text = PENDULUM.replace("along origin - P", "in P");
    assert!(Analysis::from_text(&text).is_err());
}

/// The pendulum with its bob as a body `rod` (a point mass: no inertia of its own), so that
/// the rod is a name of the model.
const ROD_PENDULUM: &str = "\
coordinates theta
parameters  m = 1, l = 1, g = 9.81
frame N
frame B = N rotated theta about z
point P = l*sin(theta)*N.x - l*cos(theta)*N.y
body rod mass m at P frame B inertia 0, 0, 0
gravity -g*N.y
reaction pivot: hinge origin on rod along rod
";

#[test]
fn along_a_body_is_along_the_line_from_its_centre_to_the_point() {
    let analysis = Analysis::from_text(ROD_PENDULUM).expect("the model checks");
    let projected = analysis.projected_reactions().expect("projected");
    let p = &projected[0];
    assert_eq!(p.onto, "rod");
    let (m, g, l) = (Expr::symbol("m"), Expr::symbol("g"), Expr::symbol("l"));
    let theta = Expr::coordinate("theta");
    let tension = m * (l * Expr::rate("theta", 1).powi(2) + g * theta.cos());
    assert!(
        p.components[0].1.equals(tension),
        "{} ≠ {tension}",
        p.components[0].1
    );
    let text = analysis
        .solution(None)
        .expect("solution")
        .document
        .to_text();
    assert!(text.contains("pivot along rod"), "{text}");
    assert!(text.contains("R_pivot · ê = m (ℓ θ̇² + g cos θ)"), "{text}");
}

#[test]
fn along_the_inverted_pendulum_rod_is_its_axial_force() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/seed/7.4-inverted-pendulum.lag");
    let text = std::fs::read_to_string(path).expect("the seed model");
    let text = text.replace(
        "reaction hinge_A: hinge A on rod\n",
        "reaction hinge_A: hinge A on rod along rod\n",
    );
    let analysis = Analysis::from_text(&text).expect("the model checks");
    let projected = analysis.projected_reactions().expect("projected");
    let force = analysis
        .reactions()
        .expect("reactions")
        .and_then(|r| r.reactions.iter().find(|r| r.name == "hinge_A"))
        .and_then(|r| r.force)
        .expect("the hinge force");
    // From G back to A is −B.y = (sin θ, −cos θ): the rod's axial force, positive in tension.
    let theta = Expr::coordinate("theta");
    let axial = force[0] * theta.sin() - force[1] * theta.cos();
    assert!(projected[0].components[0].1.equals(axial));
}

#[test]
fn along_a_name_that_is_no_body_nor_vector_is_an_error() {
    let text = ROD_PENDULUM.replace("along rod", "along N");
    assert!(Analysis::from_text(&text).is_err());
    let text = ROD_PENDULUM.replace("along rod", "along theta");
    assert!(Analysis::from_text(&text).is_err());
}
