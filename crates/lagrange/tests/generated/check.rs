//! One generated model held against the numeric route: lagrange reads its text and derives
//! it; at random states its `M` and `f`, its accelerations (solved, explicit when it gives
//! them, and from the compiled right-hand side of a simulation) agree with the numeric route;
//! every first integral it reports has the value the route gives and a zero rate along the
//! route's accelerations; a conservative model's energy (or Jacobi) integral is reported and
//! kept along a short simulation.

use lagrange::cas::{Expr, Symbol, SymbolKind};
use lagrange::mechanics::Equations;
use lagrange::{Analysis, Ending, SimulationOptions};

use super::generate::Rng;
use super::model::Model;
use super::route::{self, condition, solve, Numeric};

/// Relative agreement asked of the accelerations (of `M` and `f`: a hundred times tighter).
pub const TOLERANCE: f64 = 1e-8;

/// What a check did.
#[derive(Debug, Default, Clone, Copy)]
pub struct Tally {
    pub states: usize,
    pub ill_conditioned: usize,
    /// First integrals checked, summed over the states.
    pub integrals: usize,
    pub simulated: bool,
}

/// A state: `q`, `q̇`, `t`.
struct State {
    q: Vec<f64>,
    qd: Vec<f64>,
    t: f64,
}

impl State {
    fn random(rng: &mut Rng, n: usize) -> State {
        State {
            q: (0..n).map(|_| rng.uniform(-1.5, 1.5)).collect(),
            qd: (0..n).map(|_| rng.uniform(-1.5, 1.5)).collect(),
            t: rng.uniform(0.0, 2.0),
        }
    }
}

/// Lagrange's expressions evaluated at a state.
struct Lagrange<'a> {
    coordinates: &'a [String],
    values: Vec<(String, f64)>,
}

impl Lagrange<'_> {
    fn eval(&self, e: Expr, s: &State) -> Result<f64, String> {
        let env = |sym: Symbol| -> Option<f64> {
            if sym.kind() == SymbolKind::Time {
                return Some(s.t);
            }
            if let Some(k) = self.coordinates.iter().position(|q| q == sym.name()) {
                return match sym.order() {
                    0 => Some(s.q[k]),
                    1 => Some(s.qd[k]),
                    _ => None,
                };
            }
            self.values
                .iter()
                .find(|(n, _)| n == sym.name())
                .map(|(_, v)| *v)
        };
        e.eval(&env)
            .map_err(|err| format!("cannot evaluate: {err}"))
    }
}

fn close(a: f64, b: f64, scale: f64, tolerance: f64) -> bool {
    (a - b).abs() <= tolerance * scale.max(1.0)
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |a, x| a.max(x.abs()))
}

/// Checks `model`; `Err` says what disagrees.
pub fn check(model: &Model, seed: u64, states: usize) -> Result<Tally, String> {
    let text = model.text();
    let analysis = Analysis::from_text(&text).map_err(|e| format!("not read: {e}"))?;
    let equations = analysis
        .equations()
        .map_err(|e| format!("not derived: {e}"))?;
    if equations.coordinates() != model.coords.as_slice() {
        return Err(format!("coordinates {:?}", equations.coordinates()));
    }
    let values = analysis.values().map_err(|e| format!("values: {e}"))?;
    let params: Vec<f64> = model.params.iter().map(|p| p.1).collect();
    let lagrange = Lagrange {
        coordinates: equations.coordinates(),
        values,
    };
    let n = model.coords.len();
    let mut rng = Rng::new(seed ^ 0xa5a5_5a5a);
    let mut simulation = analysis
        .simulation(&SimulationOptions {
            t_end: Some(1.0),
            ..SimulationOptions::default()
        })
        .map_err(|e| format!("not compiled: {e}"))?;
    let mut tally = Tally::default();
    for _ in 0..states {
        let s = State::random(&mut rng, n);
        let numeric = route::equations(model, &params, &s.q, &s.qd, s.t);
        if condition(&numeric.mass) > 1e6 {
            tally.ill_conditioned += 1;
            continue;
        }
        tally.states += 1;
        let expected = solve(&numeric.mass, &numeric.forcing).ok_or("singular M")?;
        compare_equations(equations, &lagrange, &s, &numeric, &expected)?;
        let mut derivative = vec![0.0; 2 * n];
        let state: Vec<f64> = [s.q.clone(), s.qd.clone()].concat();
        simulation
            .with_rhs(|system| system.rhs(s.t, &state, &mut derivative))
            .map_err(|e| format!("compiled right-hand side: {e}"))?;
        compare("compiled q̈", &derivative[n..], &expected, &s)?;
        tally.integrals += check_integrals(equations, &lagrange, &s, &numeric, &expected)?;
    }
    if let Some(kind) = model.integral {
        conserved(
            model, &analysis, equations, &lagrange, kind, &params, &mut rng,
        )?;
        tally.simulated = true;
    }
    Ok(tally)
}

