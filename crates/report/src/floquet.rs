//! Floquet analysis of a time-periodic system, as `lagrange linearize --periodic` prints it:
//! the state the variations are taken about (an equilibrium that holds at every `t`, or a
//! periodic orbit), the monodromy matrix `Φ(T)` of the variational equations
//! `δẋ = J(x(t), t) δx`, `Φ(0) = I`, the Floquet multipliers `μ` (its eigenvalues), the
//! exponents `λ = ln μ / T`, and the verdict; and the stability chart of a sweep (CSV, and
//! a plot of the stable region).
//!
//! [`FloquetResult`] holds the numbers; [`floquet_text`] and [`floquet_json`] write them,
//! [`chart_csv`] and [`plot_stability_chart`] write a chart of [`ChartPoint`]s.

use std::fmt::Write as _;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use serde_json::{json, Value};

use crate::document::{Block, Cell, Section};
use crate::plot::{bounds, register_font, PlotError, FAMILY};

/// The linear stability of a periodic motion from its multipliers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Verdict {
    /// Every `|μ| < 1` (below the tolerance band): small variations decay.
    Stable,
    /// Every `|μ| ≤ 1`, some on the unit circle within the tolerance (an undamped system's
    /// stable motion): bounded to first order, the nonlinear terms not decided.
    Marginal,
    /// Some `|μ| > 1` beyond the tolerance: variations grow.
    Unstable,
}

impl Verdict {
    /// The word reports and the CSV use.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Stable => "stable",
            Verdict::Marginal => "marginally stable",
            Verdict::Unstable => "unstable",
        }
    }

    /// Stable or marginally stable.
    #[must_use]
    pub fn bounded(self) -> bool {
        !matches!(self, Verdict::Unstable)
    }

    /// The verdict from the multipliers `(re, im)`: unstable when some `|μ| > 1 + tolerance`,
    /// marginal when the largest is within `tolerance` of 1, else stable.
    #[must_use]
    pub fn of(multipliers: &[(f64, f64)], tolerance: f64) -> Verdict {
        let largest = multipliers
            .iter()
            .map(|(re, im)| re.hypot(*im))
            .fold(0.0, f64::max);
        if largest > 1.0 + tolerance {
            Verdict::Unstable
        } else if largest >= 1.0 - tolerance {
            Verdict::Marginal
        } else {
            Verdict::Stable
        }
    }
}

/// What the variations are taken about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Base {
    /// An equilibrium that holds at every `t`: `q̇ = 0` and `f(q, 0, t) = 0` for all `t`.
    Equilibrium,
    /// A periodic orbit `x(T) = x(0)` found by shooting.
    Orbit,
}

/// Where the period came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum PeriodSource {
    /// The common period of the `sin`/`cos` of `t` in the equations.
    Driving,
    /// Given by the user.
    Given,
}

/// The Floquet analysis about one periodic motion.
#[derive(Clone, Debug, PartialEq)]
pub struct FloquetResult {
    /// The coordinates, in the order of the state `(q, q̇)`.
    pub coordinates: Vec<String>,
    /// The period `T`.
    pub period: f64,
    /// Where `T` came from.
    pub period_source: PeriodSource,
    /// Equilibrium or orbit.
    pub base: Base,
    /// The state `(q, q̇)` at `t = 0`.
    pub state: Vec<f64>,
    /// `Φ(T)`, `2n × 2n`, row-major.
    pub monodromy: Vec<Vec<f64>>,
    /// The eigenvalues of `Φ(T)`, `(re, im)`.
    pub multipliers: Vec<(f64, f64)>,
    /// The verdict.
    pub verdict: Verdict,
    /// The band about `|μ| = 1` counted as on the unit circle.
    pub tolerance: f64,
    /// Accepted integration steps over the period.
    pub steps: u64,
}

impl FloquetResult {
    /// The exponents `λ = ln μ / T = (ln|μ| + i arg μ) / T`, one per multiplier (the
    /// imaginary part only up to multiples of `2π/T`).
    #[must_use]
    pub fn exponents(&self) -> Vec<(f64, f64)> {
        self.multipliers
            .iter()
            .map(|(re, im)| {
                (
                    re.hypot(*im).ln() / self.period,
                    im.atan2(*re) / self.period,
                )
            })
            .collect()
    }

    /// The largest `|μ|`.
    #[must_use]
    pub fn largest_multiplier(&self) -> f64 {
        self.multipliers
            .iter()
            .map(|(re, im)| re.hypot(*im))
            .fold(0.0, f64::max)
    }
}

