//! Linearization at a pole of the coordinates (issue 17): where `M₀` is singular in the
//! model's coordinates, `lagrange linearize` gives `M` and `K` in the regular chart and the
//! natural frequencies from them, equal to the textbook values — the spherical pendulum's
//! `ω² = g/ℓ` twice at the bottom (and `−g/ℓ` at the top), the hanging top's `m g ℓ / A`.

use lagrange::{Analysis, ResultFormat, Written};

fn spherical_pendulum(m: f64, l: f64, g: f64) -> Analysis {
    Analysis::from_text(&format!(
        "coordinates phi, theta\n\
         parameters m = {m}, l = {l}, g = {g}\n\
         frame N\n\
         frame B = N rotated phi about z then theta about x\n\
         point P = -l*B.z\n\
         particle P mass m\n\
         gravity -g*N.z\n"
    ))
    .expect("the model reads")
}

fn close(a: f64, b: f64, relative: f64) -> bool {
    (a - b).abs() <= relative * b.abs().max(1e-300)
}

#[test]
fn the_hanging_spherical_pendulum_has_omega_squared_g_over_l_twice() {
    for (m, l, g) in [(1.0, 1.0, 9.81), (0.3, 2.5, 1.62), (7.0, 0.04, 24.79)] {
        let analysis = spherical_pendulum(m, l, g);
        let found = analysis.equilibria().unwrap();
        assert_eq!(found.pole_modes.len(), 2);
        let bottom = found.pole_modes[0].as_ref().expect("a chart at θ = 0");
        let top = found.pole_modes[1].as_ref().expect("a chart at θ = π");
        for k in 0..2 {
            assert!(close(bottom.omega_squared[k], g / l, 1e-8), "{bottom:?}");
            assert!(close(top.omega_squared[k], -g / l, 1e-8), "{top:?}");
            // M = m ℓ² I and K = m g ℓ I in (u, v).
            assert!(close(bottom.mass[k][k], m * l * l, 1e-8), "{bottom:?}");
            assert!(close(bottom.stiffness[k][k], m * g * l, 1e-8), "{bottom:?}");
            assert!(bottom.mass[k][1 - k].abs() < 1e-8 * m * l * l);
        }
        let w = (g / l).sqrt();
        assert_eq!(bottom.frequencies().len(), 2);
        assert!(bottom
            .frequencies()
            .iter()
            .all(|f| close(f.unwrap(), w, 1e-8)));
        assert!(top.frequencies().iter().all(Option::is_none));
    }
}

#[test]
fn the_hanging_top_nutates_at_m_g_l_over_a_and_its_spin_is_free() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/heavy-symmetric-top.lag"
    );
    let analysis = Analysis::from_file(std::path::Path::new(path)).unwrap();
    let found = analysis.equilibria().unwrap();
    let (m, l, a, c, g) = (0.5, 0.05, 0.002, 0.0008, 9.81);
    let hanging = found
        .pole_modes
        .iter()
        .flatten()
        .find(|p| p.omega_squared.iter().any(|w| *w > 1.0))
        .expect("the hanging top's chart");
    let mut w2 = hanging.omega_squared.clone();
    w2.sort_by(f64::total_cmp);
    assert!(w2[0].abs() < 1e-6, "the spin is a free coordinate: {w2:?}");
    assert!(close(w2[1], m * g * l / a, 1e-7) && close(w2[2], m * g * l / a, 1e-7));
    assert!(close(hanging.mass[2][2], c, 1e-8), "{hanging:?}");
}

#[test]
fn linearize_prints_and_writes_the_chart_linearization() {
    let analysis = spherical_pendulum(1.0, 1.0, 9.81);
    let found = analysis.equilibria().unwrap();
    let linearized = lagrange::Linearized {
        equilibria: found,
        only: Some(0),
        deviations: None,
    };
    let text = linearized.written(ResultFormat::Text);
    assert!(
        text.contains("linearized in the regular chart (u, v)"),
        "{text}"
    );
    assert!(
        text.contains("natural frequencies: 3.132092 rad/s, 3.132092 rad/s"),
        "{text}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&linearized.written(ResultFormat::Json)).unwrap();
    let poles = json["at_poles"].as_array().expect("a list");
    assert_eq!(poles.len(), 1, "only the equilibrium asked for: {json}");
    assert_eq!(poles[0]["equilibrium"], 0);
    let w = poles[0]["frequencies"][0].as_f64().unwrap();
    assert!(close(w, 9.81_f64.sqrt(), 1e-8), "{w}");
}