fn compare(what: &str, got: &[f64], want: &[f64], s: &State) -> Result<(), String> {
    let scale = inf_norm(want);
    for (k, (a, b)) in got.iter().zip(want).enumerate() {
        if !close(*a, *b, scale, TOLERANCE) {
            return Err(format!(
                "{what}[{k}] = {a}, the numeric route gives {b} (all: {got:?} vs {want:?}) \
                 at q = {:?}, q̇ = {:?}, t = {}",
                s.q, s.qd, s.t
            ));
        }
    }
    Ok(())
}

/// `M`, `f`, the solved and the explicit accelerations.
fn compare_equations(
    equations: &Equations,
    lagrange: &Lagrange<'_>,
    s: &State,
    numeric: &Numeric,
    expected: &[f64],
) -> Result<(), String> {
    let mass: Vec<Vec<f64>> = equations
        .mass_matrix()
        .iter()
        .map(|row| row.iter().map(|e| lagrange.eval(*e, s)).collect())
        .collect::<Result<_, _>>()?;
    let forcing: Vec<f64> = equations
        .forcing()
        .iter()
        .map(|e| lagrange.eval(*e, s))
        .collect::<Result<_, _>>()?;
    let tight = TOLERANCE / 100.0;
    let m_scale = numeric.mass.iter().map(|r| inf_norm(r)).fold(0.0, f64::max);
    for (j, (row, want)) in mass.iter().zip(&numeric.mass).enumerate() {
        for (k, (a, b)) in row.iter().zip(want).enumerate() {
            if !close(*a, *b, m_scale, tight) {
                return Err(format!("M[{j}][{k}] = {a}, the numeric route gives {b}"));
            }
        }
    }
    let f_scale = inf_norm(&numeric.forcing) + m_scale * inf_norm(expected);
    for (j, (a, b)) in forcing.iter().zip(&numeric.forcing).enumerate() {
        if !close(*a, *b, f_scale, tight) {
            return Err(format!("f[{j}] = {a}, the numeric route gives {b}"));
        }
    }
    let solved = solve(&mass, &forcing).ok_or("lagrange's M is singular")?;
    compare("q̈ from lagrange's M and f", &solved, expected, s)?;
    if let Some(explicit) = equations.accelerations() {
        let explicit: Vec<f64> = explicit
            .iter()
            .map(|e| lagrange.eval(*e, s))
            .collect::<Result<_, _>>()?;
        compare("explicit q̈", &explicit, expected, s)?;
    }
    Ok(())
}

