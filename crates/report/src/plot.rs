//! Plots of a simulation run, with `plotters`: time histories of the coordinates, the model's
//! outputs ([`PlotExtras`]), phase portraits (`q` against `q̇`), and the energy error — or,
//! when inputs do work, the energy balance — with the constraint drift when there are
//! constraints, in one figure. SVG or PNG, chosen by the file's extension. The text uses the
//! bundled DejaVu Sans (assets/fonts, with its licence), so no system font is needed.

use std::path::Path;
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;

/// Why a plot could not be written.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PlotError {
    /// The extension is neither `.svg` nor `.png`.
    #[error("cannot plot to `{path}`: the file name must end in .svg or .png")]
    Format {
        /// The path.
        path: String,
    },
    /// The columns are not those of a run (`t`, coordinates, rates, energy error, drift).
    #[error("the run has no coordinate columns to plot")]
    NoData,
    /// Drawing or writing failed.
    #[error("cannot draw `{path}`: {message}")]
    Drawing {
        /// The path.
        path: String,
        /// What the backend said.
        message: String,
    },
}

static FONT: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");
pub(crate) const FAMILY: &str = "sans-serif";
const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

pub(crate) fn register_font() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        // The bundled font is valid TrueType; should registration fail anyway, text falls back
        // to plotters' behaviour (no text) rather than the plot failing.
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, FONT);
    });
}

/// A quantity the model asks to record (`output tip_height = …`), along a run.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputSeries {
    /// Its label as the model writes it.
    pub label: String,
    /// Its unit when the model's geometry says it (`m` for a height), else `None`.
    pub unit: Option<&'static str>,
    /// Its value at each row of the run (NaN where it does not evaluate).
    pub values: Vec<f64>,
}

/// What a solution's plot shows beside the run's own columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlotExtras {
    /// The model's scalar outputs, in a panel of their own under the coordinates.
    pub outputs: Vec<OutputSeries>,
    /// When inputs and non-conservative forces do work: at each row the energy balance
    /// `(E − E₀ − W)/|E₀|` (`W` their work since the start; `|E₀|` taken as 1 when `E₀` is
    /// 0), plotted instead of the relative energy error, which is then the work done.
    pub balance: Option<Vec<f64>>,
    /// Reactions, one per name, whose values each row carries after the run's columns (the
    /// columns `lagrange simulate` writes for the model's `reactions`, docs/reactions.md), in
    /// a panel of their own at the bottom.
    pub reactions: Vec<String>,
}

/// [`plot_run`] with a panel of reactions below (none when `reactions` is empty).
///
/// # Errors
/// As [`plot_run`].
pub fn plot_run_with_reactions(
    path: &Path,
    title: &str,
    columns: &[String],
    reactions: &[String],
    rows: &[Vec<f64>],
) -> Result<(), PlotError> {
    let extras = PlotExtras {
        reactions: reactions.to_vec(),
        ..PlotExtras::default()
    };
    plot_run_with(path, title, columns, rows, &extras)
}

/// Draws the run: `columns` as written by `lagrange simulate` (`t`, the n coordinates, the n
/// rates `q_d`, `energy_error`, `constraint_drift`), `rows` the data.
///
/// # Errors
/// A [`PlotError`] for a wrong extension, no data, or a drawing failure.
pub fn plot_run(
    path: &Path,
    title: &str,
    columns: &[String],
    rows: &[Vec<f64>],
) -> Result<(), PlotError> {
    plot_run_with(path, title, columns, rows, &PlotExtras::default())
}

