//! Stability at a pole of the coordinates (the spherical pendulum hanging at `θ = 0`, a top's
//! axis along the vertical), where the mass matrix `M₀` is singular and the linearization in
//! the model's coordinates cannot decide.
//!
//! At such a point one direction of the coordinates moves nothing: the null vector `n` of
//! `M₀`, whose largest entry names the azimuth `α` (φ of the pendulum, ψ of the top) and
//! whose other entries the coordinates turning with it (the top's spin φ). A coordinate with
//! no part in `n` whose change makes `M` regular is the polar angle `θ`. The local regular
//! chart is the polar one made Cartesian,
//!
//! `u = r cos α`, `v = r sin α`, `r = θ − θ*`, `w_β = β − (n_β/n_α) α`,
//!
//! with the other coordinates kept. Near the pole `V(θ* + r, α, …) = V₀ + ½ r² h(α) + r Σ xₖ gₖ(α)
//! + …`, and `V` is smooth in `(u, v)` exactly when `h` holds only the harmonics 0 and 2α and
//! `gₖ` only α; then `h(α) = a cos²α + 2b sin α cos α + c sin²α` gives the chart's Hessian
//! `[[a, b], [b, c]]` from `h(0)`, `h(π/2)`, `h(π/4)` (checked at `3π/4`), and `gₖ` its mixed
//! entries. For a conservative system at rest (no generalized forces besides the potential's)
//! Lagrange–Dirichlet decides: a positive definite Hessian is a strict minimum, stable; a
//! negative eigenvalue is unstable. Coordinates absent from the potential (the top's spin
//! `w = ψ + φ`) are left free, as elsewhere.

use cas::{Expr, Symbol};
use mechanics::equilibria::{spin_rate, Values};
use mechanics::Equations;

/// An equilibrium or steady motion at a pole of the coordinates, decided in a regular chart.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum AtPole {
    /// At rest: the potential's Hessian in the chart.
    Rest(PoleStability),
    /// A steady motion: the gyroscopic linearization in the chart.
    Spin(PoleSpin),
}

impl AtPole {
    /// The sentence reports print beneath the equilibrium.
    #[must_use]
    pub fn sentence(&self) -> String {
        match self {
            AtPole::Rest(p) => p.sentence(),
            AtPole::Spin(p) => p.sentence(),
        }
    }

    /// Stable, unstable, or not decided.
    #[must_use]
    pub fn stable(&self) -> Option<bool> {
        match self {
            AtPole::Rest(p) => p.stable,
            AtPole::Spin(p) => Some(p.stable),
        }
    }
}

/// The stability of an equilibrium at a pole, decided in a regular chart.
#[derive(Debug, Clone, PartialEq)]
pub struct PoleStability {
    /// The polar angle `θ` (at 0 or π there).
    pub polar: String,
    /// The azimuth `α` that moves nothing at the pole.
    pub azimuth: String,
    /// The chart's coordinates: `u`, `v`, then the others (`w_β` written `β + c α`).
    pub chart: Vec<String>,
    /// The potential's Hessian in the chart (free coordinates left out).
    pub hessian: Vec<Vec<f64>>,
    /// Its eigenvalues, increasing.
    pub eigenvalues: Vec<f64>,
    /// Stable (strict minimum), unstable (a negative eigenvalue), or `None` (semidefinite).
    pub stable: Option<bool>,
}

impl PoleStability {
    /// The sentence reports print beneath the equilibrium.
    #[must_use]
    pub fn sentence(&self) -> String {
        let verdict = match self.stable {
            Some(true) => {
                "stable (Lagrange–Dirichlet: the potential's Hessian there is positive definite)"
            }
            Some(false) => "unstable (the potential's Hessian there has a negative eigenvalue)",
            None => "not decided (the potential's Hessian there is only semidefinite)",
        };
        let eig: Vec<String> = self.eigenvalues.iter().map(|e| format!("{e:.6}")).collect();
        format!(
            "at the pole of {} (where {} moves nothing): decided in the regular chart ({}), \
             u + i v = ({} − {}₀) e^(i {}): {verdict}; Hessian eigenvalues {}",
            self.polar,
            self.azimuth,
            self.chart.join(", "),
            self.polar,
            self.polar,
            self.azimuth,
            eig.join(", ")
        )
    }
}

