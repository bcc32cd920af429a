//! What a solution's simulation figure shows beside the run's columns
//! ([`report::PlotExtras`]): the model's scalar `output` quantities along the run, and — when
//! inputs and non-conservative forces do work — the energy balance `E − E₀ − W`, with `W` the
//! integral of their power `P = Σ_j Q_j q̇_j` along the rows of the dense output.
//!
//! The balance replaces the relative energy error where that error is mostly the work done (a
//! driving torque's 30 %, not the integrator's): `dE/dt = Σ_j Q_j q̇_j` for `E = K + V` when
//! nothing depends on time explicitly, so `E − E₀ − W` stays at the integrator's error plus
//! the quadrature's. `W` is integrated by piecewise cubics through consecutive rows (fourth
//! order in the row spacing; a solution's rows are a thousand per run).

use cas::{Expr, Symbol};
use mechanics::Equations;
use model::{ExprKind, Function, Model, Quantity, State, Type};
use numeric::Tape;
use report::{OutputSeries, PlotExtras};

use crate::simulate::Run;
use crate::Analysis;

impl Analysis {
    /// The outputs and the energy balance for the figure of `run`, and the balance and work
    /// at its last row for the section's sentence.
    pub(crate) fn plot_extras(&self, run: &Run) -> (PlotExtras, Option<(f64, f64)>) {
        let outputs = self.output_series(run);
        let balance = self.energy_balance(run);
        let last = balance
            .as_ref()
            .and_then(|(b, w)| Some((*b.last()?, *w.last()?)));
        let extras = PlotExtras {
            outputs,
            balance: balance.map(|(b, _)| b),
            reactions: Vec::new(),
        };
        (extras, last)
    }

    /// The model's scalar outputs other than a bare coordinate or rate (those are plotted
    /// already), evaluated at each row.
    fn output_series(&self, run: &Run) -> Vec<OutputSeries> {
        let Some(source) = self.source() else {
            return Vec::new();
        };
        let model = &source.model;
        let wanted: Vec<(&str, &model::Expr)> = model
            .outputs()
            .iter()
            .filter_map(|o| match &o.quantity {
                Quantity::Expr(e)
                    if e.ty == Type::Scalar
                        && !matches!(e.kind, ExprKind::Coordinate(_) | ExprKind::Rate(_)) =>
                {
                    Some((o.label.as_str(), e))
                }
                _ => None,
            })
            .collect();
        if wanted.is_empty() {
            return Vec::new();
        }
        let (Ok(values), Ok(equations)) = (self.values(), self.equations()) else {
            return Vec::new();
        };
        let states: Vec<(Vec<f64>, Vec<f64>)> = run
            .rows
            .iter()
            .map(|row| model_state(model, equations, &values, &run.columns, row))
            .collect();
        wanted
            .into_iter()
            .map(|(label, e)| OutputSeries {
                label: label.to_string(),
                unit: is_length(e).then_some("m"),
                values: run
                    .rows
                    .iter()
                    .zip(&states)
                    .map(|(row, (q, qd))| {
                        let at = State {
                            time: row[0],
                            coordinates: q,
                            rates: qd,
                        };
                        model
                            .evaluate(e, &at)
                            .ok()
                            .and_then(model::Value::scalar)
                            .unwrap_or(f64::NAN)
                    })
                    .collect(),
            })
            .collect()
    }

    /// `(E − E₀ − W)/|E₀|` and `W` at each row, when inputs or non-conservative forces do work
    /// and `E = K + V` is the energy the run monitors with nothing depending on time
    /// explicitly; `None` otherwise, or when a value is missing.
    fn energy_balance(&self, run: &Run) -> Option<(Vec<f64>, Vec<f64>)> {
        let equations = self.equations().ok()?;
        let (energy, power) = energy_and_power(equations)?;
        let values = self.values().ok()?;
        let fixed: Vec<(Expr, Expr)> = values
            .iter()
            .map(|(n, v)| (Expr::symbol(n), Expr::float(*v)))
            .collect();
        let timed: Vec<(Expr, Expr)> = self
            .timed_inputs()
            .iter()
            .map(|(n, v)| (Expr::symbol(n), *v))
            .collect();
        let numeric = |e: Expr| e.subs(&timed).subs(&fixed).normal();
        let mut symbols: Vec<Symbol> = Vec::new();
        let mut positions = Vec::new();
        for (k, column) in run.columns.iter().enumerate() {
            let symbol = match column.strip_suffix("_d") {
                Some(q) => Expr::rate(q, 1),
                None if k == 0 => Expr::time(),
                None => Expr::coordinate(column),
            };
            if let Some(s) = symbol.as_symbol() {
                symbols.push(s);
                positions.push(k);
            }
        }
        let tape = Tape::compile(&[numeric(energy), numeric(power)], &symbols).ok()?;
        let mut registers = tape.registers();
        let mut inputs = vec![0.0; symbols.len()];
        let mut out = [0.0; 2];
        let mut at = |row: &[f64]| {
            for (slot, k) in inputs.iter_mut().zip(&positions) {
                *slot = row.get(*k).copied().unwrap_or(f64::NAN);
            }
            tape.eval(&inputs, &mut registers, &mut out);
            out
        };
        let (mut e, mut p) = (Vec::new(), Vec::new());
        for row in &run.rows {
            let [energy, power] = at(row);
            e.push(energy);
            p.push(power);
        }
        let times: Vec<f64> = run.rows.iter().map(|r| r[0]).collect();
        let work = cumulative_integral(&times, &p);
        let e0 = *e.first()?;
        let scale = if e0.abs() < 1e-12 { 1.0 } else { e0.abs() };
        let balance = e
            .iter()
            .zip(&work)
            .map(|(e, w)| (e - e0 - w) / scale)
            .collect();
        Some((balance, work))
    }
}

