//! Runs said in words and tables: a run's one-line summary, and a sweep of runs planned
//! from `NAME=A..B` texts and written as one CSV table (one row per run).

use simulation::Simulation;

use crate::{assign, plan, Analysis, Error, SimulationOptions, Streamed};

/// A sweep's table and how many of its runs failed.
#[derive(Debug, Clone)]
pub struct SweepTable {
    /// The CSV: `run`, the varied names, `final_` and each column, `steps`, `outcome`.
    pub csv: String,
    /// Runs that failed or stopped early.
    pub failed: usize,
    /// All runs.
    pub runs: usize,
    /// Wall time of the runs, in seconds (set by [`Analysis::write_sweep`], else 0).
    pub wall_time: f64,
    /// Derivations of the equations of motion for all the runs (set by
    /// [`Analysis::write_sweep`], else 0; one, however many runs).
    pub derivations: usize,
}

impl SweepTable {
    /// One line on the sweep: runs, threads, wall time, derivations, failures.
    #[must_use]
    pub fn summary_line(&self) -> String {
        format!(
            "{} runs on {} threads in {:.2} s ({} derivation{}), {} failed",
            self.runs,
            std::thread::available_parallelism().map_or(1, usize::from),
            self.wall_time,
            self.derivations,
            if self.derivations == 1 { "" } else { "s" },
            self.failed
        )
    }
}

/// What to sweep: ranges as `NAME=A..B` text, and how to draw values from them.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepRequest<'a> {
    /// `NAME=A..B`, the ends constant expressions of the model's values (`0..2*l`).
    pub ranges: &'a [String],
    /// Monte-Carlo runs, each value uniform in its range; `None` for a grid over one range.
    pub samples: Option<usize>,
    /// Grid steps of a one-range sweep (`steps + 1` runs).
    pub steps: usize,
    /// Seed of the Monte-Carlo draws.
    pub seed: u64,
}

impl Analysis {
    /// The model's values (after any set) as a lookup, for constant expressions in a
    /// value, range or rate given as text (`x=0..2*l`).
    pub fn lookup(&self) -> impl Fn(cas::Symbol) -> Option<f64> {
        let values = self.values().unwrap_or_default();
        move |s: cas::Symbol| values.iter().find(|(n, _)| n == s.name()).map(|(_, v)| *v)
    }

    /// A sweep of simulations (see [`Analysis::sweep`]: all cores, one derivation) as one
    /// table; `on_start` hears the number of runs, `on_done` each finished one.
    ///
    /// # Errors
    /// A range that does not read, a plan that cannot be made (several ranges without
    /// samples, zero samples), or what [`Analysis::sweep`] refuses.
    pub fn sweep_table(
        &self,
        options: &SimulationOptions,
        request: &SweepRequest<'_>,
        on_start: &mut dyn FnMut(usize),
        on_done: &(dyn Fn() + Sync),
    ) -> Result<SweepTable, Error> {
        let lookup = self.lookup();
        let ranges = request
            .ranges
            .iter()
            .map(|s| assign::parse_range(s, &lookup))
            .collect::<Result<Vec<_>, _>>()?;
        let values = plan(&ranges, request.samples, request.steps, request.seed)?;
        let names: Vec<String> = ranges.into_iter().map(|r| r.name).collect();
        on_start(values.len());
        let results = self.sweep(options, &names, &values, on_done)?;
        let columns = self
            .simulation(options)
            .map_or_else(|_| Vec::new(), |s| s.columns());
        let (csv, failed) = crate::csv::sweep(&names, &columns, &values, &results);
        Ok(SweepTable {
            csv,
            failed,
            runs: values.len(),
            wall_time: 0.0,
            derivations: 0,
        })
    }
}

impl Streamed {
    /// One line on how the run went: method, time reached, steps, evaluations, wall time,
    /// final energy error, and with constraints kept by multipliers the largest drift from
    /// them over the rows (positions, velocities).
    #[must_use]
    pub fn summary_line(&self, simulation: &Simulation) -> String {
        let stats = &self.outcome.stats;
        let drift = simulation.drift().map_or_else(String::new, |d| {
            format!(
                ", constraint drift {:.1e} (positions), {:.1e} (velocities)",
                d.position, d.velocity
            )
        });
        format!(
            "{method}: t = {t:.6} of {t_end}, {steps} steps ({rejected} rejected), {evals} evaluations, {wall}, final energy error {error:.3e}{drift}",
            method = simulation.method(),
            t = self.outcome.t,
            t_end = simulation.span().1,
            steps = stats.steps,
            rejected = stats.rejected,
            evals = stats.evaluations,
            wall = duration(self.wall_time),
            error = self.tally.energy_error(),
        )
    }
}

impl Streamed {
    /// The crossings recorded for `expressions`, as CSV: `event`, `direction`, `t`, the
    /// coordinates, their rates.
    #[must_use]
    pub fn events_csv(&self, simulation: &Simulation, expressions: &[String]) -> String {
        let columns = simulation.columns();
        let state = &columns[..columns.len() - 2];
        crate::csv::events(state, expressions, &self.tally.crossings)
    }

    /// The run as JSON (docs/json.md): settings, outcome, work, errors, crossings.
    #[must_use]
    pub fn summary_json(&self, model: &str, simulation: &Simulation) -> serde_json::Value {
        self.tally.summary(
            model,
            simulation,
            &self.outcome,
            &self.ending,
            self.wall_time,
        )
    }
}

/// A warning when the initial state was moved onto the constraints, with the values changed.
#[must_use]
pub fn correction_warning(simulation: &Simulation) -> Option<String> {
    simulation.initial_correction().map(|c| {
        format!(
            "the initial state does not satisfy the constraints; the run starts from the nearest state that does: {}",
            c.describe(&simulation.columns())
        )
    })
}

/// A duration in seconds, in the unit that reads best (µs, ms, s).
#[must_use]
pub fn duration(seconds: f64) -> String {
    if seconds < 1e-3 {
        format!("{:.1} µs", seconds * 1e6)
    } else if seconds < 1.0 {
        format!("{:.2} ms", seconds * 1e3)
    } else {
        format!("{seconds:.2} s")
    }
}

#[cfg(test)]
mod tests {
    use super::duration;

    #[test]
    fn durations_read_in_their_unit() {
        assert_eq!(duration(2.5e-5), "25.0 µs");
        assert_eq!(duration(0.0123), "12.30 ms");
        assert_eq!(duration(3.0), "3.00 s");
    }
}