/// A pole of the coordinates at `q`: `M(q)` has one null direction `null`, whose largest
/// entry is the azimuth's, and the polar angle's change makes `M` regular.
pub(crate) struct Pole {
    symbols: Vec<Symbol>,
    null: Vec<f64>,
    pub(crate) alpha: usize,
    pub(crate) polar: usize,
}

impl Pole {
    /// The pole at `q`, if it is one. The azimuth is the first coordinate with the largest
    /// entry of the null vector that is not in `turning`: a chart whose `(u, v)` turn with a
    /// spinning coordinate would be regular too, but rotating (its matrices then hold the
    /// frame's Coriolis and centrifugal terms).
    pub(crate) fn find(
        equations: &Equations,
        q: &[f64],
        values: &Values,
        turning: &[usize],
    ) -> Option<Pole> {
        let names = equations.coordinates();
        let n = names.len();
        let symbols: Vec<Symbol> = names
            .iter()
            .map(|c| Expr::coordinate(c).as_symbol())
            .collect::<Option<_>>()?;
        let mut pole = Pole {
            symbols,
            null: Vec::new(),
            alpha: 0,
            polar: 0,
        };
        let mass = |at: &[f64]| -> Option<Vec<Vec<f64>>> {
            let rows = equations.mass_matrix().iter();
            rows.map(|row| row.iter().map(|e| pole.eval(*e, at, values)).collect())
                .collect()
        };
        let null = null_vector(&mass(q)?)?;
        let largest = null.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let candidates = (0..n).filter(|&i| null[i].abs() >= (1.0 - 1e-9) * largest);
        let mut candidates: Vec<usize> = candidates.collect();
        candidates.sort_by_key(|i| turning.contains(i));
        let alpha = *candidates.first()?;
        let polar = (0..n).find(|&j| {
            null[j].abs() < 1e-9 && {
                let mut near = q.to_vec();
                near[j] += 1e-3;
                mass(&near).is_some_and(|m| null_vector(&m).is_none())
            }
        })?;
        pole.null = null;
        pole.alpha = alpha;
        pole.polar = polar;
        Some(pole)
    }

    /// `e` at the coordinates `at`, the other symbols from `values`.
    fn eval(&self, e: Expr, at: &[f64], values: &Values) -> Option<f64> {
        e.eval(&|s| match self.symbols.iter().position(|x| *x == s) {
            Some(i) => Some(at[i]),
            None => values.get(s.name()).copied(),
        })
        .ok()
        .filter(|v| v.is_finite())
    }

    /// The companion factor `c_k = n_k / n_α` of coordinate `k`.
    fn companion(&self, k: usize) -> f64 {
        self.null[k] / self.null[self.alpha]
    }
}

