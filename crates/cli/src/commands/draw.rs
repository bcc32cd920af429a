//! `lagrange draw MODEL [--at NAME=VALUE,…] [--out FILE.svg]`: the system drawn at its
//! initial state (or the one given), as an SVG figure — printed, or written to a file.

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
    /// Write the figure to this `.svg` file instead of printing it.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Draws the model and prints or writes the SVG.
pub fn run(args: &DrawArgs) -> Result<Exit, Failure> {
    let path = args.model.as_path();
    if let Some(out) = &args.out {
        if !out
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("svg"))
        {
            return Err(Failure::input(format!(
                "--out {}: a figure is written as SVG; give a file name ending in .svg",
                out.display()
            )));
        }
    }
    if let Some(out) = &args.out {
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
        Some(out) => write(out, &figure.svg)?,
    }
    Ok(Exit::Success)
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

fn write(out: &Path, svg: &str) -> Result<(), Failure> {
    std::fs::write(out, svg).map_err(|e| output_error(&format!("`{}`", out.display()), &e))?;
    println(&format!("wrote {}", out.display()))
}