/// [`plot_run`] with the model's outputs in a panel of their own and, when inputs do work, the
/// energy balance in place of the energy error ([`PlotExtras`]).
///
/// # Errors
/// As [`plot_run`].
pub fn plot_run_with(
    path: &Path,
    title: &str,
    columns: &[String],
    rows: &[Vec<f64>],
    extras: &PlotExtras,
) -> Result<(), PlotError> {
    register_font();
    let name = path.display().to_string();
    let drawing = |e: &dyn std::fmt::Display| PlotError::Drawing {
        path: name.clone(),
        message: e.to_string(),
    };
    if columns.len() < 5 || rows.is_empty() {
        return Err(PlotError::NoData);
    }
    let n = (columns.len() - 3) / 2;
    let reactions = Reactions {
        names: &extras.reactions,
        first: columns.len(),
    };
    let plot = Plot {
        title,
        columns,
        rows,
        n,
        extras,
        reactions,
    };
    let outputs = if extras.outputs.is_empty() { 0 } else { 300 };
    let reaction_panel = if extras.reactions.is_empty() { 0 } else { 360 };
    let size = (1200, 900 + outputs + reaction_panel);
    match path.extension().and_then(|e| e.to_str()) {
        Some(ext) if ext.eq_ignore_ascii_case("svg") => {
            let root = SVGBackend::new(path, size).into_drawing_area();
            draw(&root, &plot).map_err(|e| drawing(&e))?;
            root.present().map_err(|e| drawing(&e))
        }
        Some(ext) if ext.eq_ignore_ascii_case("png") => {
            let root = BitMapBackend::new(path, size).into_drawing_area();
            draw(&root, &plot).map_err(|e| drawing(&e))?;
            root.present().map_err(|e| drawing(&e))
        }
        _ => Err(PlotError::Format { path: name }),
    }
}

/// The reaction columns of the rows: their names, and where the first one is in a row.
struct Reactions<'a> {
    names: &'a [String],
    first: usize,
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// What one figure draws.
struct Plot<'a> {
    title: &'a str,
    columns: &'a [String],
    rows: &'a [Vec<f64>],
    n: usize,
    extras: &'a PlotExtras,
    reactions: Reactions<'a>,
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, plot: &Plot<'_>) -> DrawResult<DB> {
    let (columns, rows, n) = (plot.columns, plot.rows, plot.n);
    root.fill(&WHITE)?;
    let root = root.titled(plot.title, (FAMILY, 26))?;
    let root = if plot.reactions.names.is_empty() {
        root
    } else {
        let height = root.dim_in_pixel().1;
        let (upper, lower) = root.split_vertically(height.saturating_sub(360));
        draw_reactions(&lower, rows, &plot.reactions)?;
        upper
    };
    let (top, bottom) = root.split_vertically(480);
    let bottom = if plot.extras.outputs.is_empty() {
        bottom
    } else {
        let (outputs, rest) = bottom.split_vertically(300);
        draw_outputs(&outputs, rows, &plot.extras.outputs)?;
        rest
    };
    let (phase, energy_panel) = bottom.split_horizontally(600);
    draw_histories(&top, columns, rows, n)?;
    draw_portraits(&phase, rows, n)?;
    draw_energy(&energy_panel, rows, n, plot.extras.balance.as_deref())
}