/// The stability of the rest state `q` (by coordinate, with `free` those absent from the rest
/// equations) when `M(q)` is singular with one null direction of the polar kind; `None` when
/// it is not such a point, the system is not conservative, or the potential is not smooth in
/// the chart.
pub(crate) fn at_pole(
    equations: &Equations,
    q: &[f64],
    free: &[bool],
    values: &Values,
) -> Option<PoleStability> {
    if equations.generalized_forces().iter().any(|f| !f.is_zero()) {
        return None;
    }
    let pole = Pole::find(equations, q, values, &[])?;
    let (names, symbols, null) = (equations.coordinates(), &pole.symbols, &pole.null);
    let (polar, alpha) = (pole.polar, pole.alpha);
    let eval = |e: Expr, at: &[f64]| pole.eval(e, at, values);
    let potential = equations.potential_energy();
    let theta = symbols[polar];
    // The chart's other coordinates: every one but θ and α, each with its companion factor.
    let n = names.len();
    let others: Vec<usize> = (0..n).filter(|&k| k != polar && k != alpha).collect();
    let at_angle = |angle: f64| {
        let mut x = q.to_vec();
        x[alpha] = q[alpha] + angle;
        for &k in &others {
            x[k] = q[k] + null[k] / null[alpha] * angle;
        }
        x
    };
    // The first derivatives vanish in every direction of the blow-up (an equilibrium there).
    let d_theta = potential.diff(theta);
    let angles = [
        0.0,
        std::f64::consts::FRAC_PI_2,
        std::f64::consts::FRAC_PI_4,
        3.0 * std::f64::consts::FRAC_PI_4,
    ];
    let scale = 1.0 + eval(potential, q)?.abs();
    for angle in angles {
        if eval(d_theta, &at_angle(angle))?.abs() > 1e-9 * scale {
            return None;
        }
    }
    let h: Vec<f64> = angles
        .iter()
        .map(|x| eval(d_theta.diff(theta), &at_angle(*x)))
        .collect::<Option<_>>()?;
    let (ha, hc) = (h[0], h[1]);
    let hb = h[2] - 0.5 * (ha + hc);
    // h(3π/4) = (a + c)/2 − b when h holds only the harmonics 0 and 2α.
    if (h[3] - (0.5 * (ha + hc) - hb)).abs() > 1e-7 * (1.0 + ha.abs() + hc.abs()) {
        return None;
    }
    // A coordinate the potential does not hold (free at rest) is left out.
    let kept: Vec<usize> = others
        .iter()
        .copied()
        .filter(|&k| !free.get(k).copied().unwrap_or(false))
        .collect();
    let size = 2 + kept.len();
    let mut rows = vec![vec![0.0; size]; size];
    rows[0][0] = ha;
    rows[0][1] = hb;
    rows[1][0] = hb;
    rows[1][1] = hc;
    let mut chart = vec!["u".to_owned(), "v".to_owned()];
    for (i, &k) in kept.iter().enumerate() {
        let mixed = d_theta.diff(symbols[k]);
        let g: Vec<f64> = angles
            .iter()
            .map(|x| eval(mixed, &at_angle(*x)))
            .collect::<Option<_>>()?;
        // g(α) = p cos α + q sin α: g(π/4) = (p + q)/√2.
        let expected = (g[0] + g[1]) * std::f64::consts::FRAC_1_SQRT_2;
        if (g[2] - expected).abs() > 1e-7 * (1.0 + g[0].abs() + g[1].abs()) {
            return None;
        }
        for (axis, value) in [g[0], g[1]].into_iter().enumerate() {
            rows[axis][2 + i] = value;
            rows[2 + i][axis] = value;
        }
        for (j, &l) in kept.iter().enumerate() {
            rows[2 + i][2 + j] = eval(potential.diff(symbols[k]).diff(symbols[l]), q)?;
        }
        let companion = null[k] / null[alpha];
        chart.push(if companion.abs() < 1e-12 {
            names[k].clone()
        } else {
            let sign = if companion < 0.0 { "+" } else { "−" };
            format!(
                "{} {sign} {} {}",
                names[k],
                number(companion.abs()),
                names[alpha]
            )
        });
    }
    let eigenvalues: Vec<f64> = numeric::eigen::eigenvalues(&rows)
        .ok()?
        .into_iter()
        .map(|(re, _)| re)
        .collect();
    let size = eigenvalues.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
    let tolerance = 1e-9 * size.max(f64::MIN_POSITIVE);
    let stable = if eigenvalues.iter().all(|e| *e > tolerance) {
        Some(true)
    } else if eigenvalues.iter().any(|e| *e < -tolerance) {
        Some(false)
    } else {
        None
    };
    Some(PoleStability {
        polar: names[polar].clone(),
        azimuth: names[alpha].clone(),
        chart,
        hessian: rows,
        eigenvalues,
        stable,
    })
}

/// `text` (the equilibria as `lagrange equilibria` prints them) with each pole's sentence
/// beneath its equilibrium's "stability not decided" line.
pub(crate) fn with_pole_sentences(text: &str, poles: &[Option<AtPole>]) -> String {
    let marker = |line: &str| line.contains("stability not decided");
    crate::chart_modes::beneath(text, poles, marker, |pole| {
        format!("    {}\n", pole.sentence())
    })
}

/// The decisions at poles as JSON (docs/json.md): one entry per equilibrium, `null` where
/// the chart was not needed or not made.
pub(crate) fn poles_json(poles: &[Option<AtPole>]) -> serde_json::Value {
    use serde_json::json;
    let entry = |pole: &AtPole| match pole {
        AtPole::Rest(p) => json!({
            "kind": "rest",
            "polar": p.polar,
            "azimuth": p.azimuth,
            "chart": p.chart,
            "hessian": p.hessian,
            "eigenvalues": p.eigenvalues,
            "stable": p.stable,
            "sentence": pole.sentence(),
        }),
        AtPole::Spin(p) => json!({
            "kind": "spin",
            "polar": p.polar,
            "azimuth": p.azimuth,
            "chart": p.chart,
            "M": p.matrices[0],
            "G": p.matrices[1],
            "K": p.matrices[2],
            "eigenvalues": p.eigenvalues.iter().map(|(re, im)| [*re, *im]).collect::<Vec<_>>(),
            "stable": p.stable,
            "isotropic": p.isotropic.map(|(g2, m4k)| json!({ "g_squared": g2, "minus_4mk": m4k })),
            "sentence": pole.sentence(),
        }),
    };
    poles
        .iter()
        .map(|p| p.as_ref().map_or(serde_json::Value::Null, entry))
        .collect()
}

