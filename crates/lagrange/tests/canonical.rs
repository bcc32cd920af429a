//! The canonical systems (`mechanics::canonical`), built in code, through the whole pipeline:
//! derived once, simulated with the energy (or Jacobi integral) kept and the constraints
//! held, equilibria where the course asks for them — and the same numbers from their model
//! files under `examples/canonical/`.

use std::path::Path;

use lagrange::mechanics::canonical;
use lagrange::{Analysis, Ending, SimulationOptions};

fn tight(t_end: f64) -> SimulationOptions {
    SimulationOptions {
        t_end: Some(t_end),
        rtol: Some(1e-10),
        atol: Some(1e-12),
        ..SimulationOptions::default()
    }
}

fn in_code(c: &canonical::Canonical) -> Analysis {
    let mut analysis = Analysis::from_system(c.system.clone());
    for (q, x, v) in &c.initial {
        analysis.set_value(q, *x).unwrap();
        analysis.set_value(&format!("{q}_d"), *v).unwrap();
    }
    analysis
}

#[test]
fn every_canonical_system_runs_keeping_its_energy_and_constraints() {
    for c in canonical::all() {
        let analysis = in_code(&c);
        let run = analysis.simulate(&tight(2.0)).unwrap();
        assert_eq!(run.ending, Ending::Finished, "{}", c.name);
        let last = run.rows.last().unwrap();
        let (energy, drift) = (last[last.len() - 2], last[last.len() - 1]);
        assert!(energy.abs() < 1e-7, "{}: energy error {energy}", c.name);
        assert!(drift.is_nan() || drift < 1e-8, "{}: drift {drift}", c.name);
        assert_eq!(analysis.derivations(), 1, "{}", c.name);
    }
}

#[test]
fn the_model_files_give_the_same_motion_as_the_systems_built_in_code() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/canonical");
    for c in canonical::all() {
        let code = in_code(&c).simulate(&tight(1.0)).unwrap();
        let mut file = Analysis::from_file(&dir.join(format!("{}.lag", c.name))).unwrap();
        for (q, x, v) in &c.initial {
            file.set_value(q, *x).unwrap();
            file.set_value(&format!("{q}_d"), *v).unwrap();
        }
        let model = file.simulate(&tight(1.0)).unwrap();
        assert_eq!(code.columns, model.columns, "{}", c.name);
        let (a, b) = (code.rows.last().unwrap(), model.rows.last().unwrap());
        for (x, y) in a.iter().zip(b).take(a.len() - 2) {
            assert!((x - y).abs() < 1e-9, "{}: {a:?} vs {b:?}", c.name);
        }
    }
}

#[test]
fn the_pendulums_hang_stably_at_their_closed_form_frequencies() {
    let g: f64 = 9.81;
    let pendulum = Analysis::from_system(canonical::pendulum());
    let found = pendulum.equilibria().unwrap();
    let omegas: Vec<f64> = found
        .linearized
        .iter()
        .filter_map(|l| l.as_ref().ok()?.frequencies().first().copied().flatten())
        .collect();
    assert_eq!(omegas.len(), 1);
    assert!((omegas[0] - g.sqrt()).abs() < 1e-9, "{omegas:?}");
    // Double pendulum, unit masses and lengths: ω² = g (2 ∓ √2).
    let double = Analysis::from_system(canonical::double_pendulum());
    let hanging = double
        .equilibria()
        .unwrap()
        .linearized
        .iter()
        .filter_map(|l| l.as_ref().ok())
        .find(|l| l.stable == Some(true))
        .expect("a stable equilibrium");
    let w2 = hanging.omega_squared.as_ref().unwrap();
    let expected = [g * (2.0 - 2f64.sqrt()), g * (2.0 + 2f64.sqrt())];
    for (a, b) in w2.iter().zip(expected) {
        assert!((a - b).abs() < 1e-9 * b, "{w2:?}");
    }
}