/// The model's coordinates and rates at a row: the integrated ones from their columns,
/// those eliminated by a constraint from their values there (a driven coordinate has no
/// column: its entry, 0, is ignored by the evaluation).
fn model_state(
    model: &Model,
    equations: &Equations,
    values: &[(String, f64)],
    columns: &[String],
    row: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let column = |name: &str| columns.iter().position(|c| c == name).map(|k| row[k]);
    let lookup = |s: Symbol| {
        let name = s.name();
        match s.kind() {
            cas::SymbolKind::TimeFunction { order: 0 } => column(name),
            cas::SymbolKind::TimeFunction { order: 1 } => column(&format!("{name}_d")),
            _ if Expr::time().as_symbol() == Some(s) => Some(row[0]),
            _ => values.iter().find(|(n, _)| n == name).map(|(_, v)| *v),
        }
    };
    let mut q = Vec::new();
    let mut qd = Vec::new();
    for c in model.coordinates() {
        let name = c.name.name.as_str();
        let eliminated = equations.eliminated().iter().find(|e| e.coordinate == name);
        let (value, rate) = match eliminated {
            Some(e) => (e.value.eval(&lookup).ok(), e.value.dt().eval(&lookup).ok()),
            None => (column(name), column(&format!("{name}_d"))),
        };
        q.push(value.unwrap_or(0.0));
        qd.push(rate.unwrap_or(0.0));
    }
    (q, qd)
}

/// `K + V` and the power `Σ_j Q_j q̇_j` of the generalized forces, when that power is not
/// identically zero, the run monitors `K + V` (no conserved energy-like integral) and neither
/// the Lagrangian nor a constraint kept with multipliers depends on time explicitly (then
/// `dE/dt` is the power).
fn energy_and_power(equations: &Equations) -> Option<(Expr, Expr)> {
    if equations
        .first_integrals()
        .iter()
        .any(|f| f.coordinate.is_none())
    {
        return None;
    }
    let time = Expr::time().as_symbol()?;
    let timed = |e: &Expr| !e.diff(time).is_zero();
    if timed(&equations.lagrangian())
        || equations.constraint_matrix().iter().flatten().any(timed)
        || equations.constraint_rhs().iter().any(timed)
    {
        return None;
    }
    let power = Expr::add_all(
        equations
            .coordinates()
            .iter()
            .zip(equations.generalized_forces())
            .map(|(q, f)| *f * Expr::rate(q, 1)),
    )
    .normal();
    if power.is_zero() {
        return None;
    }
    let energy = (equations.kinetic_energy() + equations.potential_energy()).normal();
    Some((energy, power))
}

/// `∫ f dt` from the first time to each: on each interval, the integral of the cubic through
/// the four samples around it (fewer near the ends of a short run), by three-point Gauss–Legendre
/// (exact for it). Fourth order in the spacing.
fn cumulative_integral(times: &[f64], values: &[f64]) -> Vec<f64> {
    let n = times.len().min(values.len());
    let mut out = Vec::with_capacity(n);
    let mut total = 0.0;
    out.extend(times.first().map(|_| 0.0));
    let width = n.min(4);
    for i in 1..n {
        // The window of `width` samples that holds the interval [i − 1, i], centred on it.
        let start = (i - 1).saturating_sub(1).min(n - width);
        let window = start..start + width;
        total += interval_integral(
            &times[window.clone()],
            &values[window],
            times[i - 1],
            times[i],
        );
        out.push(total);
    }
    out
}

/// `∫_from^to` of the polynomial through the samples (Lagrange's form, at most a cubic), by
/// three-point Gauss–Legendre; the trapezoid when two sample times coincide.
fn interval_integral(t: &[f64], f: &[f64], from: f64, to: f64) -> f64 {
    let distinct = t
        .iter()
        .enumerate()
        .all(|(j, a)| t.iter().skip(j + 1).all(|b| a != b));
    if !distinct {
        let (fa, fb) = (f[0], f[f.len() - 1]);
        return 0.5 * (fa + fb) * (to - from);
    }
    let interpolant = |x: f64| -> f64 {
        (0..t.len())
            .map(|j| {
                let basis: f64 = (0..t.len())
                    .filter(|&k| k != j)
                    .map(|k| (x - t[k]) / (t[j] - t[k]))
                    .product();
                f[j] * basis
            })
            .sum()
    };
    let (mid, half) = (0.5 * (from + to), 0.5 * (to - from));
    let node = (0.6_f64).sqrt();
    half * (5.0 * interpolant(mid - half * node)
        + 8.0 * interpolant(mid)
        + 5.0 * interpolant(mid + half * node))
        / 9.0
}

