//! Issue 17: constant forces and constant couples made every equilibrium "non-conservative",
//! so a stable equilibrium (K0 positive definite, eigenvalues on the imaginary axis) was
//! reported undecided. Generalized forces at rest whose Jacobian is symmetric (checked
//! exactly, for every value of the inputs) have a potential, which now counts in
//! Lagrange–Dirichlet's criterion; a follower force (circulatory: its Jacobian is not
//! symmetric) does not, and the eigenvalues decide as before.

use lagrange::mechanics::linearize::{Criterion, Linearized};
use lagrange::{Analysis, Equilibria};

/// The equilibrium at `values` (its index) and the linearization about it.
fn linearized_at<'a>(equilibria: &'a Equilibria, values: &[f64]) -> (usize, &'a Linearized) {
    let index = equilibria
        .set
        .equilibria
        .iter()
        .position(|e| {
            e.values
                .iter()
                .zip(values)
                .all(|(a, b)| (a - b).abs() < 1e-9)
        })
        .unwrap_or_else(|| panic!("no equilibrium at {values:?}"));
    (index, equilibria.linearized[index].as_ref().unwrap())
}

const PUSHED_PENDULUM: &str = "coordinates theta
parameters m = 1, l = 1, g = 9.81
inputs F = 3
frame N
frame B = N rotated theta about z
point P = -l*B.y
particle P mass m
gravity -g*N.y
force F*N.x at P
";

#[test]
fn a_pendulum_pushed_by_a_constant_force_hangs_stably_at_its_tilt() {
    let analysis = Analysis::from_text(PUSHED_PENDULUM).unwrap();
    let equilibria = analysis.equilibria().unwrap();
    let (index, lin) = linearized_at(equilibria, &[(3.0_f64 / 9.81).atan()]);
    assert_eq!(lin.stable, Some(true));
    assert_eq!(lin.criterion, Criterion::LagrangeDirichlet);
    // ω² = √(F² + (m g)²)/(m l).
    let omega_squared = lin.omega_squared.as_ref().unwrap()[0];
    assert!(
        (omega_squared - 3.0_f64.hypot(9.81)).abs() < 1e-9,
        "{omega_squared}"
    );
    // The other rest position, upside down along the force, is unstable.
    let other = equilibria.linearized[1 - index].as_ref().unwrap();
    assert_eq!(other.stable, Some(false));
}

#[test]
fn a_constant_couple_on_a_coordinate_counts_as_a_potential() {
    let text = "coordinates theta
parameters m = 1, l = 1, g = 9.81
inputs C = 2
frame N
frame B = N rotated theta about z
point P = -l*B.y
particle P mass m
gravity -g*N.y
generalized force C on theta
";
    let analysis = Analysis::from_text(text).unwrap();
    let equilibria = analysis.equilibria().unwrap();
    // sin θ = C/(m g l): the stable one hangs at asin(2/9.81).
    let (_, lin) = linearized_at(equilibria, &[(2.0_f64 / 9.81).asin()]);
    assert_eq!(lin.criterion, Criterion::LagrangeDirichlet);
    assert_eq!(lin.stable, Some(true));
}

#[test]
fn a_follower_force_is_not_taken_for_a_potential() {
    // Ziegler's double pendulum, upright, loaded at its tip by a force along its last link
    // (a follower force): below the flutter load it is stable only in the linear sense, and
    // its stiffness is not symmetric, so Lagrange–Dirichlet must not be claimed.
    let text = "coordinates th1, th2
parameters m = 1, l = 1, k = 10
inputs P = 1
frame N
frame B1 = N rotated th1 about z
frame B2 = N rotated th2 about z
point A = l*B1.y
point T = A + l*B2.y
particle A mass 2*m
particle T mass m
spring k on th1
spring k on th2 - th1
force -P*B2.y at T
";
    let analysis = Analysis::from_text(text).unwrap();
    let (_, lin) = linearized_at(analysis.equilibria().unwrap(), &[0.0, 0.0]);
    let k0 = &lin.k0;
    assert!((k0[0][1] - k0[1][0]).abs() > 0.1, "{k0:?}");
    assert_ne!(lin.criterion, Criterion::LagrangeDirichlet);
}
