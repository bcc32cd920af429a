//! Issue 18: the upright rolling disk, a steady motion of a nonholonomic system with a known
//! stability condition: a uniform disk of radius R rolling upright at speed v is stable (to
//! first order: its lean oscillates) when v² > g R / 3 and falls over when slower.

use lagrange::Analysis;

/// A uniform disk rolling without slipping on the horizontal plane: contact P at (x, y),
/// heading psi, lean phi, spin theta about the axle Y.y.
fn disk(radius: f64, g: f64) -> Analysis {
    let text = format!(
        "coordinates x, y, psi, phi, theta
parameters  m = 1.3, R = {radius}, g = {g}, v = 1
frame N
frame Y = N rotated psi about z then phi about x
frame D = Y rotated theta about y
point P = x*N.x + y*N.y
point C = P + R*Y.z
body disk mass m at C frame D inertia m*R^2/4, m*R^2/2, m*R^2/4
gravity -g*N.z
constraint roll: rolling disk at P
initial x' = v, psi' = 0
"
    );
    match Analysis::from_text(&text) {
        Ok(a) => a,
        Err(e) => panic!("the disk model does not load: {e}"),
    }
}

/// The largest real part of the linearization's eigenvalues at speed `v`.
fn leading(a: &mut Analysis, v: f64) -> f64 {
    a.set_value("v", v).expect("v is a parameter");
    let lin = a
        .steady_linearization()
        .expect("upright rolling linearizes");
    assert_eq!(lin.shape, ["phi"]);
    lin.eigenvalues
        .iter()
        .map(|(re, _)| *re)
        .fold(f64::MIN, f64::max)
}

#[test]
fn upright_disk_is_stable_above_the_square_root_of_g_r_over_three() {
    for (radius, g) in [(0.3, 9.81), (1.0, 1.0), (0.05, 3.7)] {
        let mut a = disk(radius, g);
        let critical = (g * radius / 3.0).sqrt();
        let below = leading(&mut a, 0.98 * critical);
        let above = leading(&mut a, 1.02 * critical);
        assert!(
            below > 1e-3 * (g / radius).sqrt(),
            "R = {radius}: {below} below the critical speed"
        );
        assert!(
            above.abs() < 1e-9 * (g / radius).sqrt(),
            "R = {radius}: {above} above it"
        );
    }
}
