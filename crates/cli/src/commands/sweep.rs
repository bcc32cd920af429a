//! `lagrange simulate --sweep NAME=A..B [--steps N | --samples N]`: many simulations of one
//! model — a parameter sweep on a grid, or Monte-Carlo runs with values drawn uniformly from
//! ranges — run in parallel on all cores (rayon), with a progress bar, one CSV row per run.
//! Each run is prepared with the same options as a single `lagrange simulate`, lost contacts
//! included (`options_with_contacts`).

use std::io::Write;
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use anyhow::{anyhow, bail, Context};
use indicatif::{ProgressBar, ProgressStyle};
use numeric::StopReason;
use rayon::prelude::*;
use simulation::{Simulation, SimulationOptions};

use super::simulate::{stop_cause, SimulateArgs, StopCause};

/// One varied name and its range.
struct Range {
    name: String,
    low: f64,
    high: f64,
}

fn parse_range(text: &str) -> anyhow::Result<Range> {
    let bad = || anyhow!("--sweep `{text}` should look like NAME=A..B");
    let (name, range) = text.split_once('=').ok_or_else(bad)?;
    let (a, b) = range.split_once("..").ok_or_else(bad)?;
    let number = |s: &str| -> anyhow::Result<f64> {
        let v: f64 = s
            .trim()
            .parse()
            .map_err(|_| anyhow!("--sweep `{text}`: `{s}` is not a number"))?;
        if v.is_finite() {
            Ok(v)
        } else {
            bail!("--sweep `{text}`: `{s}` is not finite")
        }
    };
    let (low, high) = (number(a)?, number(b)?);
    if low > high {
        bail!("--sweep `{text}`: the lower end is above the upper end");
    }
    Ok(Range {
        name: name.trim().to_string(),
        low,
        high,
    })
}

/// A small deterministic generator (xorshift64*), so a seed gives the same runs everywhere.
fn uniform(state: &mut u64) -> f64 {
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    let x = state.wrapping_mul(0x2545_f491_4f6c_dd1d);
    (x >> 11) as f64 / (1u64 << 53) as f64
}

/// The values of every run: a grid for one range, uniform draws for `--samples`.
fn plan(args: &SimulateArgs, ranges: &[Range]) -> anyhow::Result<Vec<Vec<f64>>> {
    match args.samples {
        Some(0) => bail!("--samples must be at least 1"),
        Some(n) => {
            let mut state = args.seed.max(1);
            Ok((0..n)
                .map(|_| {
                    ranges
                        .iter()
                        .map(|r| r.low + (r.high - r.low) * uniform(&mut state))
                        .collect()
                })
                .collect())
        }
        None => {
            let [r] = ranges else {
                bail!(
                    "several --sweep ranges need --samples N (Monte-Carlo); a grid sweeps one name"
                );
            };
            let steps = args.steps.max(1);
            Ok((0..=steps)
                .map(|k| vec![r.low + (r.high - r.low) * k as f64 / steps as f64])
                .collect())
        }
    }
}

/// What one run gives: its last row and how it ended.
struct RunResult {
    last: Vec<f64>,
    steps: u64,
    stop: String,
}

fn one_run(
    model: &model::Model,
    args: &SimulateArgs,
    options: &SimulationOptions,
    contacts: &[String],
    ranges: &[Range],
    values: &[f64],
) -> Result<RunResult, String> {
    let overrides: Vec<(String, f64)> = ranges
        .iter()
        .zip(values)
        .map(|(r, v)| (r.name.clone(), *v))
        .collect();
    let model = model
        .with_overrides(&overrides)
        .map_err(|e| e.to_string())?;
    let mut simulation = Simulation::prepare(&model, options).map_err(|e| e.to_string())?;
    let mut last = Vec::new();
    let outcome = simulation.run(&mut |row| {
        last.clear();
        last.extend_from_slice(row);
    });
    let stop = match outcome.stop {
        StopReason::Finished => "finished".to_string(),
        StopReason::Event { index, .. } => match stop_cause(args, contacts, index) {
            StopCause::StopWhen => "event".to_string(),
            StopCause::ContactLost(name) => format!("contact lost: {name}"),
        },
        StopReason::Failed(failure) => format!("failed {failure}"),
        _ => "stopped".to_string(),
    };
    Ok(RunResult {
        last,
        steps: outcome.stats.steps,
        stop,
    })
}

