//! `lagrange simulate MODEL`: integrate the equations of motion, write the time history as
//! CSV, optionally plot it, and print a summary line; optionally record zero crossings
//! (`--record-when`, `--events`) and write the summary as JSON (`--summary`). A run that fails
//! part-way keeps and writes what it computed, then says when and why it stopped. With
//! `--sweep`, many runs on all cores, one CSV row each, from one derivation.

use lagrange::report;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use lagrange::{Analysis, Ending, MethodName, SimulationOptions};

use crate::exit::{check_output, output_error, Exit, Failure};

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
    /// Integration method (default: the model's, else dopri5): dopri5 (adaptive
    /// Dormand–Prince 5(4)), gauss (Gauss–Legendre order 6, fixed step, symplectic), sdirk
    /// (L-stable implicit SDIRK of order 2, for stiff systems).
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
    /// (default: 10⁷).
    #[arg(long, value_name = "N")]
    pub max_steps: Option<u64>,
    /// Stop (exit 3, the rows so far written) when one more output row than this is due
    /// (default: 10⁶).
    #[arg(long, value_name = "N")]
    pub max_rows: Option<u64>,
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

/// `--method NAME`, by the names the model's `simulate` statement takes too.
fn method(name: &str) -> Result<MethodName, String> {
    MethodName::parse(name).ok_or_else(|| format!("unknown method `{name}` (dopri5, gauss, sdirk)"))
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
    let analysis = super::load(&args.model, &args.set)?;
    for file in [&args.out, &args.events, &args.summary, &args.plot]
        .into_iter()
        .flatten()
    {
        check_output(file, &args.model)?;
    }
    let options = options(args);
    if !args.sweep.is_empty() {
        return sweep(args, &analysis, &options);
    }
    if let Some(path) = &args.plot {
        // Refuse a bad plot name before the run rather than after it.
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !ext.eq_ignore_ascii_case("svg") && !ext.eq_ignore_ascii_case("png") {
            return Err(Failure::input(format!(
                "cannot plot to `{}`: the file name must end in .svg or .png",
                path.display()
            )));
        }
    }
    let mut simulation = analysis
        .simulation(&options)
        .map_err(|e| failure(e, args))?;
    if let Some(warning) = lagrange::correction_warning(&simulation) {
        eprintln!("warning: {warning}");
    }
    // Every output file is created before the run, so a bad path fails before a long run.
    let mut writer: Box<dyn Write> = match &args.out {
        Some(path) => Box::new(create(path)?),
        None => Box::new(std::io::BufWriter::new(std::io::stdout().lock())),
    };
    let events_writer = args.events.as_deref().map(create).transpose()?;
    let summary_writer = args.summary.as_deref().map(create).transpose()?;
    let (t0, t1) = simulation.span();
    let started = Instant::now();
    let mut progress: Option<ProgressBar> = None;
    let run = lagrange::run_to_csv(
        &mut simulation,
        &mut writer,
        args.plot.is_some(),
        &mut |t| {
            // A progress bar only for runs long enough to need one; indicatif hides it when
            // stderr is not a terminal.
            if progress.is_none() && started.elapsed().as_secs_f64() > 0.5 {
                progress = Some(bar(
                    "simulating {bar:40} {percent:>3}% ({elapsed}, eta {eta})",
                ));
            }
            if let Some(bar) = &progress {
                bar.set_position((((t - t0) / (t1 - t0)).clamp(0.0, 1.0) * 1000.0) as u64);
            }
        },
    )
    .map_err(|e| output_error("the CSV", &e))?;
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }
    drop(writer);
    let outcome = &run.outcome;
    eprintln!("{}", run.summary_line(&simulation));
    if !args.record_when.is_empty() {
        eprintln!(
            "{}",
            lagrange::csv::crossings_line(&args.record_when, &run.tally.crossings)
        );
    }
    write_extras(args, &simulation, &run, events_writer, summary_writer)?;
    for path in [&args.out, &args.events, &args.summary]
        .into_iter()
        .flatten()
    {
        eprintln!("wrote {}", path.display());
    }
    if let Some(path) = &args.plot {
        let title = format!("{} — {}", stem(&args.model), simulation.method());
        report::plot_run(path, &title, &simulation.columns(), &run.kept)
            .map_err(|e| Failure::new(Exit::Output, e))?;
        eprintln!("wrote {}", path.display());
    }
    Ok(exit_of(&Ending::of(&simulation, outcome), outcome.t))
}

