//! Issue 17: at the poles of spherical coordinates and at Euler-angle gimbal points the
//! stability was "not decided": the hanging spherical pendulum (θ = 0, where the azimuth φ
//! moves nothing), and the sleeping top, whose Maxwell criterion C²ω₃² > 4 A m g ℓ a user
//! expects to see.
//!
//! Cause: the mass matrix is singular there (one direction of the coordinates moves
//! nothing), so the linearization in the model's coordinates cannot be solved.
//!
//! Fix (crate::chart): a regular chart made for the point — the polar pair made Cartesian,
//! `u + i v = (θ − θ*) e^{iα}`, the coordinates turning with the azimuth shifted
//! (`w = φ + ψ` for the top). At rest the potential's Hessian in that chart decides
//! (Lagrange–Dirichlet); at a steady spin the gyroscopic linearization of the chart's
//! Lagrangian, reduced at constant spin momentum, with the isotropic criterion `g² > −4 m k`
//! stated in numbers — for the top `g = C ω₃`, `m = A`, `k = −m g ℓ`: Maxwell's.

use std::path::Path;

use lagrange::{Analysis, AtPole, Search};

fn example(name: &str) -> Analysis {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    Analysis::from_file(&path).expect("a valid example")
}

#[test]
fn the_hanging_spherical_pendulum_is_stable_and_the_upright_one_unstable() {
    let pendulum = example("spherical-pendulum.lag");
    let equilibria = pendulum.equilibria().unwrap();
    assert_eq!(equilibria.at_poles.len(), 2);
    let (m, g, l) = (1.0, 9.81, 1.0);
    for (k, expected) in [(0, true), (1, false)] {
        let Some(AtPole::Rest(pole)) = &equilibria.at_poles[k] else {
            panic!("#{k}: {:?}", equilibria.at_poles[k]);
        };
        assert_eq!(pole.stable, Some(expected));
        assert_eq!(
            (pole.polar.as_str(), pole.azimuth.as_str()),
            ("theta", "phi")
        );
        // V ≈ ∓ m g ℓ + ½ (±m g ℓ)(u² + v²): the Hessian is ±m g ℓ I.
        let sign = if expected { 1.0 } else { -1.0 };
        for e in &pole.eigenvalues {
            assert!((e - sign * m * g * l).abs() < 1e-9, "{e}");
        }
    }
    let text = equilibria.to_text();
    assert!(
        text.contains("decided in the regular chart (u, v)"),
        "{text}"
    );
}

#[test]
fn the_top_at_rest_hangs_stably_and_falls_from_upright() {
    let top = example("heavy-symmetric-top.lag");
    let equilibria = top.equilibria().unwrap();
    let (m, g, l) = (0.5, 9.81, 0.05);
    // #0: θ = 0 (upright), #1: θ = π (hanging); the spin w = ψ + φ is free.
    for (k, expected) in [(0, false), (1, true)] {
        let Some(AtPole::Rest(pole)) = &equilibria.at_poles[k] else {
            panic!("#{k}: {:?}", equilibria.at_poles[k]);
        };
        assert_eq!(pole.stable, Some(expected));
        assert_eq!(pole.eigenvalues.len(), 2);
        let sign = if expected { 1.0 } else { -1.0 };
        for e in &pole.eigenvalues {
            assert!((e - sign * m * g * l).abs() < 1e-9, "{e}");
        }
    }
}

/// The decision about the sleeping (upright) top spinning at `spin`.
fn sleeping(top: &Analysis, spin: f64) -> lagrange::PoleSpin {
    let search = Search {
        steady: vec![("phi".to_owned(), spin)],
        ..Search::default()
    };
    let equilibria = top.equilibria_with(&search).unwrap();
    let upright = equilibria
        .set
        .equilibria
        .iter()
        .position(|e| e.values[1].abs() < 1e-9)
        .expect("the upright steady motion");
    match &equilibria.at_poles[upright] {
        Some(AtPole::Spin(spin)) => spin.clone(),
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_sleeping_top_follows_maxwells_criterion() {
    let top = example("heavy-symmetric-top.lag");
    let (m, l, a, c, g) = (0.5_f64, 0.05, 0.002, 0.0008, 9.81);
    let critical = (4.0 * a * m * g * l).sqrt() / c;
    for (factor, stable) in [(0.98, false), (1.02, true), (3.0, true), (0.3, false)] {
        let omega = factor * critical;
        let spin = sleeping(&top, omega);
        assert_eq!(
            spin.stable, stable,
            "ω₃ = {omega} ({factor} of Maxwell's {critical})"
        );
        // The criterion's two sides, in numbers: C² ω₃² and 4 A m g ℓ.
        let (g2, m4k) = spin.isotropic.expect("a symmetric top is isotropic");
        let (expected_g2, expected_m4k) = (c * c * omega * omega, 4.0 * a * m * g * l);
        assert!(
            (g2 - expected_g2).abs() < 1e-6 * expected_g2,
            "{g2} against {expected_g2}"
        );
        assert!(
            (m4k - expected_m4k).abs() < 1e-6 * expected_m4k,
            "{m4k} against {expected_m4k}"
        );
    }
    // Above the threshold the nutation and precession rates are
    // λ = i (C ω₃ ± √(C²ω₃² − 4 A m g ℓ)) / (2A).
    let omega = 150.0;
    let spin = sleeping(&top, omega);
    let root = (c * c * omega * omega - 4.0 * a * m * g * l).sqrt();
    let mut expected = [
        (c * omega + root) / (2.0 * a),
        (c * omega - root) / (2.0 * a),
    ];
    expected.sort_by(f64::total_cmp);
    let mut found: Vec<f64> = spin
        .eigenvalues
        .iter()
        .filter(|(_, im)| *im > 0.0)
        .map(|(re, im)| {
            assert!(re.abs() < 1e-6 * im, "{re}");
            *im
        })
        .collect();
    found.sort_by(f64::total_cmp);
    assert_eq!(found.len(), 2, "{:?}", spin.eigenvalues);
    for (f, e) in found.iter().zip(expected) {
        assert!((f - e).abs() < 1e-5 * e, "{f} against {e}");
    }
}
