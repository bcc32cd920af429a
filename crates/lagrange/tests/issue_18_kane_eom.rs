//! Issue 18: `lagrange eom --method kane` printed nothing of Kane's method — the reduced
//! equations existed only as numbers inside the steady-motion linearization. Now the same
//! derivation runs over expressions (`mechanics::kane::Sym`: an expression with its value at
//! a sample state, which picks the pivots), giving the generalized speeds, the dependent rates
//! eliminated, `M_r u̇ = f_r` per speed, and an automatic comparison with Lagrange's equations
//! projected on the speeds. The Whipple bicycle is over the size limit: its reduced mass
//! matrix and forcing at the initial state are given instead.

use std::path::Path;

use lagrange::cas::Expr;
use lagrange::mechanics::kane::{Agreement, KaneError};
use lagrange::{Analysis, KaneEom, Method, ResultFormat};

fn example(name: &str) -> Analysis {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    Analysis::from_file(&path).expect("the example loads")
}

fn symbolic(a: &Analysis) -> (lagrange::mechanics::kane::KaneEquations, Agreement) {
    match a.kane_equations().expect("Kane's method applies") {
        KaneEom::Symbolic {
            equations,
            agreement,
        } => (*equations, agreement.expect("Lagrange's equations compare")),
        other => panic!("not symbolic: {other:?}"),
    }
}

#[test]
fn the_rolling_disk_reduces_to_three_speeds_equal_to_lagrange_exactly() {
    let a = example("rolling-disk.lag");
    let (eq, agreement) = symbolic(&a);
    assert_eq!(agreement, Agreement::Exact);
    let names = |idx: &[usize]| -> Vec<String> {
        let mut sorted = idx.to_vec();
        sorted.sort_unstable();
        sorted.iter().map(|k| eq.coordinates[*k].clone()).collect()
    };
    // The contact point's coordinates are cyclic: they are the dependent rates.
    assert_eq!(names(&eq.split.dependent), ["x", "y"]);
    assert_eq!(names(&eq.split.independent), ["psi", "theta", "phi"]);
    assert_eq!(
        eq.split.independent,
        [2, 3, 4],
        "the speeds in the coordinates' order"
    );
    // x' = R φ' cos ψ and y' = R φ' sin ψ (the model's comment), exactly.
    let (r, phi_d, psi) = (
        Expr::symbol("R"),
        Expr::rate("phi", 1),
        Expr::coordinate("psi"),
    );
    let x = eq.rates[0] - r * phi_d * psi.cos();
    let y = eq.rates[1] - r * phi_d * psi.sin();
    assert!(x.is_zero(), "x' = {:?}", eq.rates[0]);
    assert!(y.is_zero(), "y' = {:?}", eq.rates[1]);
    // The spin's own inertia in M_r: m R²/2 + m R² (the axle's moment plus the rolling).
    let spin = eq.mass[2][2] - Expr::rational(3, 2).expect("3/2") * Expr::symbol("m") * r * r;
    assert!(spin.is_zero(), "M_r[φ, φ] = {:?}", eq.mass[2][2]);
}

#[test]
fn the_knife_edge_and_a_pendulum_agree_with_lagrange_exactly() {
    let (eq, agreement) = symbolic(&example("knife-edge.lag"));
    assert_eq!(agreement, Agreement::Exact);
    assert_eq!(eq.split.independent.len(), 2);
    let (eq, agreement) = symbolic(&example("simple-pendulum.lag"));
    assert_eq!(agreement, Agreement::Exact);
    assert!(eq.split.dependent.is_empty());
}

#[test]
fn a_changed_forcing_is_reported_as_a_difference() {
    // The comparison is not vacuous: Lagrange's forcing with one unit added differs.
    let a = example("rolling-disk.lag");
    let (eq, _) = symbolic(&a);
    let lagrange = a.equations().expect("Lagrange derives the disk");
    let mut forcing = lagrange.forcing().to_vec();
    forcing[3] += Expr::one();
    let values = a.values().expect("values");
    let found = eq.agreement(lagrange.mass_matrix(), &forcing, &values);
    assert_eq!(
        found,
        Agreement::Differs {
            part: "forcing",
            row: 1
        }
    );
    // What `eom --method kane` then prints, and the exit code it gives (docs/cli.md: 4).
    let differing = KaneEom::Symbolic {
        equations: Box::new(eq),
        agreement: Ok(found),
    };
    assert!(differing.disagrees());
    let text = lagrange::kane_written(&differing, ResultFormat::Text);
    assert!(text.contains("DIFFER in the forcing, equation 2"), "{text}");
    let shipped = a.kane_equations().expect("Kane's equations of the disk");
    assert!(!shipped.disagrees());
}

#[test]
fn the_bicycle_is_too_large_to_print_and_gives_numbers_at_its_initial_state() {
    let a = example("whipple-bicycle.lag");
    match a.kane_equations().expect("Kane's method applies") {
        KaneEom::Numeric {
            why,
            reduced,
            split,
            ..
        } => {
            assert!(matches!(why, KaneError::TooLarge { .. }), "{why}");
            assert_eq!(split.independent.len(), 3);
            assert_eq!(reduced.mass.len(), 3);
            // The reduced mass matrix is symmetric and positive on its diagonal.
            for i in 0..3 {
                assert!(reduced.mass[i][i] > 0.0);
                for k in 0..3 {
                    let d = reduced.mass[i][k] - reduced.mass[k][i];
                    assert!(d.abs() < 1e-12 * reduced.mass[i][i].abs().max(1.0));
                }
            }
        }
        other => panic!("the bicycle printed symbolically: {other:?}"),
    }
    let text = a
        .equations_written_by(ResultFormat::Text, Method::Kane)
        .expect("the text");
    assert!(text.contains("not printed symbolically"), "{text}");
    assert!(text.contains("M_r ="), "{text}");
}

#[test]
fn the_text_and_json_name_the_speeds_and_the_agreement() {
    let a = example("rolling-disk.lag");
    let text = a
        .equations_written_by(ResultFormat::Text, Method::Kane)
        .expect("the text");
    assert!(
        text.contains("generalized speeds: u1 = psi', u2 = theta', u3 = phi'"),
        "{text}"
    );
    assert!(text.contains("equal, exactly"), "{text}");
    let json = a
        .equations_written_by(ResultFormat::Json, Method::Kane)
        .expect("the JSON");
    let v: serde_json::Value = serde_json::from_str(&json).expect("valid JSON");
    assert_eq!(v["method"], "kane");
    assert_eq!(v["lagrange_agreement"]["result"], "exact");
    assert_eq!(v["mass_matrix"].as_array().map(Vec::len), Some(3));
}