/// `--events` and `--summary`, into the files created before the run.
fn write_extras(
    args: &SimulateArgs,
    simulation: &lagrange::simulation::Simulation,
    run: &lagrange::Streamed,
    events: Option<std::io::BufWriter<std::fs::File>>,
    summary: Option<std::io::BufWriter<std::fs::File>>,
) -> Result<(), Failure> {
    let model = args.model.display().to_string();
    let events_text = || run.events_csv(simulation, &args.record_when);
    let summary_text = || super::eom::json(&run.summary_json(&model, simulation)) + "\n";
    let texts: [(_, _, &dyn Fn() -> String); 2] = [
        (events, "the events", &events_text),
        (summary, "the summary", &summary_text),
    ];
    for (writer, what, text) in texts {
        if let Some(mut w) = writer {
            w.write_all(text().as_bytes())
                .and_then(|()| w.flush())
                .map_err(|e| output_error(what, &e))?;
        }
    }
    Ok(())
}

/// The exit code of a run's ending, said on stderr when it stopped early.
fn exit_of(ending: &Ending, t: f64) -> Exit {
    if let Some(sentence) = ending.sentence(t) {
        match ending {
            Ending::Failed(failure) => {
                eprintln!("error: {sentence}; the rows computed up to then were written");
                if let Some(hint) = hint(failure) {
                    eprintln!("hint: {hint}");
                }
            }
            Ending::ContactLost { .. } => {
                eprintln!("{sentence}; run with --through-contact-loss to go on regardless");
            }
            _ => eprintln!("{sentence}"),
        }
    }
    if matches!(ending, Ending::Failed(_)) {
        Exit::RunFailed
    } else {
        Exit::Success
    }
}

/// The flag that helps with a failure that a limit or the method decided.
fn hint(failure: &lagrange::numeric::Failure) -> Option<&'static str> {
    use lagrange::numeric::Failure as F;
    match failure {
        F::Stiff { .. } => Some("stiff: use --method sdirk"),
        F::TooManySteps { .. } => Some("raise the limit with --max-steps N"),
        F::TooManyOutputs { .. } => {
            Some("raise the limit with --max-rows N, or write fewer rows with --output-step")
        }
        _ => None,
    }
}

/// A library error, with the flag named where it comes from one.
fn failure(error: lagrange::Error, args: &SimulateArgs) -> Failure {
    use lagrange::simulation::SimulationError as S;
    match &error {
        lagrange::Error::Simulation(S::StopCondition { reason, .. }) => {
            Failure::input(format!("--stop-when: {reason}"))
        }
        lagrange::Error::Simulation(S::RecordCondition { reason, .. }) => {
            Failure::input(format!("--record-when: {reason}"))
        }
        _ => Failure::of(error, &args.model),
    }
}

/// `--sweep`: many runs from one derivation, one CSV row each.
fn sweep(
    args: &SimulateArgs,
    analysis: &Analysis,
    options: &SimulationOptions,
) -> Result<Exit, Failure> {
    if args.plot.is_some() {
        return Err(Failure::input(
            "--plot draws one run; leave it out of a --sweep",
        ));
    }
    if !args.record_when.is_empty() || args.events.is_some() || args.summary.is_some() {
        return Err(Failure::input(
            "--record-when, --events and --summary describe one run; leave them out of a --sweep",
        ));
    }
    let progress = bar("{bar:40} {pos}/{len} runs, {elapsed} (eta {eta})");
    let started = Instant::now();
    let request = lagrange::SweepRequest {
        ranges: &args.sweep,
        samples: args.samples,
        steps: args.steps,
        seed: args.seed,
    };
    let table = analysis
        .sweep_table(
            options,
            &request,
            &mut |n| progress.set_length(n as u64),
            &|| progress.inc(1),
        )
        .map_err(|e| failure(e, args).prefixed("--sweep"))?;
    progress.finish_and_clear();
    let mut writer: Box<dyn Write> = match &args.out {
        Some(path) => Box::new(create(path)?),
        None => Box::new(std::io::BufWriter::new(std::io::stdout().lock())),
    };
    writer
        .write_all(table.csv.as_bytes())
        .and_then(|()| writer.flush())
        .map_err(|e| output_error("the CSV", &e))?;
    eprintln!(
        "{} runs on {} threads in {:.2} s ({} derivation), {} failed",
        table.runs,
        std::thread::available_parallelism().map_or(1, usize::from),
        started.elapsed().as_secs_f64(),
        analysis.derivations(),
        table.failed
    );
    if let Some(path) = &args.out {
        eprintln!("wrote {}", path.display());
    }
    Ok(if table.failed > 0 {
        Exit::RunFailed
    } else {
        Exit::Success
    })
}

fn create(path: &Path) -> Result<std::io::BufWriter<std::fs::File>, Failure> {
    std::fs::File::create(path)
        .map(std::io::BufWriter::new)
        .map_err(|e| Failure::input(format!("cannot create `{}`: {e}", path.display())))
}

fn bar(template: &str) -> ProgressBar {
    let bar = ProgressBar::new(1000);
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar
}

fn stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
}