/// The model's outputs against time, each labelled with its unit; the axis names the unit
/// when there is one output or they share it.
fn draw_outputs<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    rows: &[Vec<f64>],
    outputs: &[OutputSeries],
) -> DrawResult<DB> {
    let t_range = time_range(rows);
    let series: Vec<Vec<(f64, f64)>> = outputs
        .iter()
        .map(|o| {
            rows.iter()
                .zip(&o.values)
                .map(|(r, v)| (r[0], *v))
                .filter(|(_, v)| v.is_finite())
                .collect()
        })
        .collect();
    let (lo, hi) = bounds(series.iter().flatten().map(|p| p.1));
    let with_unit = |o: &OutputSeries| match o.unit {
        Some(u) => format!("{} ({u})", o.label),
        None => o.label.clone(),
    };
    let axis = match outputs {
        [one] => with_unit(one),
        [first, ..] if outputs.iter().all(|o| o.unit == first.unit) && first.unit.is_some() => {
            format!("outputs ({})", first.unit.unwrap_or_default())
        }
        _ => "outputs (units as labelled)".to_owned(),
    };
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .caption("outputs of the model", (FAMILY, 20))
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(t_range.0..t_range.1, lo..hi)?;
    let (t_span, y_span) = (t_range.1 - t_range.0, hi - lo);
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc(axis)
        .x_label_formatter(&|v| tick(*v, t_span))
        .y_label_formatter(&|v| tick(*v, y_span))
        .label_style((FAMILY, 14))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    for (k, (points, output)) in series.iter().zip(outputs).enumerate() {
        let color = PALETTE[(k + 3) % PALETTE.len()];
        chart
            .draw_series(LineSeries::new(
                points.iter().copied(),
                color.stroke_width(1),
            ))?
            .label(with_unit(output))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(1))
            });
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font((FAMILY, 15))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(200, 200, 200))
        .draw()?;
    Ok(())
}

/// A column's name as the report writes it: `theta` → `θ`, `phi1_d` → `φ̇1`.
fn display_name(column: &str) -> String {
    let (name, order) = match column.strip_suffix("_d") {
        Some(q) => (q, 1),
        None => (column, 0),
    };
    cas::print::to_unicode(if order == 0 {
        cas::Expr::coordinate(name)
    } else {
        cas::Expr::rate(name, 1)
    })
}

/// A tick label: decimals enough for ticks about `span / 10` apart, and never `-0` or `-0.0`.
fn tick(v: f64, span: f64) -> String {
    let step = (span / 10.0).abs();
    let decimals = if step > 0.0 && step.is_finite() {
        usize::try_from((-step.log10().floor()).max(0.0) as i64)
            .unwrap_or(0)
            .min(8)
    } else {
        1
    };
    let text = format!("{v:.decimals$}");
    if text
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        text.trim_start_matches('-').to_string()
    } else {
        text.replace('-', "−")
    }
}

/// The column `k` against time, finite values only.
fn series(rows: &[Vec<f64>], k: usize) -> Vec<(f64, f64)> {
    rows.iter()
        .map(|r| (r[0], r[k]))
        .filter(|(_, y)| y.is_finite())
        .collect()
}

/// The time range of the rows.
fn time_range(rows: &[Vec<f64>]) -> (f64, f64) {
    bounds(rows.iter().map(|r| r[0]))
}

/// Time histories of the coordinates.
fn draw_histories<DB: DrawingBackend>(
    top: &DrawingArea<DB, Shift>,
    columns: &[String],
    rows: &[Vec<f64>],
    n: usize,
) -> DrawResult<DB> {
    let lines: Vec<Vec<(f64, f64)>> = (1..=n).map(|k| series(rows, k)).collect();
    let names: Vec<String> = (1..=n).map(|k| display_name(&columns[k])).collect();
    let panel = LinesPanel {
        caption: "coordinates",
        y_desc: "q (lengths in m, angles in rad)",
        lines: &lines,
        names: &names,
    };
    draw_lines(top, time_range(rows), &panel)
}

/// Lines against time on one panel, with their names in a legend.
struct LinesPanel<'a> {
    caption: &'a str,
    y_desc: &'a str,
    lines: &'a [Vec<(f64, f64)>],
    names: &'a [String],
}

/// Draws `panel`'s lines over `t_range`, the legend in a corner (not over the middle of the
/// curves).
fn draw_lines<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    t_range: (f64, f64),
    panel: &LinesPanel<'_>,
) -> DrawResult<DB> {
    let (lo, hi) = bounds(panel.lines.iter().flatten().map(|p| p.1));
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .caption(panel.caption, (FAMILY, 20))
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(t_range.0..t_range.1, lo..hi)?;
    let (t_span, y_span) = (t_range.1 - t_range.0, hi - lo);
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc(panel.y_desc)
        .x_label_formatter(&|v| tick(*v, t_span))
        .y_label_formatter(&|v| tick(*v, y_span))
        .label_style((FAMILY, 14))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    for (k, (points, name)) in panel.lines.iter().zip(panel.names).enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        chart
            .draw_series(LineSeries::new(
                points.iter().copied(),
                color.stroke_width(1),
            ))?
            .label(name.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(1))
            });
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font((FAMILY, 15))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(200, 200, 200))
        .draw()?;
    Ok(())
}