/// A factor as reports write it: `1` rather than `1.000000`.
fn number(x: f64) -> String {
    if (x - x.round()).abs() < 1e-9 {
        format!("{}", x.round())
    } else {
        format!("{x:.6}")
    }
}

/// The null vector of a symmetric matrix with exactly one null direction (relative tolerance
/// 1e-9), by Gaussian elimination with full pivoting; `None` otherwise.
fn null_vector(m: &[Vec<f64>]) -> Option<Vec<f64>> {
    let n = m.len();
    let mut a: Vec<Vec<f64>> = m.to_vec();
    let size = a.iter().flatten().fold(0.0_f64, |s, x| s.max(x.abs()));
    let tolerance = 1e-9 * size.max(f64::MIN_POSITIVE);
    let mut columns: Vec<usize> = (0..n).collect();
    let mut rank = 0;
    while rank < n {
        let (mut pi, mut pj, mut best) = (rank, rank, 0.0);
        for (i, row) in a.iter().enumerate().skip(rank) {
            for (j, &column) in columns.iter().enumerate().skip(rank) {
                if row[column].abs() > best {
                    (pi, pj, best) = (i, j, row[column].abs());
                }
            }
        }
        if best <= tolerance {
            break;
        }
        a.swap(rank, pi);
        columns.swap(rank, pj);
        let pivot_row = a[rank].clone();
        let pivot = pivot_row[columns[rank]];
        for (i, row) in a.iter_mut().enumerate() {
            if i != rank {
                let factor = row[columns[rank]] / pivot;
                for (x, p) in row.iter_mut().zip(&pivot_row) {
                    *x -= factor * p;
                }
            }
        }
        rank += 1;
    }
    if rank != n - 1 {
        return None;
    }
    // The free column is columns[n − 1]; back-substitute the pivots.
    let free = columns[n - 1];
    let mut x = vec![0.0; n];
    x[free] = 1.0;
    for r in 0..rank {
        let c = columns[r];
        x[c] = -a[r][free] / a[r][c];
    }
    let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
    Some(x.into_iter().map(|v| v / norm).collect())
}

/// A steady motion at a pole decided in the regular chart: the gyroscopic linearization
/// `M δs̈ + G δṡ + K δs = 0` of the chart's Lagrangian about the steady state, with the
/// cyclic coordinates reduced at constant momentum (Routh).
#[derive(Debug, Clone, PartialEq)]
pub struct PoleSpin {
    /// The polar angle and the azimuth, as in [`PoleStability`].
    pub polar: String,
    /// See [`PoleStability::azimuth`].
    pub azimuth: String,
    /// The reduced coordinates: `u`, `v`, then the non-cyclic others.
    pub chart: Vec<String>,
    /// `M`, `G` (skew) and `K` of the reduced linearization.
    pub matrices: [Vec<Vec<f64>>; 3],
    /// The eigenvalues `(re, im)` of its state matrix.
    pub eigenvalues: Vec<(f64, f64)>,
    /// Whether every eigenvalue is on the imaginary axis (within 1e-6 of the largest).
    pub stable: bool,
    /// For a reduced system `m I`, `g J`, `k I` in `(u, v)` alone (a symmetric top): the
    /// criterion's two sides `g²` and `−4 m k` (stable when `g² > −4 m k`).
    pub isotropic: Option<(f64, f64)>,
}

impl PoleSpin {
    /// The sentence reports print beneath the steady motion.
    #[must_use]
    pub fn sentence(&self) -> String {
        let verdict = if self.stable {
            "stable to first order (every eigenvalue of the gyroscopic linearization is on the imaginary axis)"
        } else {
            "unstable (an eigenvalue with a positive real part)"
        };
        let criterion = self.isotropic.map_or(String::new(), |(g2, m4k)| {
            format!(
                "; isotropic (M = m I, G = g J, K = k I in (u, v)): stable when g² > −4 m k, \
                 here {g2:.6} {} {m4k:.6}",
                if g2 > m4k { ">" } else { "≤" }
            )
        });
        format!(
            "at the pole of {} (where {} moves nothing): the steady motion decided in the \
             regular chart ({}): {verdict}{criterion}",
            self.polar,
            self.azimuth,
            self.chart.join(", ")
        )
    }
}

