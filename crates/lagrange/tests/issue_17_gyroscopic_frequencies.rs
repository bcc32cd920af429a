//! Issue 17: at a steady motion the printed natural frequencies came from `K0` and `M0` alone
//! and ignored the gyroscopic coupling in `C0`: for the spherical pendulum's conical motion
//! they said 4.60 rad/s beside state-matrix eigenvalues ±6.05 i. With a gyroscopic `C0` the
//! frequencies are now the state matrix's, equal to its eigenvalues and to the closed form
//! `ω² = φ̇² (1 + 3 cos² θ0)`; the mode shapes, complex there, are not given as real ones.

use std::path::Path;

use lagrange::{Analysis, Search};

#[test]
fn the_conical_pendulum_oscillates_at_the_frequency_of_its_full_linearization() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/spherical-pendulum.lag");
    let analysis = Analysis::from_file(&path).unwrap();
    let rate = 5.0_f64;
    let search = Search {
        steady: vec![("phi".to_string(), rate)],
        ..Search::default()
    };
    let equilibria = analysis.equilibria_with(&search).unwrap();
    let (g, l) = (9.81_f64, 1.0_f64);
    let cone = (g / (l * rate * rate)).acos();
    let index = equilibria
        .set
        .equilibria
        .iter()
        .position(|e| (e.values[1] - cone).abs() < 1e-9)
        .expect("the cone cos θ = g/(ℓ φ̇²)");
    let lin = equilibria.linearized[index].as_ref().unwrap();
    let c = cone.cos();
    let expected = rate * (1.0 + 3.0 * c * c).sqrt();
    let frequencies: Vec<f64> = lin.frequencies().into_iter().flatten().collect();
    assert_eq!(frequencies.len(), 1, "{frequencies:?}");
    assert!((frequencies[0] - expected).abs() < 1e-9, "{frequencies:?}");
    // The same as the eigenvalues of the state matrix.
    assert!(lin
        .eigenvalues
        .iter()
        .any(|(re, im)| re.abs() < 1e-9 && (im - frequencies[0]).abs() < 1e-9));
    // The precession's drift is the neutral mode, and no real mode shape is claimed.
    assert_eq!(lin.omega_squared.as_ref().unwrap().len(), 2);
    assert!(lin.omega_squared.as_ref().unwrap()[0].abs() < 1e-9);
    assert!(lin.modes.is_empty());
}

#[test]
fn without_coupling_the_frequencies_are_still_those_of_k0_and_m0() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/double-pendulum.lag");
    let analysis = Analysis::from_file(&path).unwrap();
    let equilibria = analysis.equilibria().unwrap();
    for lin in equilibria.linearized.iter().flatten() {
        assert_eq!(lin.modes.len(), 2);
    }
}
