//! Runs written out, as the command line writes them: a [`PreparedRun`] has its files
//! created before it starts (so that a bad path fails before a long run), streams its CSV as
//! it goes, then writes the recorded crossings, the JSON summary and the plot; a sweep is
//! written as one table ([`Analysis::write_sweep`]). No output file is ever the model file
//! ([`check_output`]).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use simulation::Simulation;

use crate::error::OneRunOnly;
use crate::{
    correction_warning, run_to_csv_with_reactions, Analysis, Error, ReactionProbe,
    SimulationOptions, Streamed, SweepRequest, SweepTable, DEFAULT_MAX_BYTES,
};

/// What a run writes besides the rows it streams.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RunFiles {
    /// The model file: its name goes into the summary, its stem into the plot's title.
    pub model: PathBuf,
    /// The CSV of the rows (default: the writer given to [`PreparedRun::run`]).
    pub csv: Option<PathBuf>,
    /// The recorded crossings as CSV: `event`, `direction`, `t`, the coordinates, the rates.
    pub events: Option<PathBuf>,
    /// The run's JSON summary (docs/json.md): settings, outcome, work, errors, crossings.
    pub summary: Option<PathBuf>,
    /// A plot of the run (`.svg` or `.png`): time histories, phase portraits, energy error.
    pub plot: Option<PathBuf>,
    /// The most bytes of CSV (default: [`DEFAULT_MAX_BYTES`]).
    pub max_bytes: Option<u64>,
}

impl RunFiles {
    /// Every output file asked for: the CSV, events, summary, plot, in that order.
    pub fn outputs(&self) -> impl Iterator<Item = &Path> {
        [&self.csv, &self.events, &self.summary, &self.plot]
            .into_iter()
            .filter_map(Option::as_deref)
    }
}

/// A simulation ready to run, its output files already created.
#[derive(Debug)]
pub struct PreparedRun {
    simulation: Simulation,
    files: RunFiles,
    csv: Option<BufWriter<File>>,
    events: Option<BufWriter<File>>,
    summary: Option<BufWriter<File>>,
    /// The reactions the model asks for, written beside each row (evaluated numerically);
    /// the error when they cannot be.
    reactions: Result<Option<ReactionProbe>, Error>,
}

/// A run that was written: how it went, in numbers and in words, and the files written.
#[derive(Debug, Clone)]
pub struct WrittenRun {
    /// How it ended, its work, what it recorded.
    pub streamed: Streamed,
    /// One line on how the run went ([`Streamed::summary_line`]).
    pub summary_line: String,
    /// One line on the recorded crossings, when any expression was recorded.
    pub crossings_line: Option<String>,
    /// The files written, in the order of [`RunFiles::outputs`].
    pub written: Vec<PathBuf>,
}

impl Analysis {
    /// A run of `options` writing `files`: the plot's name is checked and the simulation
    /// prepared (as [`Analysis::simulation`]), then every file is created.
    ///
    /// # Errors
    /// A plot name that is neither `.svg` nor `.png`, what [`Analysis::simulation`] refuses,
    /// or [`Error::Create`].
    pub fn prepare_run(
        &self,
        options: &SimulationOptions,
        files: RunFiles,
    ) -> Result<PreparedRun, Error> {
        if let Some(path) = &files.plot {
            let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
            if !ext.eq_ignore_ascii_case("svg") && !ext.eq_ignore_ascii_case("png") {
                let path = path.display().to_string();
                return Err(report::PlotError::Format { path }.into());
            }
        }
        let simulation = self.simulation(options)?;
        let open = |path: &Option<PathBuf>| path.as_deref().map(create).transpose();
        // A run on Kane's route has no multipliers to evaluate reactions with.
        let reactions = if simulation.by_kane() {
            Ok(None)
        } else {
            self.reaction_probe()
        };
        Ok(PreparedRun {
            reactions,
            csv: open(&files.csv)?,
            events: open(&files.events)?,
            summary: open(&files.summary)?,
            simulation,
            files,
        })
    }

    /// A sweep of simulations ([`Analysis::sweep_table`]) written as one CSV table to
    /// `files.csv` (created before the runs), else to `out`. The table's
    /// [`SweepTable::summary_line`] counts the derivations.
    ///
    /// # Errors
    /// [`Error::OneRunOnly`] for a plot, recorded crossings or a summary; else as
    /// [`Error::Create`], [`Analysis::sweep_table`] or [`Error::Write`].
    pub fn write_sweep(
        &self,
        options: &SimulationOptions,
        request: &SweepRequest<'_>,
        files: &RunFiles,
        out: &mut dyn Write,
        on_start: &mut dyn FnMut(usize),
        on_done: &(dyn Fn() + Sync),
    ) -> Result<SweepTable, Error> {
        let refused = if files.plot.is_some() {
            Some(OneRunOnly::Plot)
        } else if !options.record_when.is_empty() || files.events.is_some() {
            Some(OneRunOnly::Crossings)
        } else {
            files.summary.as_ref().map(|_| OneRunOnly::Summary)
        };
        if let Some(what) = refused {
            return Err(Error::OneRunOnly(what));
        }
        let mut file = files.csv.as_deref().map(create).transpose()?;
        let started = Instant::now();
        let mut table = self.sweep_table(options, request, on_start, on_done)?;
        table.wall_time = started.elapsed().as_secs_f64();
        table.derivations = self.derivations();
        let out: &mut dyn Write = match &mut file {
            Some(file) => file,
            None => out,
        };
        write_text(out, &table.csv, "the CSV")?;
        Ok(table)
    }
}

