//! `lagrange simulate MODEL`: integrate the equations of motion, write the time history as
//! CSV, optionally plot it, and print a summary line (steps, rejected steps, evaluations, wall
//! time, final energy error); optionally record zero crossings (`--record-when`, `--events`)
//! and write the summary as JSON (`--summary`). A run that fails part-way keeps and writes
//! what it computed, then says when and why it stopped and exits non-zero.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use numeric::StopReason;
use simulation::{MethodName, Simulation, SimulationOptions};

/// Flags of `lagrange simulate`.
#[derive(Args, Debug)]
pub struct SimulateArgs {
    /// The model file (`.lag`).
    pub model: PathBuf,
    /// End time (default: the model's `simulate to`).
    #[arg(long, allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    /// Start time (default: the model's `simulate from`, else 0).
    #[arg(long, allow_hyphen_values = true)]
    pub t_start: Option<f64>,
    /// Integration method (default: the model's, else dopri5).
    #[arg(long, value_enum)]
    pub method: Option<MethodArg>,
    /// Relative tolerance (default: the model's, else 1e-8).
    #[arg(long)]
    pub rtol: Option<f64>,
    /// Absolute tolerance (default: the model's, else 1e-10).
    #[arg(long)]
    pub atol: Option<f64>,
    /// Time between output rows (default: the model's `step`, else every accepted step).
    #[arg(long)]
    pub output_step: Option<f64>,
    /// Integration step: fixed for gauss, initial for dopri5 (default: chosen).
    #[arg(long)]
    pub step: Option<f64>,
    /// Override a parameter, an input, or an initial value for this run: `k=40`, `theta=0.3`,
    /// `theta_d=-1`; the value may be an expression of numbers and `pi` (`pi/4`). Repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Stop where this expression of `t`, the coordinates and their rates (`q_d`) crosses zero.
    #[arg(long, value_name = "EXPR", allow_hyphen_values = true)]
    pub stop_when: Option<String>,
    /// Record every crossing of zero of this expression (of `t`, the coordinates, their rates
    /// and the parameters) without stopping: direction, time and state. Repeatable.
    #[arg(long, value_name = "EXPR", allow_hyphen_values = true)]
    pub record_when: Vec<String>,
    /// Write the recorded crossings here as CSV: `event`, `direction`, `t`, the coordinates,
    /// their rates.
    #[arg(long, value_name = "FILE")]
    pub events: Option<PathBuf>,
    /// Write a JSON summary of the run here: settings, outcome, work, errors, crossings.
    #[arg(long, value_name = "FILE")]
    pub summary: Option<PathBuf>,
    /// Write the CSV here (default: standard output).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Plot the run (time histories, phase portraits, energy error) to this file: `.svg` or
    /// `.png`.
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Many runs instead of one: vary a parameter, input or initial value over a range,
    /// `--sweep k=10..40` (a grid of `--steps` + 1 values), or several of them with
    /// `--samples N` (N Monte-Carlo runs, each value uniform in its range). Runs go in
    /// parallel on all cores; the CSV has one row per run.
    #[arg(long, value_name = "NAME=A..B")]
    pub sweep: Vec<String>,
    /// Grid steps of a one-name `--sweep`.
    #[arg(long, default_value_t = 10)]
    pub steps: usize,
    /// Monte-Carlo: this many runs with values drawn uniformly from the `--sweep` ranges.
    #[arg(long)]
    pub samples: Option<usize>,
    /// Do not stop where a contact or rope the model asks about would be lost.
    #[arg(long)]
    pub through_contact_loss: bool,
    /// Seed of the Monte-Carlo draws (the same seed gives the same runs).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// The methods, for `--method`.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum MethodArg {
    /// Adaptive Dormand–Prince 5(4) with dense output.
    Dopri5,
    /// Gauss–Legendre order 6, fixed step, symplectic (conservative systems).
    Gauss,
    /// L-stable implicit SDIRK of order 2, adaptive (stiff systems).
    Sdirk,
}

/// The integration settings the flags ask for.
pub fn options(args: &SimulateArgs) -> SimulationOptions {
    SimulationOptions {
        method: args.method.map(|m| match m {
            MethodArg::Dopri5 => MethodName::Dopri5,
            MethodArg::Gauss => MethodName::Gauss,
            MethodArg::Sdirk => MethodName::Sdirk,
        }),
        t_start: args.t_start,
        t_end: args.t_end,
        rtol: args.rtol,
        atol: args.atol,
        output_step: args.output_step,
        step: args.step,
        stop_when: args.stop_when.clone(),
        stop_events: Vec::new(),
        record_when: args.record_when.clone(),
    }
}

