//! `lagrange equilibria MODEL` and `lagrange linearize MODEL`: all equilibria with their
//! stability, the linearized dynamics about them, and parameter sweeps (bifurcation tables).

use std::path::Path;

use lagrange::{Analysis, Linearized, Search, Written};

use super::each;
use crate::args::{EquilibriumOptions, ModelInput};
use crate::exit::{print, Exit, Failure};

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
    if initial.is_some() && analysis.describes_steady_motion() {
        return super::steady::run(path, &analysis, options);
    }
    match options.sweep.as_slice() {
        [] => {}
        [sweep] => return run_sweep(path, &analysis, &search, sweep, options),
        _ => {
            return Err(Failure::input(
                "--sweep takes one parameter here (two only with linearize --periodic)",
            ))
        }
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
        None => found.written(options.format),
        Some(initial) => {
            let deviations = (!initial.is_empty())
                .then(|| analysis.read_deviations(initial, &found.rest.coordinates))
                .transpose()
                .map_err(|e| Failure::input(format!("--initial {e}")))?;
            let deviations = deviations.as_ref().map(|(q, v)| (&q[..], &v[..]));
            let equilibria = &found;
            Linearized {
                equilibria,
                only,
                deviations,
            }
            .written(options.format)
        }
    };
    print(text)?;
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
    print(table.written(options.format))?;
    Ok(Exit::Success)
}