/// The offset of the points about which the chart's derivatives are taken (the pole itself
/// is where the model's coordinates fail): four points at this distance, averaged, which
/// cancels the odd terms and leaves an error of order its square.
const OFFSET: f64 = 1e-3;

/// The steady motion at the pole `q` with the coordinates `spinning` (index, rate) turning,
/// decided by the gyroscopic linearization in the regular chart; `None` when `q` is not a
/// pole, the system is not conservative, or the Lagrangian does not compile.
pub(crate) fn spin_at_pole(
    equations: &Equations,
    q: &[f64],
    spinning: &[(usize, f64)],
    values: &Values,
) -> Option<PoleSpin> {
    if equations.generalized_forces().iter().any(|f| !f.is_zero()) {
        return None;
    }
    let turning: Vec<usize> = spinning.iter().map(|(i, _)| *i).collect();
    let pole = Pole::find(equations, q, values, &turning)?;
    let chart = ChartLagrangian::new(equations, &pole, q, spinning, values)?;
    let n = q.len();
    let lagrangian = equations.lagrangian();
    let cyclic: Vec<bool> = (0..n)
        .map(|i| i >= 2 && lagrangian.diff(pole.symbols[chart.original[i]]).is_zero())
        .collect();
    // The steady rates must be those of cyclic coordinates (u̇ = v̇ = 0 always).
    if (0..n).any(|i| chart.rates[i] != 0.0 && !cyclic[i]) {
        return None;
    }
    let [mass, b, hessian] = chart.second_derivatives();
    let gyroscopic: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| b[i][j] - b[j][i]).collect())
        .collect();
    let stiffness: Vec<Vec<f64>> = hessian
        .iter()
        .map(|row| row.iter().map(|h| -h).collect())
        .collect();
    let [m, g, k] = routh(&[mass, gyroscopic, stiffness], &cyclic)?;
    let a = numeric::eigen::state_matrix(&m, &g, &k).ok()?;
    let eigenvalues = numeric::eigen::eigenvalues(&a).ok()?;
    let size = eigenvalues
        .iter()
        .fold(0.0_f64, |s, (re, im)| s.max(re.hypot(*im)));
    let stable = eigenvalues
        .iter()
        .all(|(re, _)| *re <= 1e-6 * size.max(f64::MIN_POSITIVE));
    let names = equations.coordinates();
    let mut coordinates = vec!["u".to_owned(), "v".to_owned()];
    coordinates.extend(
        (2..n)
            .filter(|&i| !cyclic[i])
            .map(|i| names[chart.original[i]].clone()),
    );
    Some(PoleSpin {
        polar: names[pole.polar].clone(),
        azimuth: names[pole.alpha].clone(),
        chart: coordinates,
        isotropic: isotropic(&m, &g, &k),
        matrices: [m, g, k],
        eigenvalues,
        stable,
    })
}

/// `(g², −4 m k)` when the reduced system is `m I`, `g J`, `k I` in two coordinates.
fn isotropic(m: &[Vec<f64>], g: &[Vec<f64>], k: &[Vec<f64>]) -> Option<(f64, f64)> {
    if m.len() != 2 {
        return None;
    }
    let close = |a: f64, b: f64, scale: f64| (a - b).abs() <= 1e-6 * scale.max(f64::MIN_POSITIVE);
    let (ms, gs, ks) = (m[0][0].abs(), g[0][1].abs(), k[0][0].abs());
    let ok = close(m[0][0], m[1][1], ms)
        && close(m[0][1], 0.0, ms)
        && close(k[0][0], k[1][1], ks)
        && close(k[0][1], 0.0, ks)
        && close(g[0][1], -g[1][0], gs);
    ok.then(|| (g[0][1] * g[0][1], -4.0 * m[0][0] * k[0][0]))
}

