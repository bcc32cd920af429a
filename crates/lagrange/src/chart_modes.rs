//! The linearized dynamics about an equilibrium at a pole of the coordinates (the spherical
//! pendulum hanging at `θ = 0`), where `M₀` is singular and `K x = ω² M₀ x` has no meaning in
//! the model's coordinates: `M` and `K` of the Lagrangian in the regular chart of
//! `crate::chart` (`u + i v = (θ − θ*) e^(i α)`, the others kept), and the natural
//! frequencies and modes from them. The hanging spherical pendulum gets `ω² = g/ℓ` twice,
//! as every textbook has it.

use std::fmt::Write as _;

use mechanics::equilibria::Values;
use mechanics::Equations;
use serde_json::{json, Value};

use report::equilibria::six;

use crate::chart::{ChartLagrangian, Pole};

/// The linearization `M δs̈ + K δs = 0` in a pole's regular chart.
#[derive(Debug, Clone, PartialEq)]
pub struct ChartModes {
    /// The polar angle (at its pole) and the azimuth that moves nothing there.
    pub polar: String,
    /// See [`ChartModes::polar`].
    pub azimuth: String,
    /// The chart's coordinates: `u`, `v`, then the others (`β − c α` when they turn with α).
    pub chart: Vec<String>,
    /// `M` in the chart (positive definite where the chart is regular).
    pub mass: Vec<Vec<f64>>,
    /// `K` in the chart.
    pub stiffness: Vec<Vec<f64>>,
    /// `ω²` of `K x = ω² M x`, increasing.
    pub omega_squared: Vec<f64>,
    /// The mode of each `ω²` (normalized to `xᵀ M x = 1`), in the chart's coordinates.
    pub modes: Vec<Vec<f64>>,
}

impl ChartModes {
    /// `ω` of each mode (`None` where `ω² < 0`: no oscillation).
    #[must_use]
    pub fn frequencies(&self) -> Vec<Option<f64>> {
        let scale = self
            .omega_squared
            .iter()
            .fold(0.0_f64, |m, w| m.max(w.abs()));
        self.omega_squared
            .iter()
            .map(|w2| {
                let w2 = if w2.abs() <= 1e-9 * scale { 0.0 } else { *w2 };
                (w2 >= 0.0).then(|| w2.sqrt())
            })
            .collect()
    }
}

/// The chart linearization at the rest state `q`, when it is a pole of the coordinates and the
/// system conservative; `None` otherwise.
pub(crate) fn pole_modes(equations: &Equations, q: &[f64], values: &Values) -> Option<ChartModes> {
    if equations.generalized_forces().iter().any(|f| !f.is_zero()) {
        return None;
    }
    let pole = Pole::find(equations, q, values, &[])?;
    let chart = ChartLagrangian::new(equations, &pole, q, &[], values)?;
    // Two offsets, extrapolated (Richardson): the averaged differences err by O(offset²).
    let [coarse_mass, _, coarse_hessian] = chart.second_derivatives_at(OFFSET);
    let [fine_mass, _, fine_hessian] = chart.second_derivatives_at(OFFSET / 2.0);
    let mass = extrapolated(&coarse_mass, &fine_mass);
    let hessian = extrapolated(&coarse_hessian, &fine_hessian);
    // ℒ = K + U: the stiffness is minus the force function's Hessian.
    let stiffness: Vec<Vec<f64>> = hessian
        .iter()
        .map(|row| row.iter().map(|h| -h).collect())
        .collect();
    let eigen = numeric::eigen::symmetric_generalized(&stiffness, &mass).ok()?;
    let names = equations.coordinates();
    let mut coordinates = vec!["u".to_owned(), "v".to_owned()];
    coordinates.extend((2..q.len()).map(|i| chart.name(i, names)));
    Some(ChartModes {
        polar: names[pole.polar].clone(),
        azimuth: names[pole.alpha].clone(),
        chart: coordinates,
        mass,
        stiffness,
        omega_squared: eigen.values,
        modes: eigen.modes,
    })
}

