//! `lagrange equilibria MODEL` and `lagrange linearize MODEL`: all equilibria with their
//! stability, the linearized dynamics about them, and parameter sweeps (bifurcation tables).

use std::path::Path;
use std::process::ExitCode;

use anyhow::{anyhow, bail};
use cas::Symbol;
use mechanics::equilibria::{find_equilibria, spin_rate, steady_equations, RestEquations, Values};
use mechanics::linearize::{linear_model, linearize_at, LinearModel};
use mechanics::System;
use report::equilibria::{LinearizedResult, SweepRow};

use crate::args::{EomFormat, EquilibriumOptions};

/// The default search range of a coordinate that is not an angle.
const DEFAULT_RANGE: (f64, f64) = (-10.0, 10.0);

/// Numeric values of the parameters and inputs (inputs without a value are held at 0).
fn model_values(system: &System) -> anyhow::Result<Values> {
    let mut values = Values::new();
    let entries = system
        .parameters()
        .iter()
        .map(|p| (p, false))
        .chain(system.inputs().iter().map(|p| (p, true)));
    for ((name, value), is_input) in entries {
        match value {
            Some(e) => {
                let env = |s: Symbol| values.get(s.name()).copied();
                if let Ok(v) = e.eval(&env) {
                    values.insert(name.clone(), v);
                }
            }
            None if is_input => {
                values.insert(name.clone(), 0.0);
            }
            None => {}
        }
    }
    Ok(values)
}

fn parse_number(text: &str, what: &str) -> anyhow::Result<f64> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| anyhow!("`{text}` in {what} is not a number"))?;
    if !v.is_finite() {
        bail!("`{text}` in {what} is not a finite number");
    }
    Ok(v)
}

/// `NAME=A..B` → (name, a, b).
fn parse_range(text: &str, what: &str) -> anyhow::Result<(String, f64, f64)> {
    let (name, range) = text
        .split_once('=')
        .ok_or_else(|| anyhow!("{what} `{text}` should look like NAME=A..B"))?;
    let (a, b) = range
        .split_once("..")
        .ok_or_else(|| anyhow!("{what} `{text}` should look like NAME=A..B"))?;
    let (a, b) = (parse_number(a, what)?, parse_number(b, what)?);
    if a > b {
        bail!("{what} `{text}`: the lower end is above the upper end");
    }
    Ok((name.trim().to_string(), a, b))
}

/// Everything that does not change along a sweep.
struct Prepared {
    rest: RestEquations,
    model: LinearModel,
    inputs: Vec<String>,
    bounds: Vec<(f64, f64)>,
}

fn analyse(
    prepared: &Prepared,
    values: &Values,
) -> anyhow::Result<(mechanics::equilibria::EquilibriumSet, Vec<LinearizedResult>)> {
    let set = find_equilibria(&prepared.rest, values, &prepared.bounds)?;
    let lin = set
        .equilibria
        .iter()
        .map(|e| {
            linearize_at(
                &prepared.model,
                &prepared.rest,
                &e.values,
                e.exact.as_deref(),
                values,
            )
        })
        .collect();
    Ok((set, lin))
}

/// Runs `lagrange linearize`.
pub fn run_linearize(
    path: &Path,
    options: &EquilibriumOptions,
    only: Option<usize>,
    initial: &[String],
) -> anyhow::Result<ExitCode> {
    run(path, options, only, true, initial)
}