/// Runs the sweep and writes its CSV. `options` and `contacts` come from
/// `options_with_contacts`, as for a single run.
pub fn run(
    args: &SimulateArgs,
    model: &model::Model,
    options: &SimulationOptions,
    contacts: &[String],
) -> anyhow::Result<ExitCode> {
    if args.plot.is_some() {
        bail!("--plot draws one run; leave it out of a --sweep");
    }
    if !args.record_when.is_empty() || args.events.is_some() || args.summary.is_some() {
        bail!(
            "--record-when, --events and --summary describe one run; leave them out of a --sweep"
        );
    }
    let ranges: Vec<Range> = args
        .sweep
        .iter()
        .map(|s| parse_range(s))
        .collect::<anyhow::Result<_>>()?;
    let runs = plan(args, &ranges)?;
    // Check the names and the model once, with the first run's values, before going parallel.
    let first: Vec<(String, f64)> = ranges
        .iter()
        .zip(&runs[0])
        .map(|(r, v)| (r.name.clone(), *v))
        .collect();
    let probe = match model.with_overrides(&first) {
        Ok(m) => m,
        Err(error) => {
            eprintln!("error: --sweep: {error}");
            return Ok(ExitCode::from(2));
        }
    };
    let columns = match Simulation::prepare(&probe, options) {
        Ok(s) => s.columns(),
        Err(error) => {
            eprintln!("error: {error}");
            return Ok(ExitCode::from(1));
        }
    };

    let bar = ProgressBar::new(runs.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} runs, {elapsed} (eta {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let failed = AtomicUsize::new(0);
    let started = Instant::now();
    let results: Vec<Result<RunResult, String>> = runs
        .par_iter()
        .map(|values| {
            let r = one_run(model, args, options, contacts, &ranges, values);
            if r.as_ref().map_or(true, |r| r.stop.starts_with("failed")) {
                failed.fetch_add(1, Ordering::Relaxed);
            }
            bar.inc(1);
            r
        })
        .collect();
    bar.finish_and_clear();

    let mut writer: Box<dyn Write> = match &args.out {
        Some(path) => Box::new(std::io::BufWriter::new(
            std::fs::File::create(path)
                .with_context(|| format!("cannot create `{}`", path.display()))?,
        )),
        None => Box::new(std::io::BufWriter::new(std::io::stdout().lock())),
    };
    let mut header: Vec<String> = vec!["run".into()];
    header.extend(ranges.iter().map(|r| r.name.clone()));
    header.extend(columns.iter().map(|c| format!("final_{c}")));
    header.extend(["steps".into(), "outcome".into()]);
    writeln!(writer, "{}", header.join(","))?;
    for (k, (values, result)) in runs.iter().zip(&results).enumerate() {
        let mut row: Vec<String> = vec![k.to_string()];
        row.extend(values.iter().map(|v| format!("{v:?}")));
        match result {
            Ok(r) => {
                row.extend(r.last.iter().map(|v| format!("{v:?}")));
                row.extend(std::iter::repeat_n(
                    String::new(),
                    columns.len().saturating_sub(r.last.len()),
                ));
                row.push(r.steps.to_string());
                row.push(format!("\"{}\"", r.stop.replace('"', "'")));
            }
            Err(e) => {
                row.extend(std::iter::repeat_n(String::new(), columns.len() + 1));
                row.push(format!("\"error: {}\"", e.replace('"', "'")));
            }
        }
        writeln!(writer, "{}", row.join(","))?;
    }
    writer.flush()?;
    let failed = failed.into_inner();
    eprintln!(
        "{} runs on {} threads in {:.2} s, {failed} failed",
        runs.len(),
        rayon::current_num_threads(),
        started.elapsed().as_secs_f64()
    );
    if let Some(path) = &args.out {
        eprintln!("wrote {}", path.display());
    }
    Ok(if failed > 0 {
        ExitCode::from(3)
    } else {
        ExitCode::SUCCESS
    })
}