/// One point of a stability chart: the swept values, and for each periodic motion followed
/// its verdict and largest `|μ|` (`None` where it was not found there).
#[derive(Clone, Debug, PartialEq)]
pub struct ChartPoint {
    /// One value per swept name.
    pub values: Vec<f64>,
    /// One per motion followed.
    pub verdicts: Vec<Option<(Verdict, f64)>>,
}

/// The results as `lagrange linearize --periodic` prints them.
#[must_use]
pub fn floquet_text(results: &[FloquetResult]) -> String {
    let mut out = String::new();
    let Some(first) = results.first() else {
        return "no periodic motion found about which to linearize\n".to_owned();
    };
    let source = match first.period_source {
        PeriodSource::Driving => "the common period of the driving",
        PeriodSource::Given => "given",
    };
    let _ = writeln!(
        out,
        "Floquet analysis: period T = {} ({source})",
        number(first.period)
    );
    for (k, r) in results.iter().enumerate() {
        let _ = writeln!(out);
        let _ = writeln!(out, "#{k}: {}", base_line(r));
        let _ = writeln!(out, "    monodromy matrix Φ(T) (state {}):", state_names(r));
        for row in &r.monodromy {
            let cells: Vec<String> = row.iter().map(|v| format!("{:>13}", number(*v))).collect();
            let _ = writeln!(out, "      [{} ]", cells.join(""));
        }
        let _ = writeln!(out, "    multipliers μ (|μ|) and exponents λ = ln μ / T:");
        for ((re, im), (lre, lim)) in r.multipliers.iter().zip(r.exponents()) {
            let _ = writeln!(
                out,
                "      μ = {}  (|μ| = {})   λ = {}",
                complex(*re, *im),
                number(re.hypot(*im)),
                complex(lre, lim)
            );
        }
        let _ = writeln!(out, "    {}", verdict_line(r));
    }
    out
}

/// The "Floquet analysis" section of a solution: the period, and for each periodic motion
/// where it is, its multipliers and verdict; or why there is none (`Err`, a sentence).
#[must_use]
pub fn floquet_section(results: Result<&[FloquetResult], String>) -> Section {
    let mut section = Section::new("Floquet analysis (time-periodic equations)", 2);
    let results = match results {
        Ok(r) if !r.is_empty() => r,
        Ok(_) => {
            section.paragraph("No periodic motion was found.");
            return section;
        }
        Err(why) => {
            section.paragraph(format!("Not analysed: {why}."));
            return section;
        }
    };
    section.paragraph(format!(
        "The equations depend on time periodically, with period T = {}. About each motion \
         below, the variational equations were integrated over one period; the eigenvalues \
         of the monodromy matrix Φ(T) are the Floquet multipliers μ: a small deviation is \
         multiplied by μ each period.",
        number(results[0].period)
    ));
    let rows = results
        .iter()
        .map(|r| {
            let mu: Vec<String> = r
                .multipliers
                .iter()
                .map(|(re, im)| complex(*re, *im))
                .collect();
            vec![
                Cell::Text(base_line(r)),
                Cell::Text(mu.join(", ")),
                Cell::Text(number(r.largest_multiplier())),
                Cell::Text(r.verdict.name().to_owned()),
            ]
        })
        .collect();
    section.blocks.push(Block::Table {
        header: vec![
            "motion".to_owned(),
            "multipliers μ".to_owned(),
            "largest |μ|".to_owned(),
            "verdict".to_owned(),
        ],
        rows,
    });
    section
}

/// The results as JSON (docs/json.md).
#[must_use]
pub fn floquet_json(results: &[FloquetResult]) -> Value {
    let pair = |(re, im): (f64, f64)| json!({ "re": re, "im": im, "abs": re.hypot(im) });
    let motions: Vec<Value> = results
        .iter()
        .map(|r| {
            json!({
                "base": match r.base { Base::Equilibrium => "equilibrium", Base::Orbit => "orbit" },
                "state": r.state,
                "monodromy": r.monodromy,
                "multipliers": r.multipliers.iter().copied().map(pair).collect::<Vec<_>>(),
                "exponents": r.exponents().into_iter().map(pair).collect::<Vec<_>>(),
                "verdict": r.verdict.name(),
                "largest_multiplier": r.largest_multiplier(),
                "tolerance": r.tolerance,
                "steps": r.steps,
            })
        })
        .collect();
    json!({
        "schema": crate::SCHEMA,
        "coordinates": results.first().map(|r| r.coordinates.clone()).unwrap_or_default(),
        "period": results.first().map(|r| r.period),
        "period_source": results.first().map(|r| match r.period_source {
            PeriodSource::Driving => "driving",
            PeriodSource::Given => "given",
        }),
        "motions": motions,
    })
}

