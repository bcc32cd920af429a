//! The bifurcation diagram of `lagrange equilibria --sweep P=a..b --plot FILE`: every
//! equilibrium coordinate against the swept parameter, one panel per coordinate, stable
//! equilibria as filled dots, unstable ones as open circles, undecided ones as grey crosses.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::plot::{bounds, register_font, PlotError, FAMILY};

/// One equilibrium at one parameter value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BifurcationPoint {
    /// The parameter's value.
    pub parameter: f64,
    /// Which coordinate (index into the names).
    pub coordinate: usize,
    /// The coordinate's value at the equilibrium.
    pub value: f64,
    /// Stable, unstable, or undecided.
    pub stable: Option<bool>,
}

/// Draws the diagram; SVG or PNG by the file's extension.
///
/// # Errors
/// A [`PlotError`] for a wrong extension, nothing to draw, or a drawing failure.
pub fn plot_bifurcation(
    path: &Path,
    parameter: &str,
    coordinates: &[String],
    points: &[BifurcationPoint],
) -> Result<(), PlotError> {
    register_font();
    let name = path.display().to_string();
    let drawing = |e: &dyn std::fmt::Display| PlotError::Drawing {
        path: name.clone(),
        message: e.to_string(),
    };
    if points.is_empty() || coordinates.is_empty() {
        return Err(PlotError::NoData);
    }
    let size = (
        900,
        320 * u32::try_from(coordinates.len().min(6)).unwrap_or(1) + 60,
    );
    match path.extension().and_then(|e| e.to_str()) {
        Some(ext) if ext.eq_ignore_ascii_case("svg") => {
            let root = SVGBackend::new(path, size).into_drawing_area();
            draw(&root, parameter, coordinates, points).map_err(|e| drawing(&e))?;
            root.present().map_err(|e| drawing(&e))
        }
        Some(ext) if ext.eq_ignore_ascii_case("png") => {
            let root = BitMapBackend::new(path, size).into_drawing_area();
            draw(&root, parameter, coordinates, points).map_err(|e| drawing(&e))?;
            root.present().map_err(|e| drawing(&e))
        }
        _ => Err(PlotError::Format { path: name }),
    }
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    parameter: &str,
    coordinates: &[String],
    points: &[BifurcationPoint],
) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let root = root.titled(&format!("equilibria against {parameter}"), (FAMILY, 24))?;
    let shown = coordinates.len().min(6);
    let panels = root.split_evenly((shown, 1));
    let x_range = bounds(points.iter().map(|p| p.parameter));
    for (k, panel) in panels.iter().enumerate() {
        let mine: Vec<&BifurcationPoint> = points.iter().filter(|p| p.coordinate == k).collect();
        let y_range = bounds(mine.iter().map(|p| p.value));
        let mut chart = ChartBuilder::on(panel)
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)?;
        chart
            .configure_mesh()
            .x_desc(parameter)
            .y_desc(coordinates[k].as_str())
            .label_style((FAMILY, 14))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()?;
        let stable = RGBColor(31, 119, 180);
        let unstable = RGBColor(214, 39, 40);
        chart
            .draw_series(
                mine.iter()
                    .filter(|p| p.stable == Some(true))
                    .map(|p| Circle::new((p.parameter, p.value), 4, stable.filled())),
            )?
            .label("stable")
            .legend(move |(x, y)| Circle::new((x + 10, y), 4, stable.filled()));
        chart
            .draw_series(
                mine.iter()
                    .filter(|p| p.stable == Some(false))
                    .map(|p| Circle::new((p.parameter, p.value), 4, unstable.stroke_width(2))),
            )?
            .label("unstable")
            .legend(move |(x, y)| Circle::new((x + 10, y), 4, unstable.stroke_width(2)));
        chart
            .draw_series(
                mine.iter()
                    .filter(|p| p.stable.is_none())
                    .map(|p| Cross::new((p.parameter, p.value), 4, RGBColor(140, 140, 140))),
            )?
            .label("undecided")
            .legend(|(x, y)| Cross::new((x + 10, y), 4, RGBColor(140, 140, 140)));
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(200, 200, 200))
            .label_font((FAMILY, 14))
            .draw()?;
    }
    Ok(())
}