/// The linearization `[M, G, K]` reduced at constant momentum of the cyclic coordinates
/// `c` (Routh): with `x` the others, `δṡ_c = −M_cc⁻¹ (M_cx δẋ + G_cx δx)` gives
/// `M_r = M_xx − M_xc M_cc⁻¹ M_cx`, `G_r = G_xx − M_xc M_cc⁻¹ G_cx − G_xc M_cc⁻¹ M_cx`,
/// `K_r = K_xx − G_xc M_cc⁻¹ G_cx`.
fn routh(matrices: &[Vec<Vec<f64>>; 3], cyclic: &[bool]) -> Option<[Vec<Vec<f64>>; 3]> {
    let [m, g, k] = matrices;
    let x: Vec<usize> = (0..cyclic.len()).filter(|&i| !cyclic[i]).collect();
    let c: Vec<usize> = (0..cyclic.len()).filter(|&i| cyclic[i]).collect();
    let block = |a: &[Vec<f64>], rows: &[usize], cols: &[usize]| -> Vec<Vec<f64>> {
        rows.iter()
            .map(|&i| cols.iter().map(|&j| a[i][j]).collect())
            .collect()
    };
    if c.is_empty() {
        return Some([block(m, &x, &x), block(g, &x, &x), block(k, &x, &x)]);
    }
    let mcc = block(m, &c, &c);
    let inv_mcx = numeric::eigen::solve(&mcc, &block(m, &c, &x)).ok()?;
    let inv_gcx = numeric::eigen::solve(&mcc, &block(g, &c, &x)).ok()?;
    let product = |a: &[Vec<f64>], b: &[Vec<f64>]| -> Vec<Vec<f64>> {
        a.iter()
            .map(|row| {
                (0..b[0].len())
                    .map(|j| row.iter().zip(b).map(|(p, r)| p * r[j]).sum())
                    .collect()
            })
            .collect()
    };
    let minus = |a: Vec<Vec<f64>>, b: Vec<Vec<f64>>| -> Vec<Vec<f64>> {
        a.into_iter()
            .zip(b)
            .map(|(r, s)| r.into_iter().zip(s).map(|(p, q)| p - q).collect())
            .collect()
    };
    let (mxc, gxc) = (block(m, &x, &c), block(g, &x, &c));
    let mr = minus(block(m, &x, &x), product(&mxc, &inv_mcx));
    let gr = minus(
        minus(block(g, &x, &x), product(&mxc, &inv_gcx)),
        product(&gxc, &inv_mcx),
    );
    let kr = minus(block(k, &x, &x), product(&gxc, &inv_gcx));
    Some([mr, gr, kr])
}

/// The Lagrangian in the regular chart `s = (u, v, y…)` about a pole, compiled: `θ = θ* + r`,
/// `α = α* + atan2(v, u)`, `q_k = q*_k + y_k + c_k (α − α*)`.
pub(crate) struct ChartLagrangian {
    tape: numeric::Tape,
    registers: std::cell::RefCell<Vec<f64>>,
    inputs: std::cell::RefCell<Vec<f64>>,
    /// The model's coordinate behind each chart coordinate (θ, α, then the others).
    original: Vec<usize>,
    companions: Vec<f64>,
    rest: Vec<f64>,
    /// The steady rates `ṡ₀` in the chart.
    rates: Vec<f64>,
}

impl ChartLagrangian {
    pub(crate) fn new(
        equations: &Equations,
        pole: &Pole,
        q: &[f64],
        spinning: &[(usize, f64)],
        values: &Values,
    ) -> Option<ChartLagrangian> {
        let n = q.len();
        let mut original = vec![pole.polar, pole.alpha];
        original.extend((0..n).filter(|&k| k != pole.polar && k != pole.alpha));
        let companions: Vec<f64> = original.iter().map(|&k| pole.companion(k)).collect();
        let rate_of = |k: usize| {
            spinning
                .iter()
                .find(|(i, _)| *i == k)
                .map_or(0.0, |(_, r)| *r)
        };
        let alpha_rate = rate_of(pole.alpha);
        let mut rates = vec![0.0; n];
        for i in 2..n {
            rates[i] = rate_of(original[i]) - companions[i] * alpha_rate;
        }
        let names = equations.coordinates();
        let mut symbols = pole.symbols.clone();
        symbols.extend(
            names
                .iter()
                .map(|c| Expr::rate(c, 1).as_symbol())
                .collect::<Option<Vec<_>>>()?,
        );
        let mut inputs = vec![0.0; 2 * n];
        for (name, value) in values {
            if let Some(s) = Expr::symbol(name).as_symbol() {
                if !symbols.contains(&s) {
                    symbols.push(s);
                    inputs.push(*value);
                }
            }
        }
        let tape = numeric::Tape::compile(&[equations.lagrangian()], &symbols).ok()?;
        Some(ChartLagrangian {
            registers: std::cell::RefCell::new(tape.registers()),
            tape,
            inputs: std::cell::RefCell::new(inputs),
            original,
            companions,
            rest: q.to_vec(),
            rates,
        })
    }

