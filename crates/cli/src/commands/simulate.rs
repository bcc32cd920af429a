//! `lagrange simulate MODEL`: integrate the equations of motion, write the time history as
//! CSV, optionally plot it, and print a summary line (steps, rejected steps, evaluations, wall
//! time, final energy error). A run that fails part-way keeps and writes what it computed, then
//! says when and why it stopped and exits non-zero.

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
    if !args.sweep.is_empty() {
        return super::sweep::run(args, &model);
    }
    let mut options = options(args);
    // A contact or rope the model asks about stops the run where it would be lost: past that
    // point the equations describe a motion that cannot happen.
    let one_sided = if args.through_contact_loss {
        Vec::new()
    } else {
        match one_sided_reactions(&args.model, &model, &source) {
            Ok(list) => list,
            Err(code) => return Ok(code),
        }
    };
    options.stop_events = one_sided.iter().map(|(_, value)| *value).collect();
    let mut simulation = match Simulation::prepare(&model, &options) {
        Ok(s) => s,
        Err(error) => {
            eprintln!("error: {error}");
            return Ok(ExitCode::from(1));
        }
    };
    let mut writer: Box<dyn Write> = match &args.out {
        Some(path) => Box::new(std::io::BufWriter::new(
            std::fs::File::create(path)
                .with_context(|| format!("cannot create `{}`", path.display()))?,
        )),
        None => Box::new(std::io::BufWriter::new(std::io::stdout().lock())),
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
    let columns = simulation.columns();
    writeln!(writer, "{}", columns.join(","))?;
    let mut write_error = None;
    let mut last_row: Vec<f64> = Vec::new();
    let mut kept: Vec<Vec<f64>> = Vec::new();
    let keep = args.plot.is_some();
    let (t_start, t_end) = simulation.span();
    let mut progress: Option<ProgressBar> = None;
    let started = Instant::now();
    let outcome = simulation.run(&mut |row| {
        if write_error.is_none() {
            if let Err(e) = write_row(&mut writer, row) {
                write_error = Some(e);
            }
        }
        if keep {
            kept.push(row.to_vec());
        }
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
    });
    let elapsed = started.elapsed();
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }
    writer.flush()?;
    drop(writer);
    if let Some(error) = write_error {
        return Err(error).context("cannot write the CSV");
    }
    let energy_error = last_row.iter().rev().nth(1).copied().unwrap_or(f64::NAN);
    let (_, t_end) = simulation.span();
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
    if let Some(path) = &args.out {
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
            let first_contact = usize::from(args.stop_when.is_some());
            match index.checked_sub(first_contact).and_then(|k| one_sided.get(k)) {
                Some((name, _)) => eprintln!(
                    "stopped at t = {t}: the one-sided constraint `{name}` is lost there (its reaction changes sign); run with --through-contact-loss to go on regardless"
                ),
                None => eprintln!("stopped at t = {t}: --stop-when expression crossed zero"),
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