/// The settings of a run as the flags and the model ask for them, with the one-sided
/// constraints the model asks about as stop events (unless `--through-contact-loss`): past
/// the point where one is lost the equations describe a motion that cannot happen. Shared by
/// single runs and sweeps. Returns the options and the names of those constraints.
pub fn options_with_contacts(
    args: &SimulateArgs,
    model: &model::Model,
    source: &str,
) -> Result<(SimulationOptions, Vec<String>), ExitCode> {
    let mut options = options(args);
    let one_sided = if args.through_contact_loss {
        Vec::new()
    } else {
        one_sided_reactions(&args.model, model, source)?
    };
    options.stop_events = one_sided.iter().map(|(_, value)| *value).collect();
    Ok((
        options,
        one_sided.into_iter().map(|(name, _)| name).collect(),
    ))
}

/// What stopped a run at a stop event.
pub enum StopCause<'a> {
    /// The `--stop-when` expression crossed zero.
    StopWhen,
    /// The one-sided constraint of that name is lost.
    ContactLost(&'a str),
}

/// Which stop event `index` is: `--stop-when`'s comes first, then the contacts.
pub fn stop_cause<'a>(args: &SimulateArgs, contacts: &'a [String], index: usize) -> StopCause<'a> {
    let first_contact = usize::from(args.stop_when.is_some());
    match index
        .checked_sub(first_contact)
        .and_then(|k| contacts.get(k))
    {
        Some(name) => StopCause::ContactLost(name),
        None => StopCause::StopWhen,
    }
}

/// The one-sided reactions the model asks for (contacts push, ropes pull), as stop events:
/// `(name, value)` with `value ≥ 0` while the constraint holds.
fn one_sided_reactions(
    path: &Path,
    model: &model::Model,
    source: &str,
) -> Result<Vec<(String, cas::Expr)>, ExitCode> {
    if model.reactions().is_empty() && model.releases().is_empty() {
        return Ok(Vec::new());
    }
    let Ok(system) = model::lower(model) else {
        return Ok(Vec::new());
    };
    let Some(computed) = super::reactions::compute(path, model, source, &system, None)? else {
        return Ok(Vec::new());
    };
    Ok(computed
        .reactions
        .iter()
        .filter_map(|r| r.along.map(|(value, _)| (r.name.clone(), value)))
        .collect())
}