/// The chart as CSV: the swept names, then for each motion `k` its verdict
/// (`stable`, `marginal`, `unstable`, or `none` where it was not found) and largest `|μ|`.
#[must_use]
pub fn chart_csv(names: &[String], motions: usize, points: &[ChartPoint]) -> String {
    let mut out = names.join(",");
    for k in 0..motions {
        let _ = write!(out, ",verdict_{k},max_abs_multiplier_{k}");
    }
    out.push('\n');
    for p in points {
        let cells: Vec<String> = p.values.iter().map(|v| format!("{v}")).collect();
        out.push_str(&cells.join(","));
        for v in &p.verdicts {
            match v {
                Some((verdict, mu)) => {
                    let word = match verdict {
                        Verdict::Stable => "stable",
                        Verdict::Marginal => "marginal",
                        Verdict::Unstable => "unstable",
                    };
                    let _ = write!(out, ",{word},{mu}");
                }
                None => out.push_str(",none,"),
            }
        }
        out.push('\n');
    }
    out
}

/// Draws the chart of motion `motion`: for two swept names, the plane of their values with
/// the bounded (stable or marginal) cells filled and the unstable ones pale; for one, the
/// largest `|μ|` against the value (log scale), bounded points filled. SVG or PNG by the
/// file's extension.
///
/// # Errors
/// A [`PlotError`] for a wrong extension, nothing to draw, or a drawing failure.
pub fn plot_stability_chart(
    path: &Path,
    names: &[String],
    points: &[ChartPoint],
    motion: usize,
) -> Result<(), PlotError> {
    register_font();
    let name = path.display().to_string();
    let drawing = |e: &dyn std::fmt::Display| PlotError::Drawing {
        path: name.clone(),
        message: e.to_string(),
    };
    let cells: Vec<(&[f64], Verdict, f64)> = points
        .iter()
        .filter_map(|p| {
            let (v, mu) = p.verdicts.get(motion).copied().flatten()?;
            Some((&p.values[..], v, mu))
        })
        .collect();
    if cells.is_empty() || names.is_empty() || names.len() > 2 {
        return Err(PlotError::NoData);
    }
    let size = (900, 700);
    match path.extension().and_then(|e| e.to_str()) {
        Some(ext) if ext.eq_ignore_ascii_case("svg") => {
            let root = SVGBackend::new(path, size).into_drawing_area();
            draw_chart(&root, names, &cells).map_err(|e| drawing(&e))?;
            root.present().map_err(|e| drawing(&e))
        }
        Some(ext) if ext.eq_ignore_ascii_case("png") => {
            let root = BitMapBackend::new(path, size).into_drawing_area();
            draw_chart(&root, names, &cells).map_err(|e| drawing(&e))?;
            root.present().map_err(|e| drawing(&e))
        }
        _ => Err(PlotError::Format { path: name }),
    }
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

const BOUNDED: RGBColor = RGBColor(31, 119, 180);
const UNBOUNDED: RGBColor = RGBColor(250, 215, 210);

fn draw_chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    names: &[String],
    cells: &[(&[f64], Verdict, f64)],
) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    if names.len() == 2 {
        let title = format!(
            "stability chart: stable (filled) in the ({}, {}) plane",
            names[0], names[1]
        );
        let root = root.titled(&title, (FAMILY, 22))?;
        draw_plane(&root, names, cells)
    } else {
        let title = format!("largest Floquet multiplier against {}", names[0]);
        let root = root.titled(&title, (FAMILY, 22))?;
        draw_line(&root, &names[0], cells)
    }
}

/// The grid step along axis `axis`: the smallest gap between distinct values.
fn step(cells: &[(&[f64], Verdict, f64)], axis: usize) -> f64 {
    let mut values: Vec<f64> = cells.iter().map(|c| c.0[axis]).collect();
    values.sort_by(f64::total_cmp);
    values.dedup();
    values
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min)
        .min(1.0e300)
}