/// Every reported first integral: its value, and `dh/dt = 0` along the numeric route's `q̈`.
fn check_integrals(
    equations: &Equations,
    lagrange: &Lagrange<'_>,
    s: &State,
    numeric: &Numeric,
    expected: &[f64],
) -> Result<usize, String> {
    let mut checked = 0;
    for integral in equations.first_integrals() {
        if !integral.conditions.is_empty() {
            continue;
        }
        let h = lagrange.eval(integral.value, s)?;
        let want = match (integral.kind, &integral.coordinate) {
            ("energy", _) => Some(numeric.energy),
            ("jacobi", _) => Some(numeric.jacobi),
            ("momentum", Some(q)) => lagrange
                .coordinates
                .iter()
                .position(|c| c == q)
                .map(|k| numeric.momenta[k]),
            _ => None,
        };
        if let Some(want) = want {
            if !close(h, want, want.abs(), 1e-9) {
                return Err(format!(
                    "the {} integral is {h}, the numeric route gives {want}",
                    integral.kind
                ));
            }
        }
        // dh/dt = Σ ∂h/∂q q̇ + Σ ∂h/∂q̇ q̈ + ∂h/∂t.
        let mut terms = Vec::new();
        for (k, name) in lagrange.coordinates.iter().enumerate() {
            for (order, rate) in [(0u8, s.qd[k]), (1, expected[k])] {
                let symbol = Expr::rate(name, order).as_symbol().ok_or("a rate symbol")?;
                terms.push(lagrange.eval(integral.value.diff(symbol), s)? * rate);
            }
        }
        let time = Expr::time().as_symbol().ok_or("the time symbol")?;
        terms.push(lagrange.eval(integral.value.diff(time), s)?);
        let rate: f64 = terms.iter().sum();
        let scale: f64 = terms.iter().map(|x| x.abs()).sum();
        if rate.abs() > 1e-9 * scale.max(1e-3) {
            return Err(format!(
                "the {} integral {:?} changes along the motion: dh/dt = {rate} (terms up to {scale})",
                integral.kind, integral.coordinate
            ));
        }
        checked += 1;
    }
    Ok(checked)
}

/// A conservative model: its integral is reported, and kept along a short run (lagrange's
/// `energy_error`, and the numeric route's `h` at the first and last rows).
fn conserved(
    model: &Model,
    analysis: &Analysis,
    equations: &Equations,
    lagrange: &Lagrange<'_>,
    kind: &str,
    params: &[f64],
    rng: &mut Rng,
) -> Result<(), String> {
    let found = equations
        .first_integrals()
        .iter()
        .any(|i| (i.kind == kind || i.kind == "energy") && i.conditions.is_empty());
    if !found {
        return Err(format!(
            "no {kind} integral reported (found: {:?})",
            equations
                .first_integrals()
                .iter()
                .map(|i| i.kind)
                .collect::<Vec<_>>()
        ));
    }
    let mut run_analysis = analysis.clone();
    let n = lagrange.coordinates.len();
    let start = State::random(rng, n);
    for (k, name) in lagrange.coordinates.iter().enumerate() {
        run_analysis
            .set_value(name, start.q[k] / 2.0)
            .map_err(|e| e.to_string())?;
        run_analysis
            .set_value(&format!("{name}_d"), start.qd[k] / 2.0)
            .map_err(|e| e.to_string())?;
    }
    let run = run_analysis
        .simulate(&SimulationOptions {
            t_end: Some(0.5),
            rtol: Some(1e-10),
            atol: Some(1e-12),
            ..SimulationOptions::default()
        })
        .map_err(|e| format!("not simulated: {e}"))?;
    if run.ending != Ending::Finished {
        return Err(format!("the run ended {:?}", run.ending));
    }
    let (first, last) = (&run.rows[0], &run.rows[run.rows.len() - 1]);
    let error = last[last.len() - 2];
    if error.is_nan() || error.abs() >= 1e-8 {
        return Err(format!("energy error {error} after the run"));
    }
    let h = |row: &[f64]| {
        let e = route::equations(model, params, &row[1..=n], &row[n + 1..=2 * n], row[0]);
        if kind == "energy" {
            e.energy
        } else {
            e.jacobi
        }
    };
    let (h0, h1) = (h(first), h(last));
    if !close(h0, h1, h0.abs(), 1e-8) {
        return Err(format!("the numeric route's {kind} went from {h0} to {h1}"));
    }
    Ok(())
}
