//! `lagrange equilibria MODEL` and `lagrange linearize MODEL`: all equilibria with their
//! stability, the linearized dynamics about them, and parameter sweeps (bifurcation tables).

use lagrange::report;
use std::path::Path;

use lagrange::{Analysis, Equilibria, Range, Search};
use report::equilibria as print;

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
        None if json => super::eom::json(&print::equilibria_json(
            &found.rest,
            &found.set,
            &found.linearized,
        )),
        None => print::equilibria_text(&found.rest, &found.set, &found.linearized),
        Some(initial) => {
            let deviations = deviations(&analysis, initial, &found.rest.coordinates)?;
            linearized(&found, only, deviations.as_ref(), json)
        }
    };
    println(&text)?;
    Ok(Exit::Success)
}

/// `--steady` and `--range` as a search.
fn search(analysis: &Analysis, options: &EquilibriumOptions) -> Result<Search, Failure> {
    let lookup = super::lookup(analysis);
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
    let range: Range = lagrange::parse_range(sweep, &super::lookup(analysis))
        .map_err(|e| Failure::input(format!("--sweep {e}")))?;
    let (rest, steps) = analysis
        .equilibrium_sweep(search, &range, options.steps)
        .map_err(|e| Failure::of(e, path).prefixed("--sweep"))?;
    let rows: Vec<print::SweepRow> = steps
        .into_iter()
        .map(|s| print::SweepRow {
            value: s.value,
            set: s.set,
            lin: s.linearized,
        })
        .collect();
    if let Some(plot) = &options.plot {
        let points: Vec<report::BifurcationPoint> =
            rows.iter()
                .flat_map(|row| {
                    row.set
                        .equilibria
                        .iter()
                        .zip(&row.lin)
                        .flat_map(move |(e, l)| {
                            let stable = l.as_ref().ok().and_then(|l| l.stable);
                            e.values.iter().enumerate().map(move |(k, v)| {
                                report::BifurcationPoint {
                                    parameter: row.value,
                                    coordinate: k,
                                    value: *v,
                                    stable,
                                }
                            })
                        })
                })
                .collect();
        report::plot_bifurcation(plot, &range.name, &rest.coordinates, &points)
            .map_err(|e| Failure::new(Exit::Output, e))?;
        eprintln!("wrote {}", plot.display());
    }
    let text = if json {
        super::eom::json(&print::sweep_json(&rest, &range.name, &rows))
    } else {
        print::sweep_text(&rest, &range.name, &rows)
    };
    println(&text)?;
    Ok(Exit::Success)
}

/// Initial deviations and their rates, by coordinate.
type Deviations = (Vec<f64>, Vec<f64>);

/// `--initial NAME=VALUE` / `NAME'=VALUE` → deviations and rates by coordinate.
fn deviations(
    analysis: &Analysis,
    initial: &[String],
    coordinates: &[String],
) -> Result<Option<Deviations>, Failure> {
    if initial.is_empty() {
        return Ok(None);
    }
    let lookup = super::lookup(analysis);
    let n = coordinates.len();
    let (mut dq, mut dv) = (vec![0.0; n], vec![0.0; n]);
    for item in initial {
        let bad = |e: &dyn std::fmt::Display| Failure::input(format!("--initial {e}"));
        let a = lagrange::parse_assignment(item).map_err(|e| bad(&e))?;
        let value = lagrange::assign::number(item, a.value, &lookup).map_err(|e| bad(&e))?;
        let (base, rate) = match a.name.strip_suffix('\'').or(a.name.strip_suffix("_d")) {
            Some(base) => (base, true),
            None => (a.name.as_str(), false),
        };
        let i = coordinates.iter().position(|q| q == base).ok_or_else(|| {
            bad(&format!(
                "`{item}`: `{base}` is not a coordinate (it has: {})",
                coordinates.join(", ")
            ))
        })?;
        if rate {
            dv[i] = value;
        } else {
            dq[i] = value;
        }
    }
    Ok(Some((dq, dv)))
}

/// The linearize output, with the free response from `deviations` when given.
fn linearized(
    found: &Equilibria,
    only: Option<usize>,
    deviations: Option<&Deviations>,
    json: bool,
) -> String {
    let (r, set, lin) = (&found.rest, &found.set, &found.linearized);
    if json {
        let mut value = print::linearized_json(r, set, lin, &found.inputs, only);
        if let (Some((dq, dv)), Some(list)) = (deviations, value["linearized"].as_array_mut()) {
            for entry in list {
                let i = entry["equilibrium"].as_u64().unwrap_or(0) as usize;
                if let Some(Ok(l)) = lin.get(i) {
                    entry["free_response"] = print::free_response_json(r, l, dq, dv);
                }
            }
        }
        return super::eom::json(&value);
    }
    let mut text = print::linearized_text(r, set, lin, &found.inputs, only);
    if let Some((dq, dv)) = deviations {
        for (i, l) in lin.iter().enumerate() {
            if only.is_some_and(|k| k != i) {
                continue;
            }
            if let Ok(l) = l {
                text.push_str(&format!("\nfree response about #{i}:\n"));
                text.push_str(&print::free_response_text(r, l, dq, dv));
            }
        }
    }
    text
}