fn draw_plane<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    names: &[String],
    cells: &[(&[f64], Verdict, f64)],
) -> DrawResult<DB> {
    let (dx, dy) = (step(cells, 0), step(cells, 1));
    let (dx, dy) = (
        if dx.is_finite() { dx } else { 1.0 },
        if dy.is_finite() { dy } else { 1.0 },
    );
    let x = bounds(cells.iter().map(|c| c.0[0]));
    let y = bounds(cells.iter().map(|c| c.0[1]));
    let mut chart = ChartBuilder::on(root)
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)?;
    chart
        .configure_mesh()
        .x_desc(names[0].as_str())
        .y_desc(names[1].as_str())
        .label_style((FAMILY, 14))
        .disable_mesh()
        .draw()?;
    for (bounded, colour) in [(false, UNBOUNDED), (true, BOUNDED)] {
        let series = chart.draw_series(cells.iter().filter(|c| c.1.bounded() == bounded).map(
            |(v, _, _)| {
                Rectangle::new(
                    [
                        (v[0] - dx / 2.0, v[1] - dy / 2.0),
                        (v[0] + dx / 2.0, v[1] + dy / 2.0),
                    ],
                    colour.filled(),
                )
            },
        ))?;
        let label = if bounded {
            "stable (|μ| ≤ 1)"
        } else {
            "unstable"
        };
        series.label(label).legend(move |(x, y)| {
            Rectangle::new([(x + 4, y - 5), (x + 14, y + 5)], colour.filled())
        });
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(200, 200, 200))
        .label_font((FAMILY, 14))
        .draw()?;
    Ok(())
}

fn draw_line<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    name: &str,
    cells: &[(&[f64], Verdict, f64)],
) -> DrawResult<DB> {
    let x = bounds(cells.iter().map(|c| c.0[0]));
    let y = bounds(cells.iter().map(|c| c.2.max(1e-300).log10()));
    let mut chart = ChartBuilder::on(root)
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)?;
    chart
        .configure_mesh()
        .x_desc(name)
        .y_desc("log10 max |μ|")
        .label_style((FAMILY, 14))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    let unstable = RGBColor(214, 39, 40);
    for (bounded, style) in [(true, BOUNDED.filled()), (false, unstable.stroke_width(2))] {
        let series = chart.draw_series(
            cells
                .iter()
                .filter(|c| c.1.bounded() == bounded)
                .map(move |(v, _, mu)| Circle::new((v[0], mu.max(1e-300).log10()), 4, style)),
        )?;
        let label = if bounded {
            "stable (|μ| ≤ 1)"
        } else {
            "unstable"
        };
        series
            .label(label)
            .legend(move |(x, y)| Circle::new((x + 10, y), 4, style));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(200, 200, 200))
        .label_font((FAMILY, 14))
        .draw()?;
    Ok(())
}

fn base_line(r: &FloquetResult) -> String {
    let n = r.coordinates.len();
    let at: Vec<String> = r
        .coordinates
        .iter()
        .zip(&r.state)
        .map(|(q, v)| format!("{q} = {}", number(*v)))
        .collect();
    match r.base {
        Base::Equilibrium => format!("equilibrium at every t: {}", at.join(", ")),
        Base::Orbit => {
            let rates: Vec<String> = r
                .coordinates
                .iter()
                .zip(&r.state[n..])
                .map(|(q, v)| format!("{q}' = {}", number(*v)))
                .collect();
            format!(
                "periodic orbit (found by shooting), at t = 0: {}, {}",
                at.join(", "),
                rates.join(", ")
            )
        }
    }
}

fn state_names(r: &FloquetResult) -> String {
    let mut names = r.coordinates.clone();
    names.extend(r.coordinates.iter().map(|q| format!("{q}'")));
    format!("({})", names.join(", "))
}

fn verdict_line(r: &FloquetResult) -> String {
    let largest = number(r.largest_multiplier());
    match r.verdict {
        Verdict::Stable => format!("stable: every |μ| < 1 (largest {largest})"),
        Verdict::Marginal => format!(
            "stable, marginally: the largest |μ| = {largest} is 1 within {:e} — bounded to first \
             order (as every undamped stable motion); the nonlinear terms are not decided",
            r.tolerance
        ),
        Verdict::Unstable => format!("unstable: |μ| = {largest} > 1"),
    }
}

/// Six significant digits, never `-0`.
fn number(v: f64) -> String {
    let v = if v == 0.0 { 0.0 } else { v };
    if v != 0.0 && (v.abs() >= 1e6 || v.abs() < 1e-4) {
        format!("{v:.6e}")
    } else {
        let s = format!("{v:.6}");
        if s.starts_with("-0.000000") {
            "0.000000".to_owned()
        } else {
            s
        }
    }
}

fn complex(re: f64, im: f64) -> String {
    if im.abs() <= 1e-12 * re.abs().max(1e-300) || im == 0.0 {
        number(re)
    } else if im < 0.0 {
        format!("{} − {}i", number(re), number(-im))
    } else {
        format!("{} + {}i", number(re), number(im))
    }
}
