//! `lagrange equilibria MODEL` and `lagrange linearize MODEL`: all equilibria with their
//! stability, the linearized dynamics about them, and parameter sweeps (bifurcation tables).

use std::path::Path;

use lagrange::{Analysis, Range, Search};

use crate::args::{EomFormat, EquilibriumOptions};
use crate::exit::{println, Exit, Failure};

/// `lagrange equilibria` (`initial` is `None`) or `lagrange linearize`.
pub fn run(
    path: &Path,
    options: &EquilibriumOptions,
    only: Option<usize>,
    initial: Option<&[String]>,
) -> Result<Exit, Failure> {
    let analysis = super::load(path, &options.set)?;
    let search = search(&analysis, options)?;
    let json = options.format == EomFormat::Json;
    if let Some(sweep) = &options.sweep {
        return run_sweep(path, &analysis, &search, sweep, options, json);
    }
    if options.plot.is_some() {
        return Err(Failure::input(
            "--plot draws the bifurcation diagram of a --sweep; add --sweep P=a..b",
        ));
    }
    let found = analysis
        .equilibria_with(&search)
        .map_err(|e| Failure::of(e, path))?;
    if let Some(i) = only.filter(|i| *i >= found.set.equilibria.len()) {
        return Err(Failure::input(format!(
            "--equilibrium {i}: there are {} equilibria (indices from 0)",
            found.set.equilibria.len()
        )));
    }
    let text = match initial {
        None if json => super::eom::json(&found.to_json()),
        None => found.to_text(),
        Some(initial) => {
            let lookup = analysis.lookup();
            let deviations = (!initial.is_empty())
                .then(|| lagrange::assign::deviations(initial, &found.rest.coordinates, &lookup))
                .transpose()
                .map_err(|e| Failure::input(format!("--initial {e}")))?;
            let deviations = deviations.as_ref().map(|(q, v)| (&q[..], &v[..]));
            if json {
                super::eom::json(&found.linearized_json(only, deviations))
            } else {
                found.linearized_text(only, deviations)
            }
        }
    };
    println(&text)?;
    Ok(Exit::Success)
}

/// `--steady` and `--range` as a search.
fn search(analysis: &Analysis, options: &EquilibriumOptions) -> Result<Search, Failure> {
    let lookup = analysis.lookup();
    let mut search = Search::default();
    for item in &options.steady {
        let a = lagrange::parse_assignment(item)
            .map_err(|e| Failure::input(format!("--steady {e}")))?;
        let rate = lagrange::assign::number(item, a.value, &lookup)
            .map_err(|e| Failure::input(format!("--steady {e}")))?;
        search.steady.push((a.name, rate));
    }
    for item in &options.range {
        let range = lagrange::parse_range(item, &lookup)
            .map_err(|e| Failure::input(format!("--range {e}")))?;
        search.ranges.push(range);
    }
    Ok(search)
}

fn run_sweep(
    path: &Path,
    analysis: &Analysis,
    search: &Search,
    sweep: &str,
    options: &EquilibriumOptions,
    json: bool,
) -> Result<Exit, Failure> {
    let range: Range = lagrange::parse_range(sweep, &analysis.lookup())
        .map_err(|e| Failure::input(format!("--sweep {e}")))?;
    let table = analysis
        .equilibrium_sweep(search, &range, options.steps)
        .map_err(|e| Failure::of(e, path).prefixed("--sweep"))?;
    if let Some(plot) = &options.plot {
        table
            .plot(plot)
            .map_err(|e| Failure::new(Exit::Output, e))?;
        eprintln!("wrote {}", plot.display());
    }
    let text = if json {
        super::eom::json(&table.to_json())
    } else {
        table.to_text()
    };
    println(&text)?;
    Ok(Exit::Success)
}
