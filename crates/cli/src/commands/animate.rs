//! `lagrange animate MODEL [--t-end T] [--fps N] [--trace P]… [--mode K] [--out FILE.html]`:
//! the simulated motion, or the `K`-th linearized mode about a stable equilibrium, as a
//! self-contained HTML page that plays in a browser.

use std::path::PathBuf;

use clap::Args;
use lagrange::{FileFormat, Output};

use crate::exit::{check_output, emit, Exit, Failure};

/// The flags of `lagrange animate`.
#[derive(Args, Debug)]
pub struct AnimateArgs {
    #[command(flatten)]
    pub input: crate::args::ModelInput,
    /// End time (default: the model's `simulate to T`; with `--mode`, three periods).
    #[arg(long)]
    pub t_end: Option<f64>,
    /// Animate the K-th linearized mode (1 = the slowest) about the first stable equilibrium
    /// instead of simulating: q(t) = q₀ + a φ_K cos(ω_K t).
    #[arg(long, value_name = "K")]
    pub mode: Option<usize>,
    /// Frames per second of simulated time.
    #[arg(long, default_value_t = 30.0)]
    pub fps: f64,
    /// Draw the path of this point (repeatable).
    #[arg(long, value_name = "POINT")]
    pub trace: Vec<String>,
    /// Write the animation to this `.html` file instead of printing it.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Simulates (or follows a mode), draws every frame, and prints or writes the page.
pub fn run(args: &AnimateArgs) -> Result<Exit, Failure> {
    let path = args.input.model.as_path();
    if let Some(out) = &args.out {
        FileFormat::of(out, Output::Animation).map_err(|e| Failure::flag("--out", e))?;
        check_output(out, path)?;
    }
    if !(args.fps.is_finite() && args.fps > 0.0) {
        let fps = args.fps;
        return Err(Failure::input(format!(
            "--fps {fps}: give a positive number"
        )));
    }
    let analysis = super::load(path, &args.input.set)?;
    let html = match args.mode {
        None => analysis.animation(args.t_end, args.fps, &args.trace),
        Some(k) => analysis.mode_animation(k, args.t_end, args.fps, &args.trace),
    }
    .map_err(|e| Failure::of(e, path))?;
    emit(args.out.as_deref(), html)?;
    Ok(Exit::Success)
}
