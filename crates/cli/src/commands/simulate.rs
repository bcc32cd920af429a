//! `lagrange simulate MODEL`: integrate the equations of motion, write the time history as
//! CSV, optionally plot it, and print a summary line; optionally record zero crossings
//! (`--record-when`, `--events`) and write the summary as JSON (`--summary`). A run that fails
//! part-way keeps and writes what it computed, then says when and why it stopped. With
//! `--sweep`, many runs on all cores, one CSV row each, from one derivation.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use lagrange::{Analysis, Ending, Error, MethodName, Remedy, RunFiles, SimulationOptions};

use crate::exit::{check_output, Exit, Failure};

/// Flags of `lagrange simulate`.
#[derive(Args, Debug)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub input: crate::args::ModelInput,
    /// End time (default: the model's `simulate to`).
    #[arg(long, allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    /// Start time (default: the model's `simulate from`, else 0).
    #[arg(long, allow_hyphen_values = true)]
    pub t_start: Option<f64>,
    /// Integration method (default: the model's, else dopri5 at rtol ≥ 1e-6 and dop853 below):
    /// dopri5 (adaptive Dormand–Prince 5(4)), dop853 (adaptive Dormand–Prince 8(5,3)), gauss
    /// (Gauss–Legendre order 6, fixed step, symplectic), sdirk (L-stable implicit SDIRK of
    /// order 2, for stiff systems).
    #[arg(long, value_parser = method)]
    pub method: Option<MethodName>,
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
    /// Stop (exit 3, the rows so far written) after this many integration steps
    /// (default: 10⁶).
    #[arg(long, value_name = "N")]
    pub max_steps: Option<u64>,
    /// Stop (exit 3, the rows so far written) when one more output row than this is due
    /// (default: 10⁶); a span that asks for more rows every output step is refused.
    #[arg(long, value_name = "N")]
    pub max_rows: Option<u64>,
    /// Stop (exit 3, the rows so far written) before the CSV grows past this many bytes
    /// (default: 256 MiB).
    #[arg(long, value_name = "N")]
    pub max_bytes: Option<u64>,
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

/// `--method NAME`, by the names the model's `simulate` statement takes too.
fn method(name: &str) -> Result<MethodName, String> {
    MethodName::parse(name)
        .ok_or_else(|| format!("unknown method `{name}` (dopri5, dop853, gauss, sdirk)"))
}

/// The run options the flags ask for.
fn options(args: &SimulateArgs) -> SimulationOptions {
    SimulationOptions {
        method: args.method,
        t_start: args.t_start,
        t_end: args.t_end,
        rtol: args.rtol,
        atol: args.atol,
        output_step: args.output_step,
        step: args.step,
        stop_when: args.stop_when.clone(),
        record_when: args.record_when.clone(),
        through_contact_loss: args.through_contact_loss,
        max_steps: args.max_steps,
        max_rows: args.max_rows,
    }
}

/// Runs `lagrange simulate`.
pub fn run(args: &SimulateArgs) -> Result<Exit, Failure> {
    let analysis = super::load(&args.input.model, &args.input.set)?;
    let files = RunFiles {
        model: args.input.model.clone(),
        csv: args.out.clone(),
        events: args.events.clone(),
        summary: args.summary.clone(),
        plot: args.plot.clone(),
        max_bytes: args.max_bytes,
    };
    for file in files.outputs() {
        check_output(file, &args.input.model)?;
    }
    let options = options(args);
    if !args.sweep.is_empty() {
        return sweep(args, &analysis, &options, &files);
    }
    let prepared = analysis
        .prepare_run(&options, files)
        .map_err(|e| failure(e, args))?;
    if let Some(warning) = prepared.warning() {
        eprintln!("warning: {warning}");
    }
    let started = Instant::now();
    let mut progress: Option<ProgressBar> = None;
    let written = prepared
        .run(&mut std::io::stdout().lock(), &mut |done| {
            // A bar only for runs long enough to need one (hidden when stderr is no terminal).
            if progress.is_none() && started.elapsed().as_secs_f64() > 0.5 {
                progress = Some(bar(
                    "simulating {bar:40} {percent:>3}% ({elapsed}, eta {eta})",
                ));
            }
            if let Some(bar) = &progress {
                bar.set_position((done * 1000.0) as u64);
            }
        })
        .map_err(|e| failure(e, args))?;
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }
    eprintln!("{}", written.summary_line);
    if let Some(line) = &written.crossings_line {
        eprintln!("{line}");
    }
    for path in &written.written {
        eprintln!("wrote {}", path.display());
    }
    Ok(exit_of(
        &written.streamed.ending,
        written.streamed.outcome.t,
    ))
}

