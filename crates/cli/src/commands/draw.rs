//! `lagrange draw MODEL [--at NAME=VALUE,…] [--out FILE.svg|FILE.png]`: the system drawn at
//! its initial state (or the one given), as an SVG figure — printed, or written to a file, or
//! as a PNG image.

use std::path::{Path, PathBuf};

use clap::Args;

use crate::exit::{check_output, output_error, print, println, Exit, Failure};

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
    let png = args
        .out
        .as_deref()
        .is_some_and(|out| extension_is(out, "png"));
    if let Some(out) = &args.out {
        if !png && !extension_is(out, "svg") {
            return Err(Failure::input(format!(
                "--out {}: a figure is written as SVG or PNG; give a file name ending in .svg \
                 or .png",
                out.display()
            )));
        }
        // Before any work: the model file is never written over.
        check_output(out, path)?;
    }
    let (time, rest) = split_time(&args.at)?;
    let mut analysis = super::load(path, &[])?;
    for item in &rest {
        let assignment =
            lagrange::parse_assignment(item).map_err(|e| Failure::input(format!("--at {e}")))?;
        analysis
            .set(&assignment)
            .map_err(|e| Failure::input(format!("--at {item}: {e}")))?;
    }
    let figure = analysis.figure(time).map_err(|e| Failure::of(e, path))?;
    match &args.out {
        None => print(&figure.svg)?,
        Some(out) if png => {
            let image = figure
                .png(PNG_SCALE)
                .map_err(|e| Failure::input(format!("--out {}: {e}", out.display())))?;
            write(out, &image)?;
        }
        Some(out) => write(out, figure.svg.as_bytes())?,
    }
    Ok(Exit::Success)
}

/// Image pixels per SVG pixel of a PNG figure: sharp in print at the figure's size.
pub const PNG_SCALE: f64 = 2.0;

fn extension_is(path: &Path, extension: &str) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case(extension))
}

/// `t=VALUE` among the assignments is the time; the others are values.
fn split_time(items: &[String]) -> Result<(f64, Vec<String>), Failure> {
    let mut time = 0.0;
    let mut rest = Vec::new();
    for item in items {
        match item.split_once('=') {
            Some((name, value)) if name.trim() == "t" => {
                time = value
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|t| t.is_finite())
                    .ok_or_else(|| {
                        Failure::input(format!("--at {item}: the time must be a number"))
                    })?;
            }
            _ => rest.push(item.clone()),
        }
    }
    Ok((time, rest))
}

fn write(out: &Path, bytes: &[u8]) -> Result<(), Failure> {
    std::fs::write(out, bytes).map_err(|e| output_error(&format!("`{}`", out.display()), &e))?;
    println(&format!("wrote {}", out.display()))
}
