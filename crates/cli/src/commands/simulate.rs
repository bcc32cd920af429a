//! `lagrange simulate MODEL`: integrate the equations of motion, write the time history as
//! CSV, optionally plot it, and print a summary line; optionally record zero crossings
//! (`--record-when`, `--events`) and write the summary as JSON (`--summary`). A run that fails
//! part-way keeps and writes what it computed, then says when and why it stopped. With
//! `--sweep`, many runs on all cores, one CSV row each, from one derivation.

use lagrange::report;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use lagrange::{Analysis, Crossing, Ending, MethodName, SimulationOptions};

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

/// The run options the flags ask for.
fn options(args: &SimulateArgs) -> SimulationOptions {
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
        record_when: args.record_when.clone(),
        through_contact_loss: args.through_contact_loss,
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
    warn_if_corrected(&simulation);
    // Every output file is created before the run, so a bad path fails before a long run.
    let writer: Box<dyn Write> = match &args.out {
        Some(path) => Box::new(create(path)?),
        None => Box::new(std::io::BufWriter::new(std::io::stdout().lock())),
    };
    let events_writer = args.events.as_deref().map(create).transpose()?;
    let summary_writer = args.summary.as_deref().map(create).transpose()?;
    let mut output = Output::new(writer, &simulation, args.plot.is_some())?;
    // The crossings apart: the integrator hands rows and crossings to two callbacks.
    let mut recorded = lagrange::Tally::default();
    let outcome = simulation.run_recording(&mut |row| output.row(row), &mut |c| {
        recorded.crossing(&c);
    });
    let (mut tally, kept, elapsed) = output.finish()?;
    tally.crossings = recorded.crossings;
    eprintln!(
        "{method}: t = {t:.6} of {t_end}, {steps} steps ({rejected} rejected), {evals} evaluations, {wall}, final energy error {error:.3e}",
        method = simulation.method(),
        t = outcome.t,
        t_end = simulation.span().1,
        steps = outcome.stats.steps,
        rejected = outcome.stats.rejected,
        evals = outcome.stats.evaluations,
        wall = format_duration(elapsed),
        error = tally.energy_error(),
    );
    if !args.record_when.is_empty() {
        eprintln!("{}", crossings_line(&args.record_when, &tally.crossings));
    }
    if let Some(mut w) = events_writer {
        let columns = simulation.columns();
        write_events(
            &mut w,
            &columns[..columns.len() - 2],
            &args.record_when,
            &tally.crossings,
        )
        .map_err(|e| output_error("the events", &e))?;
    }
    if let Some(mut w) = summary_writer {
        let model = args.model.display().to_string();
        let text = super::eom::json(&tally.summary(&model, &simulation, &outcome, elapsed));
        writeln!(w, "{text}")
            .and_then(|()| w.flush())
            .map_err(|e| output_error("the summary", &e))?;
    }
    for path in [&args.out, &args.events, &args.summary]
        .into_iter()
        .flatten()
    {
        eprintln!("wrote {}", path.display());
    }
    if let Some(path) = &args.plot {
        let title = format!("{} — {}", stem(&args.model), simulation.method());
        report::plot_run(path, &title, &simulation.columns(), &kept)
            .map_err(|e| Failure::new(Exit::Output, e))?;
        eprintln!("wrote {}", path.display());
    }
    Ok(exit_of(&Ending::of(&simulation, &outcome), outcome.t))
}

/// Says on stderr how the initial state was moved onto the constraints, when it was.
fn warn_if_corrected(simulation: &lagrange::simulation::Simulation) {
    let Some(c) = simulation.initial_correction() else {
        return;
    };
    let moved: Vec<String> = simulation.columns()[1..]
        .iter()
        .zip(c.given.iter().zip(&c.corrected))
        .filter(|(_, (a, b))| a != b)
        .map(|(name, (a, b))| format!("{name} = {a} → {b}"))
        .collect();
    eprintln!(
        "warning: the initial state does not satisfy the constraints; the run starts from the nearest state that does: {}",
        moved.join(", ")
    );
}