/// Phase portraits q against q̇.
fn draw_portraits<DB: DrawingBackend>(
    phase: &DrawingArea<DB, Shift>,
    rows: &[Vec<f64>],
    n: usize,
) -> DrawResult<DB> {
    let portraits: Vec<Vec<(f64, f64)>> = (1..=n)
        .map(|k| {
            rows.iter()
                .map(|r| (r[k], r[n + k]))
                .filter(|(a, b)| a.is_finite() && b.is_finite())
                .collect()
        })
        .collect();
    let x = bounds(portraits.iter().flatten().map(|p| p.0));
    let y = bounds(portraits.iter().flatten().map(|p| p.1));
    let mut chart = ChartBuilder::on(phase)
        .margin(12)
        .caption("phase portraits (q, dq/dt)", (FAMILY, 20))
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)?;
    let (x_span, y_span) = (x.1 - x.0, y.1 - y.0);
    chart
        .configure_mesh()
        .x_desc("q")
        .y_desc("dq/dt")
        .x_label_formatter(&|v| tick(*v, x_span))
        .y_label_formatter(&|v| tick(*v, y_span))
        .label_style((FAMILY, 14))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    for (k, points) in portraits.iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        chart.draw_series(LineSeries::new(
            points.iter().copied(),
            color.stroke_width(1),
        ))?;
    }

    Ok(())
}

/// The energy error (or, when inputs do work, the energy balance), and the constraint drift
/// when constrained.
fn draw_energy<DB: DrawingBackend>(
    panel: &DrawingArea<DB, Shift>,
    rows: &[Vec<f64>],
    n: usize,
    balance: Option<&[f64]>,
) -> DrawResult<DB> {
    let t_range = time_range(rows);
    let energy = match balance {
        Some(b) => rows
            .iter()
            .zip(b)
            .map(|(r, v)| (r[0], *v))
            .filter(|(_, v)| v.is_finite())
            .collect(),
        None => series(rows, 2 * n + 1),
    };
    let (what, label) = if balance.is_some() {
        (
            "energy balance (E − E₀ − W)/|E₀|",
            "E − E₀ − W of the inputs",
        )
    } else {
        ("relative energy error", "energy error")
    };
    let drift = series(rows, 2 * n + 2);
    let constrained = drift.iter().any(|p| p.1 != 0.0);
    let values = energy
        .iter()
        .map(|p| p.1)
        .chain(drift.iter().filter(|_| constrained).map(|p| p.1));
    let (lo, hi) = bounds(values);
    let mut chart = ChartBuilder::on(panel)
        .margin(12)
        .caption(
            if constrained {
                format!("{what} and constraint drift")
            } else {
                what.to_owned()
            },
            (FAMILY, 20),
        )
        .x_label_area_size(40)
        .y_label_area_size(90)
        .build_cartesian_2d(t_range.0..t_range.1, lo..hi)?;
    let t_span = t_range.1 - t_range.0;
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .x_label_formatter(&|v| tick(*v, t_span))
        .y_label_formatter(&|v| {
            // Ticks that are zero up to rounding print as 0, not 2.6e-26.
            if v.abs() < 1e-9 * (hi - lo) {
                "0".to_owned()
            } else {
                format!("{v:.1e}")
            }
        })
        .label_style((FAMILY, 14))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    chart
        .draw_series(LineSeries::new(
            energy.iter().copied(),
            PALETTE[0].stroke_width(1),
        ))?
        .label(label)
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], PALETTE[0].stroke_width(1)));
    if constrained {
        chart
            .draw_series(LineSeries::new(
                drift.iter().copied(),
                PALETTE[1].stroke_width(1),
            ))?
            .label("constraint drift")
            .legend(|(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], PALETTE[1].stroke_width(1))
            });
        chart
            .configure_series_labels()
            .label_font((FAMILY, 15))
            .background_style(WHITE.mix(0.85))
            .draw()?;
    }
    Ok(())
}

