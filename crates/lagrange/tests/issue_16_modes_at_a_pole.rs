//! Issue 16: `--mode K` failed for the spherical pendulum and the heavy top ("no stable
//! equilibrium was found") and said little for the rolling disk.
//!
//! Cause: both stable equilibria sit at a pole of the coordinates. At the spherical
//! pendulum's bottom (θ = 0) the azimuth φ moves nothing, and with the top's axis vertical
//! (θ = π, hanging) precession ψ and spin φ turn about the same line: some combination of
//! the coordinates moves no point, so the mass matrix M₀ is singular there, the linearization
//! cannot solve K₀ φ = ω² M₀ φ, and its stability was "undecided". The rolling disk on its
//! slope has no equilibrium at all.
//!
//! Fix: at such an equilibrium the modes are computed in the directions that move the system
//! (the range of M₀; the null directions must not change the forces either), which are true
//! small oscillations: the pendulum's swing (ω² = g/l), the hanging top's swing about its tip
//! (ω² = m g l / A) and its free spin (ω² = 0). The errors name the pole and what moves
//! nothing, or say that the model never rests.

use std::path::Path;

use lagrange::Analysis;

fn example(name: &str) -> Analysis {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    Analysis::from_file(&path).expect("a valid example")
}

/// The values rows of an animation's page: the time, then each coordinate.
fn values(html: &str) -> Vec<Vec<f64>> {
    let start = html.find("\nconst Q=").expect("the values") + 9;
    let end = start + html[start..].find(";\n").expect("the end of the values");
    serde_json::from_str(&html[start..end]).expect("JSON")
}

/// The `ω` in the page's title.
fn omega(html: &str) -> f64 {
    let at = html.find("ω = ").expect("ω in the title") + "ω = ".len();
    html[at..at + html[at..].find(' ').expect("a unit")]
        .parse()
        .expect("a number")
}

/// Every row is `rest + a shape cos(ω t)` (to the page's four decimals), with `a shape` read
/// off the first row; returns that first displacement.
fn follows(rows: &[Vec<f64>], rest: &[f64], omega: f64) -> Vec<f64> {
    let first: Vec<f64> = rows[0][1..].iter().zip(rest).map(|(q, r)| q - r).collect();
    for row in rows {
        let c = (omega * row[0]).cos();
        for (j, (q, r)) in row[1..].iter().zip(rest).enumerate() {
            let expected = r + first[j] * c;
            assert!(
                (q - expected).abs() < 2e-4,
                "t = {}, coordinate {j}: {q} against {expected}",
                row[0]
            );
        }
    }
    first
}

#[test]
fn the_spherical_pendulum_swings_through_its_bottom() {
    let pendulum = example("spherical-pendulum.lag");
    let html = pendulum
        .mode_animation(1, None, 30.0, &[])
        .expect("a mode about the bottom");
    // g = 9.81, l = 1: ω² = g / l.
    let w = omega(&html);
    assert!((w - 9.81f64.sqrt()).abs() < 1e-4, "ω = {w}");
    // Coordinates (phi, theta): theta swings about 0, phi stays.
    let swing = follows(&values(&html), &[0.0, 0.0], w);
    assert!(swing[0].abs() < 1e-9 && swing[1].abs() > 0.05, "{swing:?}");
    let two = pendulum.mode_animation(2, None, 30.0, &[]);
    assert!(
        matches!(&two, Err(lagrange::Error::NotAvailable(m))
            if m.contains("no mode 2") && m.contains("pole of the coordinates")
                && m.contains("moving phi alone moves nothing")),
        "{two:?}"
    );
}

#[test]
fn the_hanging_top_swings_and_its_spin_does_not_oscillate() {
    let top = example("heavy-symmetric-top.lag");
    let html = top
        .mode_animation(2, None, 30.0, &[])
        .expect("a mode about the hanging top");
    // m = 0.5, l = 0.05, A = 0.002, g = 9.81: ω² = m g l / A about the tip.
    let w = omega(&html);
    assert!(
        (w - (0.5 * 9.81 * 0.05 / 0.002f64).sqrt()).abs() < 1e-4,
        "ω = {w}"
    );
    // Coordinates (psi, theta, phi): theta swings about π, the others stay.
    let swing = follows(&values(&html), &[0.0, std::f64::consts::PI, 0.0], w);
    assert!(
        swing[0].abs() < 1e-9 && swing[2].abs() < 1e-9 && swing[1].abs() > 0.05,
        "{swing:?}"
    );
    let spin = top.mode_animation(1, None, 30.0, &[]);
    assert!(
        matches!(&spin, Err(lagrange::Error::NotAvailable(m))
            if m.contains("mode 1 does not oscillate (ω² = 0") && m.contains("oscillate: 2")),
        "{spin:?}"
    );
}

#[test]
fn a_disk_rolling_down_a_slope_never_rests() {
    let disk = example("rolling-disk-incline.lag");
    let e = disk.mode_animation(1, None, 30.0, &[]);
    assert!(
        matches!(&e, Err(lagrange::Error::NotAvailable(m))
            if m.contains("has no equilibrium") && m.contains("never rests")),
        "{e:?}"
    );
}

#[test]
fn a_top_hanging_at_the_other_pole_swings_too() {
    // With l < 0 the centre of mass is on the other side of the tip: the top hangs at θ = 0,
    // where ψ and φ turn together (ψ + φ), not at θ = π (ψ − φ); the upright θ = π, first
    // unstable in the directions that move it, is passed over.
    let mut top = example("heavy-symmetric-top.lag");
    top.set(&lagrange::parse_assignment("l=-0.05").expect("an assignment"))
        .expect("set");
    let html = top
        .mode_animation(2, None, 30.0, &[])
        .expect("the top hanging at θ = 0");
    let w = omega(&html);
    assert!(
        (w - (0.5 * 9.81 * 0.05 / 0.002f64).sqrt()).abs() < 1e-4,
        "ω = {w}"
    );
    let swing = follows(&values(&html), &[0.0, 0.0, 0.0], w);
    assert!(swing[1].abs() > 0.05, "{swing:?}");
}