/// `NAME=VALUE` / `NAME'=VALUE` → initial deviations and rates by coordinate.
fn parse_initial(
    initial: &[String],
    coordinates: &[String],
) -> anyhow::Result<Option<(Vec<f64>, Vec<f64>)>> {
    if initial.is_empty() {
        return Ok(None);
    }
    let n = coordinates.len();
    let (mut dq, mut dv) = (vec![0.0; n], vec![0.0; n]);
    for item in initial {
        let (name, value) = item.split_once('=').ok_or_else(|| {
            anyhow!("--initial `{item}` should look like NAME=VALUE or NAME'=VALUE")
        })?;
        let name = name.trim();
        let (base, rate) = match name.strip_suffix('\'') {
            Some(base) => (base, true),
            None => (name, false),
        };
        let i = coordinates
            .iter()
            .position(|q| q == base)
            .ok_or_else(|| anyhow!("--initial `{item}`: `{base}` is not a coordinate"))?;
        let v = parse_number(value, "--initial")?;
        if rate {
            dv[i] = v;
        } else {
            dq[i] = v;
        }
    }
    Ok(Some((dq, dv)))
}

/// Runs `lagrange equilibria` (`linearize = false`) or `lagrange linearize`.
pub fn run(
    path: &Path,
    options: &EquilibriumOptions,
    only: Option<usize>,
    linearize: bool,
    initial: &[String],
) -> anyhow::Result<ExitCode> {
    let (model, _source) = match super::check::load(path)? {
        Ok(loaded) => loaded,
        Err(code) => return Ok(code),
    };
    let (system, equations) = match super::check::derive(path, &model)? {
        Ok(derived) => derived,
        Err(code) => return Ok(code),
    };
    let mut steady = Vec::new();
    let mut rates = Vec::new();
    for s in &options.steady {
        let (name, value) = s
            .split_once('=')
            .ok_or_else(|| anyhow!("--steady `{s}` should look like NAME=RATE"))?;
        steady.push(name.trim().to_string());
        rates.push((spin_rate(name.trim()), parse_number(value, "--steady")?));
    }
    let rest = match steady_equations(&equations, &steady) {
        Ok(r) => r,
        Err(error) => {
            eprintln!("error: {error}");
            return Ok(ExitCode::from(1));
        }
    };
    let rate_names: Vec<String> = rates
        .iter()
        .filter_map(|(r, _)| r.as_symbol().map(|s| s.name().to_string()))
        .collect();
    let known: Vec<&String> = system
        .parameters()
        .iter()
        .chain(system.inputs())
        .map(|(n, _)| n)
        .chain(&rate_names)
        .collect();
    let mut values = model_values(&system)?;
    for (name, (_, v)) in rate_names.iter().zip(&rates) {
        values.insert(name.clone(), *v);
    }
    for s in &options.set {
        let (name, value) = s
            .split_once('=')
            .ok_or_else(|| anyhow!("--set `{s}` should look like NAME=VALUE"))?;
        let name = name.trim();
        if !known.iter().any(|k| k.as_str() == name) {
            bail!("--set `{s}`: `{name}` is not a parameter or input of the model");
        }
        values.insert(name.to_string(), parse_number(value, "--set")?);
    }
    let mut bounds = vec![DEFAULT_RANGE; rest.coordinates.len()];
    for r in &options.range {
        let (name, a, b) = parse_range(r, "--range")?;
        let i = rest
            .coordinates
            .iter()
            .position(|q| *q == name)
            .ok_or_else(|| anyhow!("--range `{r}`: `{name}` is not a coordinate"))?;
        bounds[i] = (a, b);
    }
    let inputs: Vec<String> = system.inputs().iter().map(|(n, _)| n.clone()).collect();
    let model = linear_model(&equations, &rest, &inputs);
    let prepared = Prepared {
        rest,
        model,
        inputs,
        bounds,
    };
    let json = options.format == EomFormat::Json;

    if let Some(sweep) = &options.sweep {
        let (name, a, b) = parse_range(sweep, "--sweep")?;
        if !known.iter().any(|k| **k == name) {
            bail!("--sweep `{sweep}`: `{name}` is not a parameter or input of the model");
        }
        let steps = options.steps.clamp(1, 10_000);
        let mut rows = Vec::new();
        for k in 0..=steps {
            let value = a + (b - a) * k as f64 / steps as f64;
            let mut v = values.clone();
            v.insert(name.clone(), value);
            let (set, lin) = analyse(&prepared, &v)?;
            rows.push(SweepRow { value, set, lin });
        }
        if let Some(path) = &options.plot {
            let points: Vec<report::BifurcationPoint> = rows
                .iter()
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
            match report::plot_bifurcation(path, &name, &prepared.rest.coordinates, &points) {
                Ok(()) => eprintln!("wrote {}", path.display()),
                Err(error) => {
                    eprintln!("error: {error}");
                    return Ok(ExitCode::from(1));
                }
            }
        }
        if json {
            let value = report::equilibria::sweep_json(&prepared.rest, &name, &rows);
            println!("{}", serde_json::to_string_pretty(&value)?);
        } else {
            print!(
                "{}",
                report::equilibria::sweep_text(&prepared.rest, &name, &rows)
            );
        }
        return Ok(ExitCode::SUCCESS);
    }

    if options.plot.is_some() {
        bail!("--plot draws the bifurcation diagram of a --sweep; add --sweep P=a..b");
    }
    let initial = parse_initial(initial, &prepared.rest.coordinates)?;
    let (set, lin) = analyse(&prepared, &values)?;
    if let Some(i) = only {
        if i >= set.equilibria.len() {
            bail!(
                "--equilibrium {i}: there are {} equilibria (indices from 0)",
                set.equilibria.len()
            );
        }
    }
    let r = &prepared.rest;
    let text = match (linearize, json) {
        (false, true) => {
            serde_json::to_string_pretty(&report::equilibria::equilibria_json(r, &set, &lin))?
        }
        (false, false) => report::equilibria::equilibria_text(r, &set, &lin),
        (true, true) => {
            let mut value =
                report::equilibria::linearized_json(r, &set, &lin, &prepared.inputs, only);
            if let (Some((dq, dv)), Some(list)) = (&initial, value["linearized"].as_array_mut()) {
                for entry in list {
                    let i = entry["equilibrium"].as_u64().unwrap_or(0) as usize;
                    if let Some(Ok(l)) = lin.get(i) {
                        entry["free_response"] =
                            report::equilibria::free_response_json(r, l, dq, dv);
                    }
                }
            }
            serde_json::to_string_pretty(&value)?
        }
        (true, false) => {
            let mut text =
                report::equilibria::linearized_text(r, &set, &lin, &prepared.inputs, only);
            if let Some((dq, dv)) = &initial {
                for (i, l) in lin.iter().enumerate() {
                    if only.is_some_and(|k| k != i) {
                        continue;
                    }
                    if let Ok(l) = l {
                        text.push_str(&format!("\nfree response about #{i}:\n"));
                        text.push_str(&report::equilibria::free_response_text(r, l, dq, dv));
                    }
                }
            }
            text
        }
    };
    println!("{}", text.trim_end());
    Ok(ExitCode::SUCCESS)
}

/// The equilibria and linearizations `lagrange solve` reports, with the model's values; the
/// error says why there are none (the rest of the solution stands).
pub fn analysis(
    system: &System,
    equations: &mechanics::Equations,
) -> Result<
    (
        RestEquations,
        mechanics::equilibria::EquilibriumSet,
        Vec<LinearizedResult>,
    ),
    String,
> {
    let rest = steady_equations(equations, &[]).map_err(|e| e.to_string())?;
    let values = model_values(system).map_err(|e| format!("{e:#}"))?;
    let inputs: Vec<String> = system.inputs().iter().map(|(n, _)| n.clone()).collect();
    let model = linear_model(equations, &rest, &inputs);
    let prepared = Prepared {
        bounds: vec![DEFAULT_RANGE; rest.coordinates.len()],
        rest,
        model,
        inputs,
    };
    let (set, lin) = analyse(&prepared, &values).map_err(|e| format!("{e:#}"))?;
    Ok((prepared.rest, set, lin))
}
