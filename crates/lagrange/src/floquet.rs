//! Floquet analysis of time-periodic systems (Kapitza's pendulum, Mathieu's equation, a
//! parametrically excited pendulum): the equations of motion `M(q, t) q̈ = f(q, q̇, t)` with
//! `t` only inside `sin`/`cos` of `ω t + c`.
//!
//! In first-order form `ẋ = F(x, t)`, `x = (q, q̇)`, a periodic motion `x*(t)` (an
//! equilibrium that holds at every `t`, or a periodic orbit) is stable to first order when the
//! variations `δẋ = J(x*(t), t) δx` stay bounded. Integrating `Φ̇ = J Φ`, `Φ(0) = I` over
//! one period `T` gives the monodromy matrix `Φ(T)`; its eigenvalues are the Floquet
//! multipliers `μ`, and a variation grows by `μ` each period.
//!
//! The Jacobian is symbolic: with `q̈ = M⁻¹ f`,
//! `∂q̈/∂qⱼ = M⁻¹ (∂f/∂qⱼ − (∂M/∂qⱼ) q̈)` and `∂q̈/∂q̇ⱼ = M⁻¹ ∂f/∂q̇ⱼ`, the derivatives taken
//! exactly and compiled with `M` and `f` onto one [`numeric::Tape`]. [`Driving`] finds the
//! period from the equations; [`Periodic`] holds the compiled system, finds the equilibria
//! that hold at every `t` (Gauss–Newton on the rest equations at several times) and the
//! periodic orbits (Newton shooting on `x(T) = x(0)`, with `Φ(T) − I` as its Jacobian).

use std::collections::HashSet;

use cas::{Expr, Func, Node, Symbol};
use numeric::{integrate, IntegratorOptions, Method, OdeSystem, RhsError, Tape};
use report::floquet::{Base, ChartPoint, FloquetResult, PeriodSource, Verdict};

use crate::assign::{AssignmentError, Range};
use crate::{Analysis, Error};

/// What a Floquet analysis cannot do.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FloquetError {
    /// Time enters the equations other than through `sin`/`cos` of `ω t + c`.
    #[error("the equations are not periodic in time: {reason}")]
    NotPeriodic {
        /// Where `t` appears.
        reason: String,
    },
    /// The equations do not depend on time, and no period was given.
    #[error("the equations do not depend on time, so there is no period of the driving; give the period T, or linearize about the equilibria as usual")]
    Autonomous,
    /// The driving frequencies have no common period (their ratio is not a small fraction).
    #[error("the driving frequencies {frequencies:?} (rad per unit of time) have no common period with a ratio of small integers; give the period T")]
    NoCommonPeriod {
        /// The frequencies.
        frequencies: Vec<f64>,
    },
    /// A period that is not a positive finite number.
    #[error("the period must be a positive number, not {period}")]
    BadPeriod {
        /// The value.
        period: f64,
    },
    /// Constraints kept by multipliers.
    #[error("Floquet analysis of systems with constraints kept by multipliers ({}) is not supported", names.join(", "))]
    KeptConstraints {
        /// The constraints.
        names: Vec<String>,
    },
    /// A symbol without a numeric value.
    #[error("`{name}` has no numeric value; give it one")]
    MissingValue {
        /// Its name.
        name: String,
    },
    /// Neither an equilibrium at every `t` nor a periodic orbit was found.
    #[error("no equilibrium holds at every t and shooting found no periodic orbit of period {period} from {starts} starts")]
    NothingPeriodic {
        /// The period.
        period: f64,
        /// How many starts were tried.
        starts: usize,
    },
    /// The integration over a period failed.
    #[error("the variational equations could not be integrated over the period: {reason}")]
    Integration {
        /// Why.
        reason: String,
    },
}

/// Settings of a Floquet analysis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FloquetOptions {
    /// The period `T` (default: the common period of the driving: of every `sin`/`cos` of
    /// `ω t + c` in the equations).
    pub period: Option<f64>,
    /// Relative tolerance of the integration over a period (default: 1e-10).
    pub rtol: f64,
    /// The band about `|μ| = 1` counted as on the unit circle (default: 1e-6).
    pub tolerance: f64,
}

impl Default for FloquetOptions {
    fn default() -> Self {
        FloquetOptions {
            period: None,
            rtol: 1e-10,
            tolerance: 1e-6,
        }
    }
}

/// The Floquet analysis about each periodic motion found.
#[derive(Debug, Clone)]
pub struct Floquet {
    /// One per motion: the equilibria at every `t` first, else the periodic orbits.
    pub results: Vec<FloquetResult>,
}