/// The larger of the two offsets about the pole at which the chart's derivatives are taken.
const OFFSET: f64 = 2e-3;

/// `(4 fine − coarse) / 3`: the second-order error of the halved offset removed.
fn extrapolated(coarse: &[Vec<f64>], fine: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let rows = coarse.iter().zip(fine);
    rows.map(|(c, f)| c.iter().zip(f).map(|(c, f)| (4.0 * f - c) / 3.0).collect())
        .collect()
}

/// The text of one chart linearization, indented as `lagrange linearize` prints an
/// equilibrium's.
fn chart_text(modes: &ChartModes) -> String {
    let mut out = format!(
        "  at the pole of {} (where {} moves nothing): linearized in the regular chart ({}), \
         u + i v = ({} − {}₀) e^(i {}):\n",
        modes.polar,
        modes.azimuth,
        modes.chart.join(", "),
        modes.polar,
        modes.polar,
        modes.azimuth
    );
    for (name, matrix) in [("M0", &modes.mass), ("K0", &modes.stiffness)] {
        let rows: Vec<String> = matrix
            .iter()
            .map(|row| row.iter().map(|v| six(*v)).collect::<Vec<_>>().join(", "))
            .collect();
        let _ = writeln!(out, "  {name} (chart) = [{}]", rows.join("; "));
    }
    let frequencies: Vec<String> = modes
        .frequencies()
        .iter()
        .zip(&modes.omega_squared)
        .map(|(w, w2)| match w {
            Some(w) => format!("{} rad/s", six(*w)),
            None => format!("none (ω² = {})", six(*w2)),
        })
        .collect();
    let _ = writeln!(out, "  natural frequencies: {}", frequencies.join(", "));
    for (k, mode) in modes.modes.iter().enumerate() {
        let entries: Vec<String> = mode.iter().map(|v| six(*v)).collect();
        let _ = writeln!(
            out,
            "  mode {} in the chart: ({})",
            k + 1,
            entries.join(", ")
        );
    }
    out
}

/// `text` (the linearizations as `lagrange linearize` prints them) with each pole's chart
/// linearization beneath its equilibrium's "not linearized" line.
pub(crate) fn with_chart_modes(text: &str, modes: &[Option<ChartModes>]) -> String {
    let marker = |line: &str| line.starts_with("  not linearized");
    beneath(text, modes, marker, chart_text)
}

/// `text`, a listing of equilibria (`#k: …` opens the k-th), with `render(item k)` inserted
/// after the k-th equilibrium's lines that `marker` picks.
pub(crate) fn beneath<T>(
    text: &str,
    items: &[Option<T>],
    marker: impl Fn(&str) -> bool,
    render: impl Fn(&T) -> String,
) -> String {
    let mut out = String::with_capacity(text.len());
    let mut current: Option<usize> = None;
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix('#') {
            current = rest.split(':').next().and_then(|k| k.parse().ok());
        }
        out.push_str(line);
        out.push('\n');
        let item = current.and_then(|k| items.get(k)).and_then(Option::as_ref);
        if let (Some(item), true) = (item, marker(line)) {
            out.push_str(&render(item));
        }
    }
    out
}

/// The chart linearizations as JSON (docs/json.md): one entry per equilibrium at a pole.
pub(crate) fn chart_modes_json(modes: &[Option<ChartModes>], only: Option<usize>) -> Value {
    let entries: Vec<Value> = modes
        .iter()
        .enumerate()
        .filter(|(i, _)| only.is_none_or(|k| k == *i))
        .filter_map(|(i, m)| {
            let m = m.as_ref()?;
            Some(json!({
                "equilibrium": i,
                "polar": m.polar,
                "azimuth": m.azimuth,
                "chart": m.chart,
                "M0": m.mass,
                "K0": m.stiffness,
                "omega_squared": m.omega_squared,
                "frequencies": m.frequencies(),
                "modes": m.modes,
            }))
        })
        .collect();
    Value::Array(entries)
}