/// Whether a scalar output is a length by the model's geometry: a point's coordinate
/// (`dot(A + L*B.y, N.y)`), a distance (`norm(P - Q)`), a sum with such a term.
fn is_length(e: &model::Expr) -> bool {
    length_kind(e) == Some(Dimension::Length)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Dimension {
    /// A position, a distance.
    Length,
    /// A unit vector, a number.
    Pure,
}

/// The dimension of `e` when the geometry says it, `None` when it does not (a parameter, a
/// coordinate).
fn length_kind(e: &model::Expr) -> Option<Dimension> {
    use model::ast::BinaryOp;
    match &e.kind {
        ExprKind::Point(_) => Some(Dimension::Length),
        ExprKind::UnitVector { .. } | ExprKind::Number { .. } | ExprKind::Pi => {
            Some(Dimension::Pure)
        }
        ExprKind::Neg(x) => length_kind(x),
        ExprKind::Binary { op, lhs, rhs } => match op {
            // Terms of a sum share their dimension: one length makes the sum one.
            BinaryOp::Add | BinaryOp::Sub => {
                let (a, b) = (length_kind(lhs), length_kind(rhs));
                if a == Some(Dimension::Length) || b == Some(Dimension::Length) {
                    Some(Dimension::Length)
                } else {
                    a.and(b)
                }
            }
            BinaryOp::Mul => product(length_kind(lhs), length_kind(rhs)),
            // Over a pure number only: a length over a length, or a number over one, is not.
            BinaryOp::Div => match length_kind(rhs) {
                Some(Dimension::Pure) => length_kind(lhs),
                _ => None,
            },
            _ => None,
        },
        ExprKind::Call { function, args } => match (function, args.as_slice()) {
            (Function::Dot, [a, b]) => product(length_kind(a), length_kind(b)),
            (Function::Norm | Function::Abs, [a]) => length_kind(a),
            _ => None,
        },
        _ => None,
    }
}

/// The dimension of a product (or quotient by a pure number): a length times pure numbers.
fn product(a: Option<Dimension>, b: Option<Dimension>) -> Option<Dimension> {
    match (a?, b?) {
        (Dimension::Pure, Dimension::Pure) => Some(Dimension::Pure),
        (Dimension::Length, Dimension::Pure) | (Dimension::Pure, Dimension::Length) => {
            Some(Dimension::Length)
        }
        (Dimension::Length, Dimension::Length) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::{run_sampled, SimulationOptions};

    #[test]
    fn the_work_integral_is_fourth_order() {
        // ∫₀ᵗ sin = 1 − cos t, on 1001 even samples over [0, 10].
        let times: Vec<f64> = (0..=1000).map(|k| f64::from(k) * 0.01).collect();
        let values: Vec<f64> = times.iter().map(|t| t.sin()).collect();
        let work = cumulative_integral(&times, &values);
        let worst = times
            .iter()
            .zip(&work)
            .map(|(t, w)| (w - (1.0 - t.cos())).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "{worst}");
        assert_eq!(cumulative_integral(&[0.0, 2.0], &[1.0, 3.0]), [0.0, 4.0]);
        assert!(cumulative_integral(&[], &[]).is_empty());
    }

    #[test]
    fn the_inverted_pendulum_tip_height_is_plotted_in_metres() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples/seed/7.4-inverted-pendulum.lag");
        let text = std::fs::read_to_string(path).expect("the seed model");
        let analysis = Analysis::from_text(&text).expect("the model checks");
        let options = SimulationOptions {
            output_step: Some(0.01),
            ..SimulationOptions::default()
        };
        let mut simulation = analysis.simulation(&options).expect("a simulation");
        let run = run_sampled(&mut simulation, 1_000);
        let (extras, balance) = analysis.plot_extras(&run);
        // F = 0 does no work: the energy error stays the measure.
        assert!(extras.balance.is_none() && balance.is_none());
        let [tip] = extras.outputs.as_slice() else {
            panic!("one output: {:?}", extras.outputs);
        };
        assert_eq!((tip.label.as_str(), tip.unit), ("tip_height", Some("m")));
        let theta = run.columns.iter().position(|c| c == "theta").expect("θ");
        for (row, value) in run.rows.iter().zip(&tip.values) {
            // The hinge rides at height 0: the tip is at L cos θ, L = 0.6.
            assert!((value - 0.6 * row[theta].cos()).abs() < 1e-12, "{value}");
        }
    }
}