/// Where the rows of a single run go: the CSV, the plot's copy, the tally, the progress bar.
struct Output<'w> {
    writer: Box<dyn Write + 'w>,
    write_error: Option<std::io::Error>,
    kept: Option<Vec<Vec<f64>>>,
    tally: lagrange::Tally,
    progress: Option<ProgressBar>,
    span: (f64, f64),
    started: Instant,
}

impl<'w> Output<'w> {
    fn new(
        mut writer: Box<dyn Write + 'w>,
        simulation: &lagrange::simulation::Simulation,
        keep: bool,
    ) -> Result<Output<'w>, Failure> {
        writeln!(writer, "{}", simulation.columns().join(","))
            .map_err(|e| output_error("the CSV", &e))?;
        Ok(Output {
            writer,
            write_error: None,
            kept: keep.then(Vec::new),
            tally: lagrange::Tally::default(),
            progress: None,
            span: simulation.span(),
            started: Instant::now(),
        })
    }

    fn row(&mut self, row: &[f64]) {
        if self.write_error.is_none() {
            self.write_error = write_row(&mut self.writer, row).err();
        }
        if let Some(kept) = &mut self.kept {
            kept.push(row.to_vec());
        }
        self.tally.row(row);
        // A progress bar only for runs long enough to need one; indicatif hides it when
        // stderr is not a terminal.
        if self.progress.is_none() && self.started.elapsed().as_secs_f64() > 0.5 {
            self.progress = Some(bar(
                "simulating {bar:40} {percent:>3}% ({elapsed}, eta {eta})",
            ));
        }
        if let Some(bar) = &self.progress {
            let (t0, t1) = self.span;
            let fraction = ((row[0] - t0) / (t1 - t0)).clamp(0.0, 1.0);
            bar.set_position((fraction * 1000.0) as u64);
        }
    }

    /// Flushes the CSV; the tally, the kept rows and the wall time in seconds.
    fn finish(mut self) -> Result<(lagrange::Tally, Vec<Vec<f64>>, f64), Failure> {
        let elapsed = self.started.elapsed().as_secs_f64();
        if let Some(bar) = self.progress.take() {
            bar.finish_and_clear();
        }
        let csv = |e: std::io::Error| output_error("the CSV", &e);
        if let Some(error) = self.write_error.take() {
            return Err(csv(error));
        }
        self.writer.flush().map_err(csv)?;
        Ok((self.tally, self.kept.unwrap_or_default(), elapsed))
    }
}