impl Floquet {
    /// As `lagrange linearize --periodic` prints it.
    #[must_use]
    pub fn to_text(&self) -> String {
        report::floquet::floquet_text(&self.results)
    }

    /// As JSON (docs/json.md).
    #[must_use]
    pub fn to_json(&self) -> serde_json::Value {
        report::floquet::floquet_json(&self.results)
    }
}

/// The stability chart of a sweep over one or two names: the verdict about each periodic
/// motion found with the model's values, followed at every grid point.
#[derive(Debug, Clone)]
pub struct FloquetChart {
    /// The swept names.
    pub names: Vec<String>,
    /// The motions followed (as found with the model's values).
    pub motions: Vec<FloquetResult>,
    /// The grid, the first name varying slowest.
    pub points: Vec<ChartPoint>,
}

impl FloquetChart {
    /// The chart as CSV (docs/cli.md).
    #[must_use]
    pub fn to_csv(&self) -> String {
        report::floquet::chart_csv(&self.names, self.motions.len(), &self.points)
    }

    /// Draws the stable region of motion `motion` to an `.svg` or `.png` file.
    ///
    /// # Errors
    /// A [`report::PlotError`]: the file cannot be written, or its extension is neither.
    pub fn plot(&self, path: &std::path::Path, motion: usize) -> Result<(), report::PlotError> {
        report::floquet::plot_stability_chart(path, &self.names, &self.points, motion)
    }
}

impl Analysis {
    /// Floquet analysis about every equilibrium that holds at every `t` (or, when there is
    /// none, every periodic orbit that shooting finds) over the period of the driving.
    ///
    /// # Errors
    /// As [`Analysis::equations`]; [`Error::Floquet`] when the equations are not periodic,
    /// the period is not found, nothing periodic is found, or the integration fails.
    pub fn floquet(&self, options: &FloquetOptions) -> Result<Floquet, Error> {
        let periodic = self.periodic()?;
        let values = periodic.base_values.clone();
        let (period, source) = periodic.period(options, &values)?;
        let results = periodic.analyse(options, &values, period, source)?;
        Ok(Floquet { results })
    }

    /// The stability chart over `ranges` (one or two names, `steps + 1` values each) about the
    /// motions found with the model's values.
    ///
    /// # Errors
    /// As [`Analysis::floquet`], or an unknown name.
    pub fn floquet_chart(
        &self,
        options: &FloquetOptions,
        ranges: &[Range],
        steps: usize,
    ) -> Result<FloquetChart, Error> {
        let periodic = self.periodic()?;
        let base = periodic.base_values.clone();
        for range in ranges {
            if !periodic.value_names.contains(&range.name) {
                return Err(AssignmentError::UnknownName {
                    name: range.name.clone(),
                    known: periodic.value_names.clone(),
                }
                .into());
            }
        }
        let (period, source) = periodic.period(options, &base)?;
        let motions = periodic.analyse(options, &base, period, source)?;
        let steps = steps.clamp(1, 1000);
        let points = grid(ranges, steps)
            .into_iter()
            .map(|at| periodic.chart_point(options, &base, ranges, at, &motions))
            .collect::<Result<Vec<_>, Error>>()?;
        Ok(FloquetChart {
            names: ranges.iter().map(|r| r.name.clone()).collect(),
            motions,
            points,
        })
    }

    fn periodic(&self) -> Result<Periodic, Error> {
        let equations = self.equations()?;
        if !equations.constraint_names().is_empty() {
            return Err(FloquetError::KeptConstraints {
                names: equations.constraint_names().to_vec(),
            }
            .into());
        }
        let mut timed: Vec<(Expr, Expr)> = Vec::new();
        for (name, value) in self.system().inputs() {
            if let Some((_, f)) = self.timed_inputs().iter().find(|(n, _)| n == name) {
                timed.push((Expr::symbol(name), *f));
            } else if let Some(v) = value.filter(|v| crate::assign::depends_on_time(*v)) {
                timed.push((Expr::symbol(name), v));
            }
        }
        let values = self.values()?;
        Periodic::new(equations, &timed, values)
    }
}

/// The grid of a sweep: every combination of `steps + 1` values per range, the first range
/// varying slowest.
fn grid(ranges: &[Range], steps: usize) -> Vec<Vec<f64>> {
    let mut points: Vec<Vec<f64>> = vec![Vec::new()];
    for range in ranges {
        let mut next = Vec::with_capacity(points.len() * (steps + 1));
        for p in &points {
            for k in 0..=steps {
                let mut q = p.clone();
                q.push(range.low + (range.high - range.low) * k as f64 / steps as f64);
                next.push(q);
            }
        }
        points = next;
    }
    points
}