/// Runs `lagrange simulate`.
pub fn run(args: &SimulateArgs) -> anyhow::Result<ExitCode> {
    let (model, source) = match super::check::load_with_overrides(&args.model, &args.set)? {
        Ok(loaded) => loaded,
        Err(code) => return Ok(code),
    };
    let (options, contacts) = match options_with_contacts(args, &model, &source) {
        Ok(prepared) => prepared,
        Err(code) => return Ok(code),
    };
    if !args.sweep.is_empty() {
        return super::sweep::run(args, &model, &options, &contacts);
    }
    let mut simulation = match Simulation::prepare(&model, &options) {
        Ok(s) => s,
        Err(error) => {
            eprintln!("error: {error}");
            return Ok(ExitCode::from(1));
        }
    };
    if let Some(path) = &args.plot {
        // Refuse a bad plot name before the run rather than after it.
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !ext.eq_ignore_ascii_case("svg") && !ext.eq_ignore_ascii_case("png") {
            eprintln!(
                "error: cannot plot to `{}`: the file name must end in .svg or .png",
                display(path)
            );
            return Ok(ExitCode::from(2));
        }
    }
    // Every output file is created before the run, so a bad path fails before a long run.
    let mut writer: Box<dyn Write> = match &args.out {
        Some(path) => Box::new(create(path)?),
        None => Box::new(std::io::BufWriter::new(std::io::stdout().lock())),
    };
    let mut events_writer = args.events.as_deref().map(create).transpose()?;
    let summary_writer = args.summary.as_deref().map(create).transpose()?;
    let columns = simulation.columns();
    let n = (columns.len() - 3) / 2;
    writeln!(writer, "{}", columns.join(","))?;
    if let Some(w) = events_writer.as_mut() {
        writeln!(w, "event,direction,{}", columns[..=2 * n].join(","))?;
    }
    let mut write_error = None;
    let mut last_row: Vec<f64> = Vec::new();
    let mut kept: Vec<Vec<f64>> = Vec::new();
    let mut crossings: Vec<(usize, bool, Vec<f64>)> = Vec::new();
    let mut row_count = 0u64;
    let mut max_drift = 0.0f64;
    let keep = args.plot.is_some();
    let (t_start, t_end) = simulation.span();
    let mut progress: Option<ProgressBar> = None;
    let started = Instant::now();
    let outcome = simulation.run_recording(
        &mut |row| {
            if write_error.is_none() {
                if let Err(e) = write_row(&mut writer, row) {
                    write_error = Some(e);
                }
            }
            if keep {
                kept.push(row.to_vec());
            }
            row_count += 1;
            // NaN (drift unknown) stays NaN: `max` would drop it.
            let drift = row[row.len() - 1];
            max_drift = if drift.is_nan() || max_drift.is_nan() {
                f64::NAN
            } else {
                max_drift.max(drift)
            };
            last_row.clear();
            last_row.extend_from_slice(row);
            // A progress bar only for runs long enough to need one; indicatif hides it when
            // stderr is not a terminal.
            if progress.is_none() && started.elapsed().as_secs_f64() > 0.5 {
                progress = Some(progress_bar());
            }
            if let Some(bar) = &progress {
                let fraction = ((row[0] - t_start) / (t_end - t_start)).clamp(0.0, 1.0);
                bar.set_position((fraction * 1000.0) as u64);
            }
        },
        &mut |crossing| {
            crossings.push((
                crossing.event,
                crossing.rising,
                crossing.row[..=2 * n].to_vec(),
            ));
        },
    );
    let elapsed = started.elapsed();
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }
    writer.flush()?;
    drop(writer);
    if let Some(error) = write_error {
        return Err(error).context("cannot write the CSV");
    }
    if let Some(mut w) = events_writer {
        for (event, rising, row) in &crossings {
            write!(
                w,
                "{},{},",
                csv_text(&args.record_when[*event]),
                direction(*rising)
            )?;
            write_row(&mut w, row)?;
        }
        w.flush().context("cannot write the events")?;
    }
    let energy_error = last_row.iter().rev().nth(1).copied().unwrap_or(f64::NAN);
    let stats = outcome.stats;
    let summary = format!(
        "{method}: t = {t:.6} of {t_end}, {steps} steps ({rejected} rejected), {evals} evaluations, {wall}, final energy error {energy_error:.3e}",
        method = simulation.method(),
        t = outcome.t,
        steps = stats.steps,
        rejected = stats.rejected,
        evals = stats.evaluations,
        wall = format_duration(elapsed.as_secs_f64()),
    );
    eprintln!("{summary}");
    if !args.record_when.is_empty() {
        eprintln!("{}", crossings_line(&args.record_when, &crossings));
    }
    let outcome_json = outcome_json(args, &contacts, &outcome);
    if let Some(mut w) = summary_writer {
        let integrator = simulation.integrator_options();
        let summary = serde_json::json!({
            "schema": 1,
            "model": display(&args.model),
            "method": simulation.method().to_string(),
            "rtol": integrator.rtol,
            "atol": integrator.atol,
            "step": integrator.step,
            "output_step": integrator.output_step,
            "t_start": t_start,
            "t_end": t_end,
            "t_reached": outcome.t,
            "outcome": outcome_json,
            "steps": stats.steps,
            "rejected_steps": stats.rejected,
            "rhs_evaluations": stats.evaluations,
            "wall_time_s": elapsed.as_secs_f64(),
            "rows": row_count,
            "final_energy_error": energy_error,
            "max_constraint_drift": max_drift,
            "events": crossings
                .iter()
                .map(|(event, rising, row)| {
                    let state: serde_json::Map<String, serde_json::Value> = columns[1..=2 * n]
                        .iter()
                        .zip(&row[1..])
                        .map(|(name, value)| (name.clone(), serde_json::json!(value)))
                        .collect();
                    serde_json::json!({
                        "event": args.record_when[*event],
                        "direction": direction(*rising),
                        "t": row[0],
                        "state": state,
                    })
                })
                .collect::<Vec<_>>(),
        });
        serde_json::to_writer_pretty(&mut w, &summary)?;
        writeln!(w)?;
        w.flush().context("cannot write the summary")?;
    }
    for path in [&args.out, &args.events, &args.summary]
        .into_iter()
        .flatten()
    {
        eprintln!("wrote {}", display(path));
    }
    if let Some(path) = &args.plot {
        let title = format!(
            "{} — {}",
            args.model
                .file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned()),
            simulation.method()
        );
        match report::plot_run(path, &title, &columns, &kept) {
            Ok(()) => eprintln!("wrote {}", display(path)),
            Err(error) => {
                eprintln!("error: {error}");
                return Ok(ExitCode::from(1));
            }
        }
    }
    match outcome.stop {
        StopReason::Finished => Ok(ExitCode::SUCCESS),
        StopReason::Event { t, index } => {
            match stop_cause(args, &contacts, index) {
                StopCause::ContactLost(name) => eprintln!(
                    "stopped at t = {t}: the one-sided constraint `{name}` is lost there (its reaction changes sign); run with --through-contact-loss to go on regardless"
                ),
                StopCause::StopWhen => {
                    eprintln!("stopped at t = {t}: --stop-when expression crossed zero");
                }
            }
            Ok(ExitCode::SUCCESS)
        }
        StopReason::Failed(failure) => {
            eprintln!("error: the simulation stopped {failure}; the rows computed up to then were written");
            Ok(ExitCode::from(3))
        }
        _ => Ok(ExitCode::from(3)),
    }
}

