//! `lagrange linearize MODEL --periodic [T]`: Floquet analysis of a time-periodic system
//! (monodromy matrix, multipliers, verdict), and with `--sweep` (one or two) its stability
//! chart as CSV, drawn with `--plot`.

use lagrange::{Analysis, FloquetOptions, Written};

use super::each;
use crate::args::{EquilibriumOptions, ModelInput};
use crate::exit::{print, println, Exit, Failure};

/// `lagrange linearize --periodic`; `period` is the flag's value (empty: the driving's).
pub fn run(
    input: &ModelInput,
    options: &EquilibriumOptions,
    only: Option<usize>,
    period: &str,
    initial: &[String],
) -> Result<Exit, Failure> {
    let path = input.model.as_path();
    let analysis = super::load(path, &input.set)?;
    for (flag, given) in [
        ("--steady", !options.steady.is_empty()),
        ("--range", !options.range.is_empty()),
        ("--initial", !initial.is_empty()),
    ] {
        if given {
            return Err(Failure::input(format!(
                "{flag} does not go with --periodic"
            )));
        }
    }
    let floquet = FloquetOptions {
        period: read_period(&analysis, period)?,
        ..FloquetOptions::default()
    };
    if !options.sweep.is_empty() {
        return chart(path, &analysis, &floquet, options, only);
    }
    if options.plot.is_some() {
        return Err(Failure::input(
            "--plot draws the stability chart of a --sweep; add --sweep P=a..b",
        ));
    }
    let mut found = analysis
        .floquet(&floquet)
        .map_err(|e| Failure::of(e, path).prefixed("--periodic"))?;
    if let Some(i) = only {
        let count = found.results.len();
        if i >= count {
            return Err(Failure::input(format!(
                "--equilibrium {i}: there are {count} periodic motion(s), numbered from 0"
            )));
        }
        found.results = vec![found.results.swap_remove(i)];
    }
    print(found.written(options.format))?;
    Ok(Exit::Success)
}

/// The period given to `--periodic` (a number or a constant expression such as `2*pi`), or
/// `None` for the driving's.
fn read_period(analysis: &Analysis, text: &str) -> Result<Option<f64>, Failure> {
    if text.trim().is_empty() {
        return Ok(None);
    }
    analysis
        .read_number(&format!("T={text}"))
        .map(|(_, v)| Some(v))
        .map_err(|e| Failure::input(format!("--periodic {text}: {e}")))
}

fn chart(
    path: &std::path::Path,
    analysis: &Analysis,
    floquet: &FloquetOptions,
    options: &EquilibriumOptions,
    only: Option<usize>,
) -> Result<Exit, Failure> {
    if options.sweep.len() > 2 {
        return Err(Failure::input(
            "--sweep: a stability chart sweeps one or two names",
        ));
    }
    let ranges = each(&options.sweep, "--sweep", |s| analysis.read_range(s))?;
    let chart = analysis
        .floquet_chart(floquet, &ranges, options.steps)
        .map_err(|e| Failure::of(e, path).prefixed("--sweep"))?;
    if let Some(plot) = &options.plot {
        let motion = only.unwrap_or(0);
        if motion >= chart.motions.len() {
            return Err(Failure::input(format!(
                "--equilibrium {motion}: there are {} periodic motion(s), numbered from 0",
                chart.motions.len()
            )));
        }
        chart
            .plot(plot, motion)
            .map_err(|e| Failure::of(e.into(), path))?;
        eprintln!("wrote {}", plot.display());
    }
    println(&chart.to_csv())?;
    Ok(Exit::Success)
}