/// The exit code of a run's ending, said on stderr (with the flag that helps) when it stopped
/// early.
fn exit_of(ending: &Ending, t: f64) -> Exit {
    let Some(sentence) = ending.sentence(t) else {
        return Exit::Success;
    };
    let hint = ending.remedy().map(|remedy| match remedy {
        Remedy::ImplicitMethod => "stiff: use --method sdirk",
        Remedy::ImplicitMethodOrSmallerStep => {
            "if stiff, use --method sdirk; else give a smaller --step"
        }
        Remedy::MoreSteps => "raise the limit with --max-steps N",
        Remedy::MoreRows => {
            "raise the limit with --max-rows N, or write fewer rows with --output-step"
        }
        Remedy::MoreBytes => {
            "raise the limit with --max-bytes N, or write fewer rows with --output-step"
        }
        _ => "run with --through-contact-loss to go on regardless",
    });
    if !ending.stopped_short() {
        eprintln!(
            "{sentence}{}",
            hint.map(|h| format!("; {h}")).unwrap_or_default()
        );
        return Exit::Success;
    }
    eprintln!("error: {sentence}; the rows computed up to then were written");
    if let Some(hint) = hint {
        eprintln!("hint: {hint}");
    }
    Exit::RunFailed
}

/// A library error, with the flag named where it comes from one.
fn failure(error: Error, args: &SimulateArgs) -> Failure {
    use lagrange::simulation::SimulationError as S;
    match &error {
        Error::Simulation(S::StopCondition { reason, .. }) => {
            Failure::input(format!("--stop-when: {reason}"))
        }
        Error::Simulation(S::RecordCondition { reason, .. }) => {
            Failure::input(format!("--record-when: {reason}"))
        }
        Error::Simulation(S::BeyondLimit { limit, .. }) => {
            Failure::input(format!("{error} (--max-{limit}s N)"))
        }
        Error::OneRunOnly(what) => Failure::input(match what {
            lagrange::OneRunOnly::Plot => "--plot draws one run; leave it out of a --sweep",
            _ => "--record-when, --events and --summary describe one run; leave them out of a --sweep",
        }),
        _ => Failure::of(error, &args.input.model),
    }
}

/// `--sweep`: many runs from one derivation, one CSV row each.
fn sweep(
    args: &SimulateArgs,
    analysis: &Analysis,
    options: &SimulationOptions,
    files: &RunFiles,
) -> Result<Exit, Failure> {
    let progress = bar("{bar:40} {pos}/{len} runs, {elapsed} (eta {eta})");
    let request = lagrange::SweepRequest {
        ranges: &args.sweep,
        samples: args.samples,
        steps: args.steps,
        seed: args.seed,
    };
    let table = analysis
        .write_sweep(
            options,
            &request,
            files,
            &mut std::io::stdout().lock(),
            &mut |n| progress.set_length(n as u64),
            &|| progress.inc(1),
        )
        .map_err(|e| match e {
            Error::OneRunOnly(_) | Error::Create { .. } | Error::Write { .. } => failure(e, args),
            _ => failure(e, args).prefixed("--sweep"),
        })?;
    progress.finish_and_clear();
    eprintln!("{}", table.summary_line());
    if let Some(path) = &args.out {
        eprintln!("wrote {}", path.display());
    }
    Ok(if table.failed > 0 {
        Exit::RunFailed
    } else {
        Exit::Success
    })
}

fn bar(template: &str) -> ProgressBar {
    let bar = ProgressBar::new(1000);
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar
}