/// How a run ended, for `--summary`: `kind` is `finished`, `event` (`--stop-when`),
/// `contact_lost` (with `constraint`) or `failed` (with `reason`).
fn outcome_json(
    args: &SimulateArgs,
    contacts: &[String],
    outcome: &numeric::Outcome,
) -> serde_json::Value {
    match outcome.stop {
        StopReason::Event { t, index } => match stop_cause(args, contacts, index) {
            StopCause::StopWhen => serde_json::json!({
                "kind": "event", "t": t, "event": args.stop_when,
            }),
            StopCause::ContactLost(name) => serde_json::json!({
                "kind": "contact_lost", "t": t, "constraint": name,
            }),
        },
        StopReason::Failed(failure) => {
            // The failure reads "at t = …: why"; the time is a field of its own.
            let text = failure.to_string();
            let reason = text.split_once(": ").map_or(text.as_str(), |(_, r)| r);
            serde_json::json!({
                "kind": "failed", "t": failure_time(&failure).unwrap_or(outcome.t), "reason": reason,
            })
        }
        _ => serde_json::json!({ "kind": "finished", "t": outcome.t }),
    }
}

fn failure_time(failure: &numeric::Failure) -> Option<f64> {
    match *failure {
        numeric::Failure::Rhs { t, .. }
        | numeric::Failure::StepUnderflow { t, .. }
        | numeric::Failure::NotConverged { t, .. }
        | numeric::Failure::TooManySteps { t, .. } => Some(t),
        _ => None,
    }
}

/// The stderr line about recorded crossings: how many, and the first few.
fn crossings_line(expressions: &[String], crossings: &[(usize, bool, Vec<f64>)]) -> String {
    const SHOWN: usize = 4;
    let mut line = format!(
        "recorded {} crossing{}",
        crossings.len(),
        if crossings.len() == 1 { "" } else { "s" }
    );
    for (k, (event, rising, row)) in crossings.iter().take(SHOWN).enumerate() {
        line.push_str(if k == 0 { ": " } else { ", " });
        line.push_str(&format!(
            "`{}` {} at t = {:.6}",
            expressions[*event],
            direction(*rising),
            row[0]
        ));
    }
    if crossings.len() > SHOWN {
        line.push_str(&format!(", … ({} more)", crossings.len() - SHOWN));
    }
    line
}

fn direction(rising: bool) -> &'static str {
    if rising {
        "rising"
    } else {
        "falling"
    }
}

/// A CSV field: quoted (with quotes doubled) when it holds a comma, a quote or a line break.
fn csv_text(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}

fn create(path: &Path) -> anyhow::Result<std::io::BufWriter<std::fs::File>> {
    Ok(std::io::BufWriter::new(
        std::fs::File::create(path)
            .with_context(|| format!("cannot create `{}`", path.display()))?,
    ))
}

fn progress_bar() -> ProgressBar {
    let bar = ProgressBar::new(1000);
    if let Ok(style) =
        ProgressStyle::with_template("simulating {bar:40} {percent:>3}% ({elapsed}, eta {eta})")
    {
        bar.set_style(style);
    }
    bar
}

fn write_row(writer: &mut dyn Write, row: &[f64]) -> std::io::Result<()> {
    for (k, value) in row.iter().enumerate() {
        if k > 0 {
            writer.write_all(b",")?;
        }
        // `{:?}` is the shortest text that reads back to the same f64.
        write!(writer, "{value:?}")?;
    }
    writer.write_all(b"\n")
}

fn format_duration(seconds: f64) -> String {
    if seconds < 1e-3 {
        format!("{:.1} µs", seconds * 1e6)
    } else if seconds < 1.0 {
        format!("{:.2} ms", seconds * 1e3)
    } else {
        format!("{seconds:.2} s")
    }
}

fn display(path: &Path) -> String {
    path.display().to_string()
}
