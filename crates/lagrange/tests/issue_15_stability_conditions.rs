//! Issues 15, 17, 18: stability was decided at the numbers (`--set` values) only, where a
//! course states it in the parameters — the bead on a spinning parabola `z = a r²` is stable
//! for `Ω² < 2 a g`, and at `Ω² = 2 a g` every `r` is an equilibrium (a degenerate family,
//! not a point).
//!
//! Cause: the symbolic `K0` at an exact equilibrium was printed, but no criterion was read
//! from it; the numeric criteria (Lagrange–Dirichlet, Lyapunov) need numbers.
//!
//! Fix (`mechanics::stability_condition`, `lagrange::StabilityConditions`): at each
//! equilibrium known in closed form, the sign of `K0` (one coordinate), Sylvester's leading
//! minors (several), Routh's reduced potential (steady motions) or the two-coordinate
//! gyroscopic conditions, read with the parameters whose values are positive taken positive;
//! each boundary checked for a family of equilibria. Checked here with the exact condition
//! and with numbers on both sides of its boundary.

use std::path::Path;

use lagrange::mechanics::stability_condition::{ConditionCriterion, Verdict};
use lagrange::{Analysis, Search};

fn example(name: &str) -> Analysis {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    Analysis::from_file(&path).expect("a valid example")
}

#[test]
fn the_bead_on_a_spinning_parabola_is_stable_iff_omega_squared_is_below_2ag() {
    let (a, g) = (2.0_f64, 9.81_f64);
    let critical = (2.0 * a * g).sqrt();
    for (omega, stable) in [(0.9 * critical, true), (1.1 * critical, false)] {
        let mut bead = example("bead-on-spinning-parabola.lag");
        bead.set_value("Omega", omega).unwrap();
        let equilibria = bead.equilibria().unwrap();
        assert_eq!(equilibria.set.equilibria.len(), 1);
        let condition = equilibria.conditions.at[0].as_ref().expect("a condition");
        assert_eq!(condition.criterion, ConditionCriterion::Sign);
        let Verdict::When(all) = &condition.verdict else {
            panic!("{:?}", condition.verdict)
        };
        assert_eq!(all.len(), 1);
        let text = all[0].text(lagrange::cas::print::to_sympy);
        assert_eq!(text, "Omega**2 < 2*a*g");
        // The condition agrees with the numeric decision on either side of the boundary.
        let numeric = equilibria.linearized[0].as_ref().unwrap().stable;
        assert_eq!(numeric, Some(stable), "Ω = {omega}");
        let holds = omega * omega < 2.0 * a * g;
        assert_eq!(holds, stable);
        assert_eq!(condition.boundaries.len(), 1);
        assert!(condition.boundaries[0].family, "Ω² = 2ag is a family");
        assert_eq!(equilibria.conditions.on_boundary[0], None);
    }
}

#[test]
fn on_the_boundary_the_family_of_equilibria_is_flagged_in_the_text_and_json() {
    let mut bead = example("bead-on-spinning-parabola.lag");
    bead.set_value("Omega", (2.0_f64 * 2.0 * 9.81).sqrt())
        .unwrap();
    let equilibria = bead.equilibria().unwrap();
    assert_eq!(equilibria.conditions.on_boundary[0], Some(0));
    let text = equilibria.to_text();
    assert!(
        text.contains("in the parameters: stable iff Ω² < 2 a g"),
        "{text}"
    );
    assert!(
        text.contains("these values sit on that boundary: at Ω² = 2 a g every r is an equilibrium (a family of equilibria"),
        "{text}"
    );
    let json = equilibria.to_json();
    let entry = &json["stability_conditions"][0];
    assert_eq!(entry["inequalities"][0], "Omega**2 < 2*a*g");
    assert_eq!(entry["boundaries"][0]["relation"], "Omega**2 == 2*a*g");
    assert_eq!(entry["boundaries"][0]["family"], true);
    assert_eq!(entry["on_boundary"], 0);
}

#[test]
fn the_double_pendulum_hangs_stably_for_every_positive_parameter() {
    let pendulum = example("double-pendulum.lag");
    let equilibria = pendulum.equilibria().unwrap();
    assert_eq!(equilibria.set.equilibria.len(), 4);
    for (k, (condition, lin)) in equilibria
        .conditions
        .at
        .iter()
        .zip(&equilibria.linearized)
        .enumerate()
    {
        let condition = condition
            .as_ref()
            .expect("a condition at each exact equilibrium");
        assert_eq!(condition.criterion, ConditionCriterion::Sylvester);
        let stable = lin.as_ref().unwrap().stable == Some(true);
        let always = condition.verdict == Verdict::Always;
        // Hanging (#0) is stable for every value; the other three never meet Sylvester.
        assert_eq!(always, stable, "#{k}: {:?}", condition.verdict);
        assert_eq!(always, k == 0);
    }
}