impl PreparedRun {
    /// The prepared simulation.
    #[must_use]
    pub fn simulation(&self) -> &Simulation {
        &self.simulation
    }

    /// A warning when the initial state was moved onto the constraints.
    #[must_use]
    pub fn warning(&self) -> Option<String> {
        let reactions = self
            .reactions
            .as_ref()
            .err()
            .map(|e| format!("the reactions are left out of the CSV: {e}"));
        match (correction_warning(&self.simulation), reactions) {
            (Some(a), Some(b)) => Some(format!("{a}\nwarning: {b}")),
            (a, b) => a.or(b),
        }
    }

    /// Runs, streaming the CSV to its file or else to `out`, then writes the crossings, the
    /// summary and the plot. `on_progress` hears the fraction of the time span done.
    ///
    /// # Errors
    /// [`Error::Write`] or [`Error::Plot`]; a run that fails part-way is not an error (its
    /// [`Streamed::ending`] says so, and what it computed is written).
    pub fn run(
        mut self,
        out: &mut dyn Write,
        on_progress: &mut dyn FnMut(f64),
    ) -> Result<WrittenRun, Error> {
        let (t0, t1) = self.simulation.span();
        let max_bytes = self.files.max_bytes.unwrap_or(DEFAULT_MAX_BYTES);
        let keep = self.files.plot.is_some();
        let csv: &mut dyn Write = match &mut self.csv {
            Some(file) => file,
            None => out,
        };
        let reactions = self.reactions.as_ref().ok().and_then(Option::as_ref);
        let streamed = run_to_csv_with_reactions(
            &mut self.simulation,
            reactions,
            csv,
            keep,
            max_bytes,
            &mut |t| on_progress(((t - t0) / (t1 - t0)).clamp(0.0, 1.0)),
        )
        .map_err(|e| write_error("the CSV", &e))?;
        let simulation = &self.simulation;
        if let Some(mut file) = self.events.take() {
            let text = streamed.events_csv(simulation, simulation.recorded());
            write_text(&mut file, &text, "the events")?;
        }
        if let Some(mut file) = self.summary.take() {
            let model = self.files.model.display().to_string();
            let json = streamed.summary_json(&model, simulation);
            let text = serde_json::to_string_pretty(&json).unwrap_or_else(|e| format!("\"{e}\""));
            write_text(&mut file, &(text + "\n"), "the summary")?;
        }
        if let Some(path) = &self.files.plot {
            let stem = self.files.model.file_stem().unwrap_or_default();
            let title = format!("{} — {}", stem.to_string_lossy(), simulation.method());
            let columns = reactions.map_or_else(Vec::new, ReactionProbe::columns);
            report::plot_run_with_reactions(
                path,
                &title,
                &simulation.columns(),
                &columns,
                &streamed.kept,
            )?;
        }
        let recorded = simulation.recorded();
        Ok(WrittenRun {
            summary_line: streamed.summary_line(simulation),
            crossings_line: (!recorded.is_empty())
                .then(|| crate::csv::crossings_line(recorded, &streamed.tally.crossings)),
            written: self.files.outputs().map(Path::to_owned).collect(),
            streamed,
        })
    }
}

/// Refuses an output file that is the model file itself; `Ok(true)` when `file` exists and
/// will be replaced.
///
/// # Errors
/// [`Error::OverwritesInput`].
pub fn check_output(file: &Path, model: &Path) -> Result<bool, Error> {
    match (file.canonicalize(), model.canonicalize()) {
        (Ok(a), Ok(b)) if a == b => Err(Error::OverwritesInput {
            path: file.to_owned(),
        }),
        _ => Ok(file.exists()),
    }
}

/// Creates (or empties) an output file.
///
/// # Errors
/// [`Error::Create`].
pub fn create(path: &Path) -> Result<BufWriter<File>, Error> {
    File::create(path)
        .map(BufWriter::new)
        .map_err(|e| Error::Create {
            path: path.to_owned(),
            reason: e.to_string(),
        })
}

/// Writes `bytes` (a text or an image) to a file, created or emptied first.
///
/// # Errors
/// [`Error::Write`], naming the file.
pub fn write_file(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), Error> {
    std::fs::write(path, bytes).map_err(|e| write_error(&format!("`{}`", path.display()), &e))
}

/// Writes and flushes `text`; an error names `what` was being written.
fn write_text(out: &mut dyn Write, text: &str, what: &str) -> Result<(), Error> {
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| write_error(what, &e))
}

fn write_error(what: &str, error: &std::io::Error) -> Error {
    Error::Write {
        what: what.to_owned(),
        reason: error.to_string(),
    }
}
