//! Times one right-hand side evaluation (tapes and the solve for `q̈`) of a model at its
//! initial state, for `bench/simulate/run.sh` and `bench/compare/run.sh`: `cargo run --release
//! -p lagrange --example rhs_timing -- MODEL [CALLS] [tree|dense]` prints `rhs_ns=…
//! instructions=… route=tree|dense`. The route is the O(n) elimination on the model's
//! kinematic tree or the dense solve of `M q̈ = f`: the library's choice, or the one asked for.

use std::time::Instant;

use lagrange::{numeric, Analysis, SimulationOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .ok_or("usage: rhs_timing MODEL [CALLS] [tree|dense]")?;
    let calls: u32 = args.next().map_or(Ok(1_000_000), |s| s.parse())?;
    let route = args.next();
    let analysis = Analysis::from_file(std::path::Path::new(&path))?;
    let options = SimulationOptions {
        t_end: Some(10.0),
        ..SimulationOptions::default()
    };
    let mut simulation = analysis.simulation(&options)?;
    match route.as_deref() {
        None => {}
        Some("tree") if !simulation.set_rhs_by_tree(true) => {
            return Err("the model has no kinematic tree".into());
        }
        Some("tree") => {}
        Some("dense") => {
            simulation.set_rhs_by_tree(false);
        }
        Some(other) => return Err(format!("route `{other}`: tree or dense").into()),
    }
    let state = simulation.initial_state().to_vec();
    let mut derivative = vec![0.0; state.len()];
    let best = simulation.with_rhs(|system| -> Result<f64, numeric::RhsError> {
        let mut best = f64::INFINITY;
        for _ in 0..5 {
            let started = Instant::now();
            for k in 0..calls {
                // The time varies so the work cannot be hoisted out of the loop.
                let t = f64::from(k) * 1e-9;
                system.rhs(t, std::hint::black_box(&state), &mut derivative)?;
                std::hint::black_box(&derivative);
            }
            best = best.min(started.elapsed().as_secs_f64() / f64::from(calls));
        }
        Ok(best)
    })?;
    println!(
        "rhs_ns={:.1} instructions={} route={}",
        best * 1e9,
        simulation.rhs_instructions(),
        if simulation.rhs_by_tree() {
            "tree"
        } else {
            "dense"
        }
    );
    Ok(())
}