/// The frequencies of the driving: `∂(ω t + c)/∂t` of every `sin`/`cos`/`tan` of `t` in the
/// equations.
#[derive(Debug, Clone)]
pub(crate) struct Driving {
    frequencies: Vec<Expr>,
}

impl Driving {
    /// Reads the frequencies off `exprs`; refuses `t` anywhere else, or not linearly.
    pub(crate) fn find(exprs: &[Expr], t: Symbol) -> Result<Driving, FloquetError> {
        let mut seen = HashSet::new();
        let mut trig = Vec::new();
        for e in exprs {
            collect_trig_of_time(*e, t, &mut seen, &mut trig);
        }
        let mut frequencies = Vec::new();
        for node in &trig {
            let arg = node.children()[0];
            let rate = arg.diff(t).normal();
            if mentions(rate, t) {
                return Err(FloquetError::NotPeriodic {
                    reason: format!(
                        "`{}` is not of a linear function of t",
                        cas::print::to_sympy(*node)
                    ),
                });
            }
            if !frequencies.contains(&rate) {
                frequencies.push(rate);
            }
        }
        let marks: Vec<(Expr, Expr)> = trig
            .iter()
            .enumerate()
            .map(|(i, e)| (*e, Expr::symbol(&format!("__driving_{i}"))))
            .collect();
        for e in exprs {
            if mentions(e.subs(&marks), t) {
                return Err(FloquetError::NotPeriodic {
                    reason: "t appears outside a sine or cosine".to_owned(),
                });
            }
        }
        Ok(Driving { frequencies })
    }

    /// The common period at `values`: the smallest `T` that every `2π/|ωᵢ|` divides.
    pub(crate) fn period(&self, env: &dyn Fn(Symbol) -> Option<f64>) -> Result<f64, FloquetError> {
        let mut omegas = Vec::new();
        for f in &self.frequencies {
            let w = f.eval(env).map_err(|_| FloquetError::MissingValue {
                name: cas::print::to_sympy(*f),
            })?;
            if w.is_finite() && w.abs() > 1e-300 {
                omegas.push(w.abs());
            }
        }
        common_period(&omegas)
    }
}