#[test]
fn the_solution_report_states_the_condition_in_its_stability_section() {
    let bead = example("bead-on-spinning-parabola.lag");
    let document = bead.solution(None).unwrap().document;
    let markdown = document.to_markdown();
    assert!(
        markdown.contains("Equilibrium 0 in the parameters: stable iff $\\Omega^2 < 2 a g$"),
        "{markdown}"
    );
    assert!(markdown.contains("a family of equilibria"), "{markdown}");
    let latex = document.to_latex();
    assert!(latex.contains("stable iff $\\Omega^2 < 2 a g$"), "{latex}");
}

#[test]
fn the_sleeping_top_meets_maxwells_criterion_in_the_parameters() {
    // A = 0.002, C = 0.0008, m = 0.5, g = 9.81, ℓ = 0.05: C² ω₃² = 4 A m g ℓ at ω₃ ≈ 55.37.
    let (a, c, m, g, l) = (0.002_f64, 0.0008_f64, 0.5_f64, 9.81_f64, 0.05_f64);
    let critical = (4.0 * a * m * g * l).sqrt() / c;
    let top = example("heavy-symmetric-top.lag");
    for (rate, stable) in [(0.9 * critical, false), (1.1 * critical, true)] {
        let search = Search {
            steady: vec![("phi".to_owned(), rate)],
            ..Search::default()
        };
        let equilibria = top.equilibria_with(&search).unwrap();
        let upright = equilibria
            .set
            .equilibria
            .iter()
            .position(|e| e.values[1].abs() < 1e-12)
            .expect("the upright top");
        let condition = equilibria.conditions.at[upright].as_ref().expect("Maxwell");
        assert_eq!(condition.criterion, ConditionCriterion::Gyroscopic);
        let Verdict::When(all) = &condition.verdict else {
            panic!("{:?}", condition.verdict)
        };
        let texts: Vec<String> = all
            .iter()
            .map(|i| i.text(lagrange::cas::print::to_sympy))
            .collect();
        assert_eq!(texts, ["C**2*phi_d**2 > 4*A*g*l*m"]);
        // The chart's numeric decision agrees on either side of the boundary.
        let pole = equilibria.at_poles[upright]
            .as_ref()
            .expect("decided at the pole");
        assert_eq!(pole.stable(), Some(stable), "φ̇ = {rate}");
        assert_eq!(c * c * rate * rate > 4.0 * a * m * g * l, stable);
    }
}

#[test]
fn the_two_link_arms_four_equilibria_come_out_in_closed_form() {
    // Joint angles: sin(θ1 + θ2) in both rest equations, so no equation holds one unknown
    // until the second is subtracted from the first.
    let arm = example("two-link-arm.lag");
    let equilibria = arm.equilibria().unwrap();
    assert_eq!(
        equilibria.set.method,
        lagrange::mechanics::equilibria::Method::Exact
    );
    let mut points: Vec<(f64, f64)> = equilibria
        .set
        .equilibria
        .iter()
        .map(|e| {
            let exact = e.exact.as_ref().expect("closed form");
            let value = |x: lagrange::cas::Expr| x.eval(&|_| None).unwrap();
            (value(exact[0]), value(exact[1]))
        })
        .collect();
    points.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let pi = std::f64::consts::PI;
    let expected = [(0.0, 0.0), (0.0, pi), (pi, 0.0), (pi, pi)];
    assert_eq!(points.len(), 4);
    for (p, e) in points.iter().zip(expected) {
        assert!(
            (p.0 - e.0).abs() < 1e-12 && (p.1 - e.1).abs() < 1e-12,
            "{p:?}"
        );
    }
    // Hanging straight down is the one stable equilibrium, for every positive parameter.
    let verdicts: Vec<bool> = equilibria
        .conditions
        .at
        .iter()
        .map(|c| c.as_ref().expect("a condition").verdict == Verdict::Always)
        .collect();
    let hanging = equilibria
        .set
        .equilibria
        .iter()
        .position(|e| e.values.iter().all(|v| v.abs() < 1e-12))
        .unwrap();
    for (k, always) in verdicts.iter().enumerate() {
        assert_eq!(*always, k == hanging);
    }
}
