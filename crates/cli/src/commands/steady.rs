//! `lagrange linearize MODEL` for a model whose `initial` statement describes a steady motion
//! of a nonholonomic system (the Whipple bicycle): the linearization by Kane's method, the
//! canonical form when the steady rates follow one parameter, and `--sweep` of a parameter
//! with the speeds where stability changes and `--plot` of the eigenvalues.

use std::path::Path;

use lagrange::steady_print::{plot_sweep, steady_json, steady_text, sweep_json, sweep_text};
use lagrange::{json_text, Analysis, ResultFormat};

use crate::args::EquilibriumOptions;
use crate::exit::{print, println, Exit, Failure};

/// Prints the steady linearization, or the sweep asked for.
pub fn run(
    path: &Path,
    analysis: &Analysis,
    options: &EquilibriumOptions,
) -> Result<Exit, Failure> {
    let as_json = options.format == ResultFormat::Json;
    if options.sweep.len() > 1 {
        return Err(Failure::input(
            "--sweep takes one parameter about a steady motion",
        ));
    }
    if let [sweep] = options.sweep.as_slice() {
        let range = analysis
            .read_range(sweep)
            .map_err(|e| Failure::input(format!("--sweep {e}")))?;
        let table = analysis
            .steady_sweep(&range.name, range.low, range.high, options.steps)
            .map_err(|e| Failure::of(e, path).prefixed("--sweep"))?;
        let changes = analysis
            .steady_crossings(&table)
            .map_err(|e| Failure::of(e, path).prefixed("--sweep"))?;
        if let Some(plot) = &options.plot {
            plot_sweep(plot, &table).map_err(|e| Failure::of(e, path))?;
            eprintln!("wrote {}", plot.display());
        }
        if as_json {
            print(json_text(&sweep_json(&table, &changes)))?;
        } else {
            println(&sweep_text(&table, &changes))?;
        }
        return Ok(Exit::Success);
    }
    let lin = analysis
        .steady_linearization()
        .map_err(|e| Failure::of(e, path))?;
    let canonical = analysis
        .steady_speed_parameter()
        .and_then(|v| analysis.canonical_form(&v).ok());
    let coordinates = analysis.system().coordinates();
    if as_json {
        print(json_text(&steady_json(
            coordinates,
            &lin,
            canonical.as_ref(),
        )))?;
    } else {
        println(&steady_text(coordinates, &lin, canonical.as_ref()))?;
    }
    Ok(Exit::Success)
}