/// The reactions against time (evaluated numerically at each row's state), one line each.
fn draw_reactions<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    rows: &[Vec<f64>],
    reactions: &Reactions<'_>,
) -> DrawResult<DB> {
    let lines: Vec<Vec<(f64, f64)>> = (0..reactions.names.len())
        .map(|k| {
            rows.iter()
                .filter_map(|r| Some((r[0], *r.get(reactions.first + k)?)))
                .filter(|(_, y)| y.is_finite())
                .collect()
        })
        .collect();
    let panel = LinesPanel {
        caption: "reactions (inertial components, multipliers)",
        y_desc: "N, N·m, or λ",
        lines: &lines,
        names: reactions.names,
    };
    draw_lines(area, time_range(rows), &panel)
}

/// The range of the finite values, widened by 5% (and to a unit range around a constant) so
/// lines do not run along the frame.
pub(crate) fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return (-1.0, 1.0);
    }
    let span = hi - lo;
    if span <= 1e-300 + 1e-12 * lo.abs().max(hi.abs()) {
        let pad = if lo == 0.0 { 1.0 } else { 0.5 * lo.abs() };
        return (lo - pad, hi + pad);
    }
    (lo - 0.05 * span, hi + 0.05 * span)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_never_read_minus_zero() {
        assert_eq!(tick(-0.0, 1.0), "0.0");
        assert_eq!(tick(-0.00001, 1.0), "0.0");
        assert_eq!(tick(-0.25, 1.0), "−0.2");
        assert_eq!(tick(3.0, 10.0), "3");
        assert_eq!(tick(0.05, 0.1), "0.05");
    }

    #[test]
    fn legends_name_the_coordinates_as_the_report_does() {
        assert_eq!(display_name("theta"), "θ");
        assert_eq!(display_name("x"), "x");
        assert_eq!(display_name("phi1_d"), "φ̇1");
    }

    #[test]
    fn a_plot_has_units_unicode_names_and_no_minus_zero() {
        let path = std::env::temp_dir().join(format!("lagrange-plot-{}.svg", std::process::id()));
        let columns: Vec<String> = [
            "t",
            "x",
            "theta",
            "x_d",
            "theta_d",
            "energy_error",
            "constraint_drift",
        ]
        .iter()
        .map(|s| (*s).to_string())
        .collect();
        let rows: Vec<Vec<f64>> = (0..200)
            .map(|i| {
                let t = f64::from(i) * 0.05;
                vec![
                    t,
                    0.1 * t.cos(),
                    0.3 * (2.0 * t).sin(),
                    -0.1 * t.sin(),
                    0.6 * (2.0 * t).cos(),
                    1e-9 * t,
                    0.0,
                ]
            })
            .collect();
        plot_run(&path, "test", &columns, &rows).expect("plotted");
        // The backend writes each text on a line of its own between its tags.
        let svg = std::fs::read_to_string(&path)
            .expect("written")
            .replace('\n', "");
        let _ = std::fs::remove_file(&path);
        assert!(svg.contains(">θ<"), "no θ in the legend");
        assert!(
            svg.contains("angles in rad"),
            "no unit on the coordinates axis"
        );
        assert!(
            !svg.contains(">-0.0<") && !svg.contains(">-0<") && !svg.contains(">−0.0<"),
            "a minus zero tick"
        );
    }
}