    /// The name of the chart's coordinate `i ≥ 2`: the model's, or `β − c α` when it turns
    /// with the azimuth.
    pub(crate) fn name(&self, i: usize, names: &[String]) -> String {
        let (k, companion) = (self.original[i], self.companions[i]);
        if companion.abs() < 1e-12 {
            return names[k].clone();
        }
        let sign = if companion < 0.0 { "+" } else { "−" };
        let alpha = &names[self.original[1]];
        if (companion.abs() - 1.0).abs() < 1e-12 {
            return format!("{} {sign} {alpha}", names[k]);
        }
        format!("{} {sign} {} {alpha}", names[k], number(companion.abs()))
    }

    /// `L` at the chart's state `(s, ṡ)` (not at the pole itself: `r > 0`).
    fn at(&self, s: &[f64], rates: &[f64]) -> f64 {
        let n = s.len();
        let (u, v, du, dv) = (s[0], s[1], rates[0], rates[1]);
        let r2 = u * u + v * v;
        let r = r2.sqrt();
        let angle = v.atan2(u);
        let angle_rate = (u * dv - v * du) / r2;
        let mut inputs = self.inputs.borrow_mut();
        let (polar, alpha) = (self.original[0], self.original[1]);
        inputs[polar] = self.rest[polar] + r;
        inputs[n + polar] = (u * du + v * dv) / r;
        inputs[alpha] = self.rest[alpha] + angle;
        inputs[n + alpha] = angle_rate;
        for i in 2..n {
            let k = self.original[i];
            inputs[k] = self.rest[k] + s[i] + self.companions[i] * angle;
            inputs[n + k] = rates[i] + self.companions[i] * angle_rate;
        }
        let mut out = [0.0];
        self.tape
            .eval(&inputs, &mut self.registers.borrow_mut(), &mut out);
        out[0]
    }

    /// `[∂²L/∂ṡ∂ṡ, ∂²L/∂ṡ∂s, ∂²L/∂s∂s]` at `(0, ṡ₀)`, by central differences about four
    /// points at [`OFFSET`] from the pole, averaged.
    pub(crate) fn second_derivatives(&self) -> [Vec<Vec<f64>>; 3] {
        self.second_derivatives_at(OFFSET)
    }

    /// [`ChartLagrangian::second_derivatives`] about four points at `offset` from the pole.
    pub(crate) fn second_derivatives_at(&self, offset: f64) -> [Vec<Vec<f64>>; 3] {
        let n = self.rest.len();
        let mut sums = [
            vec![vec![0.0; n]; n],
            vec![vec![0.0; n]; n],
            vec![vec![0.0; n]; n],
        ];
        let bases = [[offset, 0.0], [-offset, 0.0], [0.0, offset], [0.0, -offset]];
        // `L` is quadratic in the rates, so any step is exact there; positions take a step
        // that keeps every point at least half the offset from the pole.
        let (dr, h) = (1.0, offset / 4.0);
        for base in bases {
            let mut s0 = vec![0.0; n];
            s0[..2].copy_from_slice(&base);
            let f = |ds: &[(usize, f64)], dv: &[(usize, f64)]| {
                let (mut s, mut v) = (s0.clone(), self.rates.clone());
                ds.iter().for_each(|(i, x)| s[*i] += x);
                dv.iter().for_each(|(i, x)| v[*i] += x);
                self.at(&s, &v)
            };
            let entry = |i: usize, j: usize| -> [f64; 3] {
                let vv = f(&[], &[(i, dr), (j, dr)])
                    - f(&[], &[(i, dr), (j, -dr)])
                    - f(&[], &[(i, -dr), (j, dr)])
                    + f(&[], &[(i, -dr), (j, -dr)]);
                let vs = f(&[(j, h)], &[(i, dr)])
                    - f(&[(j, h)], &[(i, -dr)])
                    - f(&[(j, -h)], &[(i, dr)])
                    + f(&[(j, -h)], &[(i, -dr)]);
                let ss = f(&[(i, h), (j, h)], &[])
                    - f(&[(i, h), (j, -h)], &[])
                    - f(&[(i, -h), (j, h)], &[])
                    + f(&[(i, -h), (j, -h)], &[]);
                [
                    vv / (4.0 * dr * dr),
                    vs / (4.0 * h * dr),
                    ss / (4.0 * h * h),
                ]
            };
            for (i, j) in (0..n).flat_map(|i| (0..n).map(move |j| (i, j))) {
                let values = entry(i, j);
                for (sum, value) in sums.iter_mut().zip(values) {
                    sum[i][j] += value / bases.len() as f64;
                }
            }
        }
        sums
    }
}