/// The exit code of a run's ending, said on stderr when it stopped early.
fn exit_of(ending: &Ending, t: f64) -> Exit {
    match ending {
        Ending::Finished => Exit::Success,
        Ending::ContactLost { constraint } => {
            eprintln!(
                "stopped at t = {t}: the one-sided constraint `{constraint}` is lost there (its reaction changes sign); run with --through-contact-loss to go on regardless"
            );
            Exit::Success
        }
        Ending::Condition { .. } => {
            eprintln!("stopped at t = {t}: --stop-when expression crossed zero");
            Exit::Success
        }
        Ending::Failed(failure) => {
            eprintln!("error: the simulation stopped {failure}; the rows computed up to then were written");
            Exit::RunFailed
        }
        _ => Exit::RunFailed,
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
    let lookup = super::lookup(analysis);
    let ranges = args
        .sweep
        .iter()
        .map(|s| lagrange::parse_range(s, &lookup))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| Failure::input(format!("--sweep {e}")))?;
    let runs = match (args.samples, ranges.as_slice()) {
        (Some(count), _) => lagrange::samples(&ranges, count, args.seed)
            .map_err(|_| Failure::input("--samples must be at least 1"))?,
        (None, [range]) => lagrange::grid(range, args.steps),
        (None, _) => {
            return Err(Failure::input(
                "several --sweep ranges need --samples N (Monte-Carlo); a grid sweeps one name",
            ))
        }
    };
    let names: Vec<String> = ranges.iter().map(|r| r.name.clone()).collect();
    let progress = bar("{bar:40} {pos}/{len} runs, {elapsed} (eta {eta})");
    progress.set_length(runs.len() as u64);
    let started = Instant::now();
    let results = analysis
        .sweep(options, &names, &runs, &|| progress.inc(1))
        .map_err(|e| failure(e, args).prefixed("--sweep"))?;
    progress.finish_and_clear();
    let columns = analysis
        .simulation(options)
        .map_or_else(|_| Vec::new(), |s| s.columns());
    let mut writer: Box<dyn Write> = match &args.out {
        Some(path) => Box::new(create(path)?),
        None => Box::new(std::io::BufWriter::new(std::io::stdout().lock())),
    };
    let mut text = String::new();
    let mut header: Vec<String> = vec!["run".into()];
    header.extend(names.iter().cloned());
    header.extend(columns.iter().map(|c| format!("final_{c}")));
    header.extend(["steps".into(), "outcome".into()]);
    text.push_str(&header.join(","));
    text.push('\n');
    let mut failed = 0;
    for (k, (values, result)) in runs.iter().zip(&results).enumerate() {
        let mut row: Vec<String> = vec![k.to_string()];
        row.extend(values.iter().map(|v| format!("{v:?}")));
        match result {
            Ok(r) => {
                failed += usize::from(matches!(r.ending, Ending::Failed(_)));
                row.extend(r.last.iter().map(|v| format!("{v:?}")));
                row.extend(std::iter::repeat_n(
                    String::new(),
                    columns.len().saturating_sub(r.last.len()),
                ));
                row.push(r.steps.to_string());
                row.push(format!("\"{}\"", r.ending.word().replace('"', "'")));
            }
            Err(e) => {
                failed += 1;
                row.extend(std::iter::repeat_n(String::new(), columns.len() + 1));
                row.push(format!("\"error: {}\"", e.to_string().replace('"', "'")));
            }
        }
        text.push_str(&row.join(","));
        text.push('\n');
    }
    writer
        .write_all(text.as_bytes())
        .and_then(|()| writer.flush())
        .map_err(|e| output_error("the CSV", &e))?;
    eprintln!(
        "{} runs on {} threads in {:.2} s ({} derivation), {failed} failed",
        runs.len(),
        rayon_threads(),
        started.elapsed().as_secs_f64(),
        analysis.derivations()
    );
    if let Some(path) = &args.out {
        eprintln!("wrote {}", path.display());
    }
    Ok(if failed > 0 {
        Exit::RunFailed
    } else {
        Exit::Success
    })
}

fn rayon_threads() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

fn write_events(
    w: &mut dyn Write,
    columns: &[String],
    expressions: &[String],
    crossings: &[Crossing],
) -> std::io::Result<()> {
    writeln!(w, "event,direction,{}", columns.join(","))?;
    for c in crossings {
        let name = expressions.get(c.event).map_or("", String::as_str);
        write!(w, "{},{},", csv_text(name), lagrange::direction(c.rising))?;
        write_row(w, &c.state)?;
    }
    w.flush()
}

/// The stderr line about recorded crossings: how many, and the first few.
fn crossings_line(expressions: &[String], crossings: &[Crossing]) -> String {
    const SHOWN: usize = 4;
    let mut line = format!(
        "recorded {} crossing{}",
        crossings.len(),
        if crossings.len() == 1 { "" } else { "s" }
    );
    for (k, c) in crossings.iter().take(SHOWN).enumerate() {
        line.push_str(if k == 0 { ": " } else { ", " });
        line.push_str(&format!(
            "`{}` {} at t = {:.6}",
            expressions.get(c.event).map_or("", String::as_str),
            lagrange::direction(c.rising),
            c.state[0]
        ));
    }
    if crossings.len() > SHOWN {
        line.push_str(&format!(", … ({} more)", crossings.len() - SHOWN));
    }
    line
}

/// A CSV field: quoted (with quotes doubled) when it holds a comma, a quote or a line break.
fn csv_text(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
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

fn stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
}