/// The smallest `T` with `T ωᵢ / 2π` an integer for every `ωᵢ`, when their ratios are
/// fractions with denominators up to 1000 (to 1e-9).
pub(crate) fn common_period(omegas: &[f64]) -> Result<f64, FloquetError> {
    let Some(&first) = omegas.first() else {
        return Err(FloquetError::Autonomous);
    };
    let mut fractions = Vec::with_capacity(omegas.len());
    for w in omegas {
        let r = w / first;
        let found = (1..=1000u64).find_map(|q| {
            let p = (r * q as f64).round();
            ((r * q as f64 - p).abs() <= 1e-9 * r.max(1.0) * q as f64 && p >= 1.0)
                .then_some((p as u64, q))
        });
        let Some(f) = found else {
            return Err(FloquetError::NoCommonPeriod {
                frequencies: omegas.to_vec(),
            });
        };
        fractions.push(f);
    }
    // ωᵢ = first pᵢ/qᵢ = (first/L) kᵢ with L the lcm of the qᵢ; the fundamental is
    // (first/L) gcd(kᵢ).
    let l = fractions.iter().fold(1u64, |l, (_, q)| lcm(l, *q));
    let g = fractions.iter().fold(0u64, |g, (p, q)| gcd(g, p * (l / q)));
    let fundamental = first / l as f64 * g.max(1) as f64;
    Ok(2.0 * std::f64::consts::PI / fundamental)
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

fn lcm(a: u64, b: u64) -> u64 {
    a / gcd(a, b).max(1) * b
}

/// Collects every `sin`, `cos`, `tan` node whose argument mentions `t`.
fn collect_trig_of_time(e: Expr, t: Symbol, seen: &mut HashSet<Expr>, out: &mut Vec<Expr>) {
    if !seen.insert(e) {
        return;
    }
    if let Node::Func(Func::Sin | Func::Cos | Func::Tan, args) = e.node() {
        if args.len() == 1 && mentions(args[0], t) {
            out.push(e);
            return;
        }
    }
    for c in e.children() {
        collect_trig_of_time(*c, t, seen, out);
    }
}

/// Whether the symbol `s` occurs in `e` (syntactically).
fn mentions(e: Expr, s: Symbol) -> bool {
    let mut seen = HashSet::new();
    let mut stack = vec![e];
    while let Some(x) = stack.pop() {
        if !seen.insert(x) {
            continue;
        }
        if x.as_symbol() == Some(s) {
            return true;
        }
        stack.extend_from_slice(x.children());
    }
    false
}

/// Whether coordinate `q` enters `exprs` only through `sin`, `cos`, `tan` of itself.
fn is_angle(exprs: &[Expr], q: Symbol) -> bool {
    let x = Expr::coordinate(q.name());
    let marks = [
        (x.sin(), Expr::symbol("__angle_sin")),
        (x.cos(), Expr::symbol("__angle_cos")),
        (x.tan(), Expr::symbol("__angle_tan")),
    ];
    exprs.iter().any(|e| mentions(*e, q)) && exprs.iter().all(|e| !mentions(e.subs(&marks), q))
}

/// The compiled time-periodic system: one tape with outputs `M` (n², row-major), `f` (n),
/// `∂f/∂q` (n², `[i][j] = ∂fᵢ/∂qⱼ`), `∂f/∂q̇` (n²), `∂M/∂qₖ` (n³, `k` slowest) and inputs
/// `[q, q̇, t, values…]`.
struct Periodic {
    n: usize,
    coordinates: Vec<String>,
    angles: Vec<bool>,
    /// Whether the equations are affine in the state (`M` free of `q`, `f` affine in `q` and
    /// `q̇`): then the map over a period is affine too, `x(T) = Φ x₀ + c` with `Φ` the same
    /// from every start, and its fixed point, when `Φ − I` is invertible, is unique.
    affine: bool,
    tape: Tape,
    driving: Driving,
    /// The names of the values, in the order of the tape's inputs after `t`.
    value_names: Vec<String>,
    /// The model's values, in that order.
    base_values: Vec<f64>,
}

/// Newton's starts per coordinate (angles over a turn, other coordinates over −10..10).
const STARTS_PER_AXIS: usize = 12;
/// Starts tried by shooting (each costs up to 30 integrations over the period).
const SHOOTING_STARTS: usize = 16;
/// The most steps of one integration over the period: a period that needs more (a driving
/// far slower than the system's own motion, or a stiff one) is refused rather than left to
/// run for minutes inside the shooting's loops.
const MAX_STEPS_PER_PERIOD: u64 = 50_000;
/// Times per period at which the rest equations must hold.
const SAMPLE_TIMES: usize = 7;

impl Periodic {
    fn new(
        equations: &mechanics::Equations,
        timed: &[(Expr, Expr)],
        values: Vec<(String, f64)>,
    ) -> Result<Periodic, Error> {
        let names = equations.coordinates().to_vec();
        let n = names.len();
        let sym = |e: Expr| {
            e.as_symbol().ok_or_else(|| {
                Error::Inconsistent(format!("`{}` is not a symbol", cas::print::to_sympy(e)))
            })
        };
        let q: Vec<Symbol> = names
            .iter()
            .map(|c| sym(Expr::coordinate(c)))
            .collect::<Result<_, _>>()?;
        let v: Vec<Symbol> = names
            .iter()
            .map(|c| sym(Expr::rate(c, 1)))
            .collect::<Result<_, _>>()?;
        let t = sym(Expr::time())?;
        let mass: Vec<Expr> = equations
            .mass_matrix()
            .iter()
            .flatten()
            .map(|e| e.subs(timed))
            .collect();
        let force: Vec<Expr> = equations
            .forcing()
            .iter()
            .map(|e| e.subs(timed).normal())
            .collect();
        let mut all = mass.clone();
        all.extend(&force);
        let driving = Driving::find(&all, t)?;
        let angles = q.iter().map(|s| is_angle(&all, *s)).collect();
        let mut outputs = all;
        for wrt in [&q, &v] {
            for f in &force {
                outputs.extend(wrt.iter().map(|s| f.diff(*s).normal()));
            }
        }
        for s in &q {
            outputs.extend(mass.iter().map(|m| m.diff(*s).normal()));
        }
        let state: Vec<Symbol> = q.iter().chain(&v).copied().collect();
        let derivatives = &outputs[n * n + n..3 * n * n + n];
        let affine = mass
            .iter()
            .chain(derivatives)
            .all(|e| state.iter().all(|s| !mentions(*e, *s)));
        let mut inputs: Vec<Symbol> = q.iter().chain(&v).copied().collect();
        inputs.push(t);
        let (mut value_names, mut base_values) = (Vec::new(), Vec::new());
        for (name, x) in values {
            if let Some(s) = Expr::symbol(&name).as_symbol() {
                if !inputs.contains(&s) {
                    inputs.push(s);
                    value_names.push(name);
                    base_values.push(x);
                }
            }
        }
        let tape = Tape::compile(&outputs, &inputs).map_err(|e| match e {
            numeric::TapeError::UnboundSymbol { name } => FloquetError::MissingValue { name },
            other => FloquetError::MissingValue {
                name: other.to_string(),
            },
        })?;
        Ok(Periodic {
            n,
            coordinates: names,
            angles,
            affine,
            tape,
            driving,
            value_names,
            base_values,
        })
    }

    fn period(
        &self,
        options: &FloquetOptions,
        values: &[f64],
    ) -> Result<(f64, PeriodSource), Error> {
        if let Some(p) = options.period {
            if !(p.is_finite() && p > 0.0) {
                return Err(FloquetError::BadPeriod { period: p }.into());
            }
            return Ok((p, PeriodSource::Given));
        }
        let env = |s: Symbol| {
            self.value_names
                .iter()
                .position(|n| n == s.name())
                .map(|i| values[i])
        };
        Ok((self.driving.period(&env)?, PeriodSource::Driving))
    }

    /// The motions found at `values`, each with its Floquet analysis.
    fn analyse(
        &self,
        options: &FloquetOptions,
        values: &[f64],
        period: f64,
        source: PeriodSource,
    ) -> Result<Vec<FloquetResult>, Error> {
        let mut flow = Flow::new(self, values, options.rtol);
        let mut bases: Vec<(Base, Vec<f64>)> = self
            .equilibria(&mut flow, period)
            .into_iter()
            .map(|q| (Base::Equilibrium, q))
            .collect();
        if bases.is_empty() {
            bases = self
                .orbits(&mut flow, period)
                .into_iter()
                .map(|x| (Base::Orbit, x))
                .collect();
        }
        if bases.is_empty() {
            return Err(FloquetError::NothingPeriodic {
                period,
                starts: self.starts().len(),
            }
            .into());
        }
        bases
            .into_iter()
            .map(|(base, x0)| {
                let (_, monodromy, steps) = flow.over(&x0, period)?;
                self.result(options, period, source, base, x0, monodromy, steps)
            })
            .collect()
    }

    #[allow(clippy::too_many_arguments)] // One call site; the fields of the result.
    fn result(
        &self,
        options: &FloquetOptions,
        period: f64,
        source: PeriodSource,
        base: Base,
        state: Vec<f64>,
        monodromy: Vec<Vec<f64>>,
        steps: u64,
    ) -> Result<FloquetResult, Error> {
        let multipliers =
            numeric::eigen::eigenvalues(&monodromy).map_err(|e| FloquetError::Integration {
                reason: format!("the multipliers: {e}"),
            })?;
        Ok(FloquetResult {
            coordinates: self.coordinates.clone(),
            period,
            period_source: source,
            base,
            state,
            verdict: Verdict::of(&multipliers, options.tolerance),
            monodromy,
            multipliers,
            tolerance: options.tolerance,
            steps,
        })
    }

    /// One point of a chart: each motion of `motions` followed to the values `at` of the
    /// swept names (Newton from where it was), and its verdict there.
    fn chart_point(
        &self,
        options: &FloquetOptions,
        base: &[f64],
        ranges: &[Range],
        at: Vec<f64>,
        motions: &[FloquetResult],
    ) -> Result<ChartPoint, Error> {
        let mut values = base.to_vec();
        for (range, x) in ranges.iter().zip(&at) {
            if let Some(i) = self.value_names.iter().position(|n| *n == range.name) {
                values[i] = *x;
            }
        }
        let (period, _) = self.period(options, &values)?;
        let mut flow = Flow::new(self, &values, options.rtol);
        let verdicts = motions
            .iter()
            .map(|m| {
                let x0 = if m.base == Base::Orbit {
                    self.shoot(&mut flow, m.state.clone(), period)
                } else {
                    self.rest_newton(&mut flow, &m.state[..self.n], period)
                        .map(|mut q| {
                            q.resize(2 * self.n, 0.0);
                            q
                        })
                }?;
                let (_, monodromy, _) = flow.over(&x0, period).ok()?;
                let mu = numeric::eigen::eigenvalues(&monodromy).ok()?;
                let verdict = Verdict::of(&mu, options.tolerance);
                let largest = mu.iter().map(|(r, i)| r.hypot(*i)).fold(0.0, f64::max);
                Some((verdict, largest))
            })
            .collect();
        Ok(ChartPoint {
            values: at,
            verdicts,
        })
    }

    /// The starting points of the searches: a grid over a turn for angles, −10..10 otherwise
    /// (fewer points per axis with more coordinates, at most about 2000 in all).
    fn starts(&self) -> Vec<Vec<f64>> {
        let per_axis = match self.n {
            0 => return Vec::new(),
            1 => STARTS_PER_AXIS,
            2 => 10,
            3 => 8,
            _ => 3,
        };
        let axis = |angle: bool| -> Vec<f64> {
            (0..per_axis)
                .map(|k| {
                    let s = (k as f64 + 0.5) / per_axis as f64;
                    if angle {
                        -std::f64::consts::PI + 2.0 * std::f64::consts::PI * s
                    } else {
                        -10.0 + 20.0 * s
                    }
                })
                .collect()
        };
        let mut points: Vec<Vec<f64>> = vec![Vec::new()];
        for &angle in &self.angles {
            points = points
                .into_iter()
                .flat_map(|p| {
                    axis(angle).into_iter().map(move |x| {
                        let mut q = p.clone();
                        q.push(x);
                        q
                    })
                })
                .take(4096)
                .collect();
        }
        points
    }

    /// The equilibria that hold at every `t` (states `(q, 0)`), distinct, sorted.
    fn equilibria(&self, flow: &mut Flow<'_>, period: f64) -> Vec<Vec<f64>> {
        let mut found: Vec<Vec<f64>> = Vec::new();
        for start in self.starts() {
            if let Some(q) = self.rest_newton(flow, &start, period) {
                if !found.iter().any(|f| self.same(f, &q)) {
                    found.push(q);
                }
            }
        }
        found.sort_by(|a, b| {
            a.iter()
                .zip(b)
                .map(|(x, y)| x.total_cmp(y))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        found
            .into_iter()
            .map(|mut q| {
                q.resize(2 * self.n, 0.0);
                q
            })
            .collect()
    }

    /// Whether two configurations are the same (angles modulo 2π).
    fn same(&self, a: &[f64], b: &[f64]) -> bool {
        a.iter().zip(b).zip(&self.angles).all(|((x, y), angle)| {
            let d = if *angle { wrap(x - y) } else { x - y };
            d.abs() <= 1e-6 * (1.0 + x.abs())
        })
    }

    /// Gauss–Newton on `f(q, 0, tₖ) = 0` at [`SAMPLE_TIMES`] times over the period: a
    /// configuration (angles in (−π, π]) where the rest equations hold at every sampled `t`.
    fn rest_newton(&self, flow: &mut Flow<'_>, start: &[f64], period: f64) -> Option<Vec<f64>> {
        let n = self.n;
        let mut q = start.to_vec();
        let times: Vec<f64> = (0..SAMPLE_TIMES)
            .map(|k| period * (k as f64 + 0.37) / SAMPLE_TIMES as f64)
            .collect();
        // One more step after the residual is small: Newton's last step leaves the start's
        // size times ε, the next one rounding only.
        let mut polished = false;
        for _ in 0..60 {
            let (mut jtj, mut jtr, mut norm, mut scale) =
                (vec![0.0; n * n], vec![0.0; n], 0.0_f64, 0.0_f64);
            for &t in &times {
                let out = flow.eval(&q, &vec![0.0; n], t);
                let (f, dfdq) = (&out[n * n..n * n + n], &out[n * n + n..2 * n * n + n]);
                for i in 0..n {
                    norm = norm.max(f[i].abs());
                    for j in 0..n {
                        scale = scale.max(dfdq[i * n + j].abs());
                        jtr[j] += dfdq[i * n + j] * f[i];
                        for k in 0..n {
                            jtj[j * n + k] += dfdq[i * n + j] * dfdq[i * n + k];
                        }
                    }
                }
            }
            if !norm.is_finite() {
                return None;
            }
            let converged = norm <= 1e-10 * (1.0 + scale);
            if converged && polished {
                // Values at rounding level are zeros (the start's size times ε).
                for x in &mut q {
                    if x.abs() < 1e-11 {
                        *x = 0.0;
                    }
                }
                return Some(self.wrapped(q));
            }
            polished = converged;
            let lift = 1e-14 * jtj.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            for j in 0..n {
                jtj[j * n + j] += lift.max(1e-300);
            }
            numeric::solve_in_place(n, &mut jtj, &mut jtr).ok()?;
            for j in 0..n {
                q[j] -= jtr[j];
            }
            if q.iter().any(|x| !x.is_finite() || x.abs() > 1e6) {
                return None;
            }
        }
        None
    }

    fn wrapped(&self, mut q: Vec<f64>) -> Vec<f64> {
        for (x, angle) in q.iter_mut().zip(&self.angles) {
            if *angle {
                *x = wrap(*x);
            }
        }
        q
    }

    /// Periodic orbits by shooting from the grid of starts (at rest), distinct.
    fn orbits(&self, flow: &mut Flow<'_>, period: f64) -> Vec<Vec<f64>> {
        let mut found: Vec<Vec<f64>> = Vec::new();
        for start in self.starts().into_iter().take(SHOOTING_STARTS) {
            let mut x = start;
            x.resize(2 * self.n, 0.0);
            if let Some(x) = self.shoot(flow, x, period) {
                if !found.iter().any(|f| self.same(f, &x)) {
                    found.push(x);
                }
            }
            // An affine map's Newton step lands on its one fixed point from any start: once
            // shooting converged, every other start finds the same orbit again (the damped
            // oscillator's sixteen shootings were nine tenths of its `solve`; issue 20).
            if self.affine && !found.is_empty() {
                break;
            }
        }
        found
    }

    /// Newton on `G(x₀) = x(T) − x₀` (angle differences taken modulo 2π), with
    /// `Φ(T) − I` as the Jacobian.
    fn shoot(&self, flow: &mut Flow<'_>, mut x: Vec<f64>, period: f64) -> Option<Vec<f64>> {
        let m = 2 * self.n;
        for _ in 0..30 {
            let (end, phi, _) = flow.over(&x, period).ok()?;
            let mut g: Vec<f64> = (0..m).map(|i| end[i] - x[i]).collect();
            for (gi, angle) in g.iter_mut().zip(&self.angles) {
                if *angle {
                    *gi = wrap(*gi);
                }
            }
            let size = x.iter().fold(1.0_f64, |s, v| s.max(v.abs()));
            if g.iter().all(|v| v.abs() <= 1e-10 * size) {
                let mut x = x;
                for (xi, angle) in x.iter_mut().zip(&self.angles) {
                    if *angle {
                        *xi = wrap(*xi);
                    }
                }
                return Some(x);
            }
            let mut a: Vec<f64> = (0..m * m)
                .map(|k| phi[k / m][k % m] - f64::from(u8::from(k / m == k % m)))
                .collect();
            numeric::solve_in_place(m, &mut a, &mut g).ok()?;
            for i in 0..m {
                x[i] -= g[i];
            }
            if x.iter().any(|v| !v.is_finite() || v.abs() > 1e6) {
                return None;
            }
        }
        None
    }
}

/// An angle in (−π, π].
fn wrap(x: f64) -> f64 {
    let tau = 2.0 * std::f64::consts::PI;
    let r = x - tau * (x / tau).round();
    if r <= -std::f64::consts::PI {
        r + tau
    } else {
        r
    }
}

/// After one period: `x(T)`, `Φ(T)` (rows), and the accepted steps.
type OnePeriod = (Vec<f64>, Vec<Vec<f64>>, u64);

/// The state and its variations `y = (x, Φ)` (`Φ` row-major, `2n × 2n`) as an ODE, with
/// the tape's buffers.
struct Flow<'a> {
    system: &'a Periodic,
    inputs: Vec<f64>,
    registers: Vec<f64>,
    outputs: Vec<f64>,
    rtol: f64,
    /// The right-hand side's work space, kept between calls: `q̈`, the Jacobian's lower half
    /// (`n × 2n`), one of its columns and the mass matrix being factored. The shooting calls
    /// the right-hand side tens of thousands of times; allocating these per call was a third
    /// of `solve`'s time on the damped oscillator (issue 20).
    acceleration: Vec<f64>,
    jacobian: Vec<f64>,
    column: Vec<f64>,
    factored: Vec<f64>,
}

impl<'a> Flow<'a> {
    fn new(system: &'a Periodic, values: &[f64], rtol: f64) -> Flow<'a> {
        let n = system.n;
        let mut inputs = vec![0.0; 2 * n + 1];
        inputs.extend_from_slice(values);
        Flow {
            system,
            inputs,
            registers: system.tape.registers(),
            outputs: vec![0.0; system.tape.output_count()],
            rtol,
            acceleration: vec![0.0; n],
            jacobian: vec![0.0; 2 * n * n],
            column: vec![0.0; n],
            factored: vec![0.0; n * n],
        }
    }

    fn eval(&mut self, q: &[f64], v: &[f64], t: f64) -> &[f64] {
        let n = self.system.n;
        self.inputs[..n].copy_from_slice(q);
        self.inputs[n..2 * n].copy_from_slice(v);
        self.inputs[2 * n] = t;
        self.system
            .tape
            .eval(&self.inputs, &mut self.registers, &mut self.outputs);
        &self.outputs
    }

    /// `x(T)` and `Φ(T)` from `x(0) = x0`, `Φ(0) = I`, with the accepted steps.
    fn over(&mut self, x0: &[f64], period: f64) -> Result<OnePeriod, FloquetError> {
        let m = 2 * self.system.n;
        let mut y0 = x0.to_vec();
        y0.extend((0..m * m).map(|k| f64::from(u8::from(k / m == k % m))));
        let options = IntegratorOptions {
            max_steps: MAX_STEPS_PER_PERIOD,
            rtol: self.rtol,
            atol: self.rtol * 1e-2,
            ..IntegratorOptions::default()
        };
        let mut last = y0.clone();
        let outcome = integrate(
            self,
            Method::Dopri5,
            0.0,
            &y0,
            period,
            &options,
            &mut |_, y| {
                last.clear();
                last.extend_from_slice(y);
            },
        );
        if let numeric::StopReason::Failed(f) = outcome.stop {
            return Err(FloquetError::Integration {
                reason: f.to_string(),
            });
        }
        if (outcome.t - period).abs() > 1e-9 * period {
            return Err(FloquetError::Integration {
                reason: format!("stopped at t = {}", outcome.t),
            });
        }
        let phi = (0..m)
            .map(|i| last[m + i * m..m + (i + 1) * m].to_vec())
            .collect();
        Ok((last[..m].to_vec(), phi, outcome.stats.steps))
    }
}

impl OdeSystem for Flow<'_> {
    fn dimension(&self) -> usize {
        let m = 2 * self.system.n;
        m + m * m
    }

    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        let n = self.system.n;
        let m = 2 * n;
        self.eval(&y[..n], &y[n..m], t);
        let Flow {
            outputs: out,
            acceleration: acc,
            jacobian: jac,
            column: col,
            factored,
            ..
        } = self;
        let (mass, f) = (&out[..n * n], &out[n * n..n * n + n]);
        let dfdq = &out[n * n + n..2 * n * n + n];
        let dfdv = &out[2 * n * n + n..3 * n * n + n];
        let dmdq = &out[3 * n * n + n..];
        // Each solve factors a fresh copy of `M`, as one `solve_in_place` call does: the same
        // operations, so the same numbers, as before the work space was kept.
        let mut solve = |rhs: &mut [f64]| -> Result<(), RhsError> {
            factored.copy_from_slice(mass);
            numeric::solve_in_place(n, factored, rhs)
                .map_err(|_| RhsError::SingularMatrix { column: 0 })
        };
        acc.copy_from_slice(f);
        solve(acc)?;
        // The Jacobian's lower half, column by column: ∂q̈/∂qⱼ, then ∂q̈/∂q̇ⱼ.
        for j in 0..m {
            for (i, c) in col.iter_mut().enumerate() {
                *c = if j < n {
                    dfdq[i * n + j]
                        - (0..n)
                            .map(|k| dmdq[j * n * n + i * n + k] * acc[k])
                            .sum::<f64>()
                } else {
                    dfdv[i * n + (j - n)]
                };
            }
            solve(col)?;
            for i in 0..n {
                jac[i * m + j] = col[i];
            }
        }
        dy[..n].copy_from_slice(&y[n..m]);
        dy[n..m].copy_from_slice(acc);
        let phi = &y[m..];
        for c in 0..m {
            // Upper half: d(δq)/dt = δq̇.
            for i in 0..n {
                dy[m + i * m + c] = phi[(n + i) * m + c];
            }
            for i in 0..n {
                dy[m + (n + i) * m + c] = (0..m).map(|k| jac[i * m + k] * phi[k * m + c]).sum();
            }
        }
        if dy.iter().any(|v| !v.is_finite()) {
            return Err(RhsError::NotFinite);
        }
        Ok(())
    }
}
