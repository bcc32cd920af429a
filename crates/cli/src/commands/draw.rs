//! `lagrange draw MODEL [--at NAME=VALUE,…] [--out FILE.svg|FILE.png]`: the system drawn at
//! its initial state (or the one given), as an SVG figure — printed, or written to a file, or
//! as a PNG image.

use std::path::PathBuf;

use clap::Args;
use lagrange::{FileFormat, Output};

use crate::exit::{check_output, emit, Exit, Failure};

/// The flags of `lagrange draw`.
#[derive(Args, Debug)]
pub struct DrawArgs {
    /// The model file (`.lag`).
    pub model: PathBuf,
    /// The state to draw, instead of the model's initial one: coordinates, parameters or
    /// inputs, and `t` for the time, e.g. `--at theta=0.3,x=0.1` (repeatable).
    #[arg(long, value_name = "NAME=VALUE,…", value_delimiter = ',')]
    pub at: Vec<String>,
    /// Write the figure to this `.svg` file (or `.png`, at twice the SVG's pixels) instead of
    /// printing it.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Draws the model and prints or writes the SVG.
pub fn run(args: &DrawArgs) -> Result<Exit, Failure> {
    let path = args.model.as_path();
    let out = args.out.as_deref();
    // Before any work: the format is known and the model file is never written over.
    let format = out
        .map(|out| FileFormat::of(out, Output::Figure))
        .transpose()
        .map_err(|e| Failure::flag("--out", e))?;
    if let Some(out) = out {
        check_output(out, path)?;
    }
    let mut analysis = super::load(path, &[])?;
    let time = analysis
        .set_state(&args.at)
        .map_err(|e| Failure::flag("--at", e))?;
    let figure = analysis.figure(time).map_err(|e| Failure::of(e, path))?;
    let bytes = match format {
        Some(FileFormat::Png) => figure
            .png(lagrange::PNG_SCALE)
            .map_err(|e| Failure::input(format!("--out: {e}")))?,
        _ => figure.svg.into_bytes(),
    };
    emit(out, bytes)?;
    Ok(Exit::Success)
}
