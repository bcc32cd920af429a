//! `lagrange equilibria MODEL` and `lagrange linearize MODEL`: all equilibria with their
//! stability, the linearized dynamics about them, and parameter sweeps (bifurcation tables).

use std::path::Path;

use lagrange::{Analysis, Search};

use super::{each, eom::json};
use crate::args::{EomFormat, EquilibriumOptions, ModelInput};
use crate::exit::{println, Exit, Failure};

/// `lagrange equilibria` (`initial` is `None`) or `lagrange linearize`.
pub fn run(
    input: &ModelInput,
    options: &EquilibriumOptions,
    only: Option<usize>,
    initial: Option<&[String]>,
) -> Result<Exit, Failure> {
    let path = input.model.as_path();
    let analysis = super::load(path, &input.set)?;
    let search = Search {
        steady: each(&options.steady, "--steady", |s| analysis.read_number(s))?,
        ranges: each(&options.range, "--range", |s| analysis.read_range(s))?,
    };
    let as_json = options.format == EomFormat::Json;
    if initial.is_some() && analysis.describes_steady_motion() {
        return super::steady::run(path, &analysis, options);
    }
    if let Some(sweep) = &options.sweep {
        return run_sweep(path, &analysis, &search, sweep, options);
    }
    if options.plot.is_some() {
        return Err(Failure::input(
            "--plot draws the bifurcation diagram of a --sweep; add --sweep P=a..b",
        ));
    }
    let found = analysis
        .equilibria_with(&search)
        .map_err(|e| Failure::of(e, path))?;
    if let Some(i) = only {
        let refused = |e| Failure::plain(e).prefixed(&format!("--equilibrium {i}"));
        found.check_index(i).map_err(refused)?;
    }
    let text = match initial {
        None if as_json => json(&found.to_json()),
        None => found.to_text(),
        Some(initial) => {
            let deviations = (!initial.is_empty())
                .then(|| analysis.read_deviations(initial, &found.rest.coordinates))
                .transpose()
                .map_err(|e| Failure::input(format!("--initial {e}")))?;
            let deviations = deviations.as_ref().map(|(q, v)| (&q[..], &v[..]));
            if as_json {
                json(&found.linearized_json(only, deviations))
            } else {
                found.linearized_text(only, deviations)
            }
        }
    };
    println(&text)?;
    Ok(Exit::Success)
}

fn run_sweep(
    path: &Path,
    analysis: &Analysis,
    search: &Search,
    sweep: &str,
    options: &EquilibriumOptions,
) -> Result<Exit, Failure> {
    let range = analysis
        .read_range(sweep)
        .map_err(|e| Failure::input(format!("--sweep {e}")))?;
    let table = analysis
        .equilibrium_sweep(search, &range, options.steps)
        .map_err(|e| Failure::of(e, path).prefixed("--sweep"))?;
    if let Some(plot) = &options.plot {
        table.plot(plot).map_err(|e| Failure::of(e.into(), path))?;
        eprintln!("wrote {}", plot.display());
    }
    println(&if options.format == EomFormat::Json {
        json(&table.to_json())
    } else {
        table.to_text()
    })?;
    Ok(Exit::Success)
}