/// The steady motion at the pole `q` (exact values `exact`) stated in the parameters, when
/// its chart linearization is isotropic (`PoleSpin::isotropic`) and one coordinate turning
/// with the azimuth is cyclic (the top's `w = ψ + φ`): `m`, `γ`, `k` of
/// `mechanics::stability_condition::isotropic_condition` from the chart's Routhian at
/// constant momentum `p = M'_ww ω` of the cyclic coordinate, along the polar angle:
///
/// `m = M'_θθ − M'_θw²/M'_ww`, `γ = d²/dθ² (p M'_wα/M'_ww)`, `k = d²/dθ² (V + p²/(2 M'_ww))`
///
/// at `θ*`, with `M' = Tᵀ M T` the mass matrix in `(θ, α, w)`. (Smoothness in `(u, v)` makes
/// the Routhian's linear term `a(θ) dα = ½ γ r² dα`, whose curl is `γ`.)
pub(crate) fn spin_condition_at_pole(
    equations: &Equations,
    (q, exact): (&[f64], &[Expr]),
    spinning: &[(usize, f64)],
    values: &Values,
    positive: &dyn Fn(Symbol) -> bool,
) -> Option<mechanics::stability_condition::StabilityCondition> {
    let n = q.len();
    let turning: Vec<usize> = spinning.iter().map(|(i, _)| *i).collect();
    let pole = Pole::find(equations, q, values, &turning)?;
    if n != 3 || exact.len() != n {
        return None;
    }
    let w = (0..n).find(|&k| k != pole.polar && k != pole.alpha)?;
    if !equations.lagrangian().diff(pole.symbols[w]).is_zero() {
        return None;
    }
    let companion = small_fraction(pole.companion(w))?;
    // q̇ = T (θ̇, α̇, ẇ): the coordinate w turns with the azimuth by its companion factor.
    let order = [pole.polar, pole.alpha, w];
    let transform = |row: usize, column: usize| -> Expr {
        match (row == order[column], row == w && column == 1) {
            (true, _) => Expr::one(),
            (_, true) => companion,
            _ => Expr::zero(),
        }
    };
    let m = equations.mass_matrix();
    let chart_mass = |a: usize, b: usize| -> Expr {
        let terms = (0..n).flat_map(|i| (0..n).map(move |j| (i, j)));
        Expr::add_all(terms.map(|(i, j)| transform(i, a) * m[i][j] * transform(j, b)))
    };
    // Along the polar angle: every other coordinate at its exact value.
    let theta = pole.symbols[pole.polar];
    let along: Vec<(Expr, Expr)> = (0..n)
        .filter(|&k| k != pole.polar)
        .map(|k| (Expr::from_symbol(pole.symbols[k]), exact[k]))
        .collect();
    let at_pole = |e: Expr| -> Expr {
        let pairs = [(Expr::from_symbol(theta), exact[pole.polar])];
        e.subs(&pairs).normal()
    };
    let [m_tt, m_tw, m_ww, m_wa] =
        [(0, 0), (0, 2), (2, 2), (2, 1)].map(|(a, b)| chart_mass(a, b).subs(&along).normal());
    let names = equations.coordinates();
    let rate = |k: usize| {
        if turning.contains(&k) {
            spin_rate(&names[k])
        } else {
            Expr::zero()
        }
    };
    let omega = rate(w) - companion * rate(pole.alpha);
    let momentum = at_pole(m_ww * omega);
    let twice = |e: Expr| at_pole(e.diff(theta).diff(theta));
    let mass = at_pole(m_tt - m_tw.powi(2) / m_ww);
    let gamma = twice(momentum * m_wa / m_ww);
    let potential = equations.potential_energy().subs(&along);
    let stiffness = twice(potential + momentum.powi(2) / (2 * m_ww));
    Some(mechanics::stability_condition::isotropic_condition(
        [mass, gamma, stiffness],
        positive,
    ))
}

/// `x` as an exact fraction with a denominator up to 12 (a companion factor, ±1 for the
/// top), or `None`.
fn small_fraction(x: f64) -> Option<Expr> {
    (1..=12_i64).find_map(|d| {
        let k = (x * d as f64).round();
        ((x * d as f64 - k).abs() < 1e-9).then(|| Expr::rational(k as i64, d))?
    })
}
