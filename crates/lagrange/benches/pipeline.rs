//! The pipeline on the canonical systems (`mechanics::canonical`): deriving, preparing a
//! run (compiling the tapes), a one-second simulation, and a 50-run sweep from one derivation.
//! `cargo bench -p lagrange --bench pipeline`.

use divan::Bencher;
use lagrange::mechanics::canonical;
use lagrange::{Analysis, SimulationOptions};

fn main() {
    divan::main();
}

const NAMES: [&str; 5] = [
    "pendulum",
    "double-pendulum",
    "cart-pendulum",
    "rolling-disk",
    "four-bar",
];

fn analysis(name: &str) -> Analysis {
    let c = canonical::all()
        .into_iter()
        .find(|c| c.name == name)
        .expect("a canonical system");
    let mut analysis = Analysis::from_system(c.system);
    for (q, x, v) in &c.initial {
        analysis.set_value(q, *x).expect("a coordinate");
        analysis.set_value(&format!("{q}_d"), *v).expect("a rate");
    }
    analysis
}

fn one_second() -> SimulationOptions {
    SimulationOptions {
        t_end: Some(1.0),
        ..SimulationOptions::default()
    }
}

#[divan::bench(args = NAMES)]
fn derive(bencher: Bencher, name: &str) {
    bencher
        .with_inputs(|| analysis(name))
        .bench_values(|a| a.equations().map(|e| e.coordinates().len()).ok());
}

#[divan::bench(args = NAMES)]
fn prepare_run(bencher: Bencher, name: &str) {
    let a = analysis(name);
    let _ = a.equations();
    bencher.bench(|| a.simulation(&one_second()).is_ok());
}

#[divan::bench(args = NAMES)]
fn simulate_one_second(bencher: Bencher, name: &str) {
    let a = analysis(name);
    let _ = a.equations();
    bencher.bench(|| a.simulate(&one_second()).map(|r| r.rows.len()).ok());
}

#[divan::bench(args = ["pendulum", "double-pendulum"])]
fn sweep_of_50_runs(bencher: Bencher, name: &str) {
    let a = analysis(name);
    let q = a.system().coordinates()[0].clone();
    let values: Vec<Vec<f64>> = (0..50).map(|k| vec![0.02 * f64::from(k)]).collect();
    bencher.bench(|| {
        a.sweep(&one_second(), std::slice::from_ref(&q), &values, &|| {})
            .map(|r| r.len())
            .ok()
    });
}
