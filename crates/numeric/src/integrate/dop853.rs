//! Dormand–Prince 8(5,3): the explicit Runge–Kutta method of order 8 with twelve stages,
//! FSAL, an error estimate that combines an embedded fifth-order and a third-order formula,
//! Hairer's step-size control with its stabilisation term, his stiffness test, and the
//! seventh-order continuous extension (three more stages, evaluated only for a step that
//! holds an output row or an event) — Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.10, and
//! Hairer's code DOP853.
//!
//! Fewer, longer steps than [`super::Method::Dopri5`] at tight tolerances: an 8th-order
//! local error shrinks as `h⁹`, so halving the tolerance lengthens its steps by 2^(1/8)
//! against dopri5's 2^(1/5).

// The coefficients are copied digit for digit from the published tables, so that they can be
// checked against them; f64 rounds them on reading.
#![allow(clippy::excessive_precision)]

use super::explicit::{self, Pair};
use super::{Driver, Failure, Observer, StopReason};

/// Hairer's stiffness threshold for DOP853: `h·|λ|` above it (near the boundary of its
/// stability region on the negative real axis, about 6.1) is a step limited by stability.
const STIFF_H_LAMBDA: f64 = 6.1;

/// The exponent of the stabilising (Lund) term of the step-size controller, `β` in Hairer's
/// code, whose default for DOP853 is 0 (a pure I controller, as SciPy's). Measured on the
/// n-link pendulum (10 s from θ₁ = 0.5, rtol 1e-9, atol 1e-11), evaluations for
/// n = 2 / 5 / 10: β = 0: 3538 / 6120 / 9072 (64 / 98 / 146 steps rejected); β = 0.04:
/// 3419 / 5989 / 8865 (39 / 61 / 89 rejected); β = 0.08: 3792 / 6828 / 10128 (2 rejected).
const BETA: f64 = 0.04;

/// The nodes `c₁ … c₁₂` of the twelve stages (stage 12 and the FSAL stage at `t + h`), then
/// `c₁₄ … c₁₆` of the dense output's three (`c₁₃ = 1` is the FSAL stage).
///
/// The coefficients of this file are Hairer's, from the code `dop853.f` (Hairer & Wanner,
/// 1989–2004), as tabulated in SciPy's `scipy/integrate/_ivp/dop853_coefficients.py`.
const C: [f64; 16] = [
    0.0,
    0.526001519587677318785587544488e-01,
    0.789002279381515978178381316732e-01,
    0.118350341907227396726757197510,
    0.281649658092772603273242802490,
    0.333333333333333333333333333333,
    0.25,
    0.307692307692307692307692307692,
    0.651282051282051282051282051282,
    0.6,
    0.857142857142857142857142857142,
    1.0,
    1.0,
    0.1,
    0.2,
    0.777777777777777777777777777778,
];

/// A row of the Butcher matrix: the nonzero `(j, a_ij)`.
type Row = &'static [(usize, f64)];

/// Rows 2…12 of the Butcher matrix (stage `i` from stages `j < i`, 0-based), then the
/// weights `b` of the eighth-order solution (row 13).
const A: [Row; 12] = [
    &[(0, 5.26001519587677318785587544488e-2)],
    &[
        (0, 1.97250569845378994544595329183e-2),
        (1, 5.91751709536136983633785987549e-2),
    ],
    &[
        (0, 2.95875854768068491816892993775e-2),
        (2, 8.87627564304205475450678981324e-2),
    ],
    &[
        (0, 2.41365134159266685502369798665e-1),
        (2, -8.84549479328286085344864962717e-1),
        (3, 9.24834003261792003115737966543e-1),
    ],
    &[
        (0, 3.7037037037037037037037037037e-2),
        (3, 1.70828608729473871279604482173e-1),
        (4, 1.25467687566822425016691814123e-1),
    ],
    &[
        (0, 3.7109375e-2),
        (3, 1.70252211019544039314978060272e-1),
        (4, 6.02165389804559606850219397283e-2),
        (5, -1.7578125e-2),
    ],
    &[
        (0, 3.70920001185047927108779319836e-2),
        (3, 1.70383925712239993810214054705e-1),
        (4, 1.07262030446373284651809199168e-1),
        (5, -1.53194377486244017527936158236e-2),
        (6, 8.27378916381402288758473766002e-3),
    ],
    &[
        (0, 6.24110958716075717114429577812e-1),
        (3, -3.36089262944694129406857109825),
        (4, -8.68219346841726006818189891453e-1),
        (5, 2.75920996994467083049415600797e1),
        (6, 2.01540675504778934086186788979e1),
        (7, -4.34898841810699588477366255144e1),
    ],
    &[
        (0, 4.77662536438264365890433908527e-1),
        (3, -2.48811461997166764192642586468),
        (4, -5.90290826836842996371446475743e-1),
        (5, 2.12300514481811942347288949897e1),
        (6, 1.52792336328824235832596922938e1),
        (7, -3.32882109689848629194453265587e1),
        (8, -2.03312017085086261358222928593e-2),
    ],
    &[
        (0, -9.3714243008598732571704021658e-1),
        (3, 5.18637242884406370830023853209),
        (4, 1.09143734899672957818500254654),
        (5, -8.14978701074692612513997267357),
        (6, -1.85200656599969598641566180701e1),
        (7, 2.27394870993505042818970056734e1),
        (8, 2.49360555267965238987089396762),
        (9, -3.0467644718982195003823669022),
    ],
    &[
        (0, 2.27331014751653820792359768449),
        (3, -1.05344954667372501984066689879e1),
        (4, -2.00087205822486249909675718444),
        (5, -1.79589318631187989172765950534e1),
        (6, 2.79488845294199600508499808837e1),
        (7, -2.85899827713502369474065508674),
        (8, -8.87285693353062954433549289258),
        (9, 1.23605671757943030647266201528e1),
        (10, 6.43392746015763530355970484046e-1),
    ],
    &[
        (0, 5.42937341165687622380535766363e-2),
        (5, 4.45031289275240888144113950566),
        (6, 1.89151789931450038304281599044),
        (7, -5.8012039600105847814672114227),
        (8, 3.1116436695781989440891606237e-1),
        (9, -1.52160949662516078556178806805e-1),
        (10, 2.01365400804030348374776537501e-1),
        (11, 4.47106157277725905176885569043e-2),
    ],
];

/// The weights of the eighth-order solution (the last row of [`A`]) minus those of the
/// third-order one: `b − b̂₃` (nonzero at stages 1, 9 and 12).
const E3: [(usize, f64); 8] = [
    (
        0,
        5.42937341165687622380535766363e-2 - 0.244094488188976377952755905512,
    ),
    (5, 4.45031289275240888144113950566),
    (6, 1.89151789931450038304281599044),
    (7, -5.8012039600105847814672114227),
    (
        8,
        3.1116436695781989440891606237e-1 - 0.733846688281611857341361741547,
    ),
    (9, -1.52160949662516078556178806805e-1),
    (10, 2.01365400804030348374776537501e-1),
    (
        11,
        4.47106157277725905176885569043e-2 - 0.220588235294117647058823529412e-1,
    ),
];

/// `b − b̂₅`: the eighth-order weights minus the embedded fifth-order ones.
const E5: [(usize, f64); 8] = [
    (0, 0.1312004499419488073250102996e-1),
    (5, -0.1225156446376204440720569753e1),
    (6, -0.4957589496572501915214079952),
    (7, 0.1664377182454986536961530415e1),
    (8, -0.3503288487499736816886487290),
    (9, 0.3341791187130174790297318841),
    (10, 0.8192320648511571246570742613e-1),
    (11, -0.2235530786388629525884427845e-1),
];

/// Rows 14…16 of the Butcher matrix: the dense output's extra stages, from the twelve
/// stages and the FSAL stage (index 12) and from each other.
const A_DENSE: [Row; 3] = [
    &[
        (0, 5.61675022830479523392909219681e-2),
        (6, 2.53500210216624811088794765333e-1),
        (7, -2.46239037470802489917441475441e-1),
        (8, -1.24191423263816360469010140626e-1),
        (9, 1.5329179827876569731206322685e-1),
        (10, 8.20105229563468988491666602057e-3),
        (11, 7.56789766054569976138603589584e-3),
        (12, -8.298e-3),
    ],
    &[
        (0, 3.18346481635021405060768473261e-2),
        (5, 2.83009096723667755288322961402e-2),
        (6, 5.35419883074385676223797384372e-2),
        (7, -5.49237485713909884646569340306e-2),
        (10, -1.08347328697249322858509316994e-4),
        (11, 3.82571090835658412954920192323e-4),
        (12, -3.40465008687404560802977114492e-4),
        (13, 1.41312443674632500278074618366e-1),
    ],
    &[
        (0, -4.28896301583791923408573538692e-1),
        (5, -4.69762141536116384314449447206),
        (6, 7.68342119606259904184240953878),
        (7, 4.06898981839711007970213554331),
        (8, 3.56727187455281109270669543021e-1),
        (12, -1.39902416515901462129418009734e-3),
        (13, 2.9475147891527723389556272149),
        (14, -9.15095847217987001081870187138),
    ],
];

/// The coefficients `d₄ … d₇` of the continuous extension over the sixteen stages.
const D: [[(usize, f64); 12]; 4] = [
    [
        (0, -0.84289382761090128651353491142e1),
        (5, 0.56671495351937776962531783590),
        (6, -0.30689499459498916912797304727e1),
        (7, 0.23846676565120698287728149680e1),
        (8, 0.21170345824450282767155149946e1),
        (9, -0.87139158377797299206789907490),
        (10, 0.22404374302607882758541771650e1),
        (11, 0.63157877876946881815570249290),
        (12, -0.88990336451333310820698117400e-1),
        (13, 0.18148505520854727256656404962e2),
        (14, -0.91946323924783554000451984436e1),
        (15, -0.44360363875948939664310572000e1),
    ],
    [
        (0, 0.10427508642579134603413151009e2),
        (5, 0.24228349177525818288430175319e3),
        (6, 0.16520045171727028198505394887e3),
        (7, -0.37454675472269020279518312152e3),
        (8, -0.22113666853125306036270938578e2),
        (9, 0.77334326684722638389603898808e1),
        (10, -0.30674084731089398182061213626e2),
        (11, -0.93321305264302278729567221706e1),
        (12, 0.15697238121770843886131091075e2),
        (13, -0.31139403219565177677282850411e2),
        (14, -0.93529243588444783865713862664e1),
        (15, 0.35816841486394083752465898540e2),
    ],
    [
        (0, 0.19985053242002433820987653617e2),
        (5, -0.38703730874935176555105901742e3),
        (6, -0.18917813819516756882830838328e3),
        (7, 0.52780815920542364900561016686e3),
        (8, -0.11573902539959630126141871134e2),
        (9, 0.68812326946963000169666922661e1),
        (10, -0.10006050966910838403183860980e1),
        (11, 0.77771377980534432092869265740),
        (12, -0.27782057523535084065932004339e1),
        (13, -0.60196695231264120758267380846e2),
        (14, 0.84320405506677161018159903784e2),
        (15, 0.11992291136182789328035130030e2),
    ],
    [
        (0, -0.25693933462703749003312586129e2),
        (5, -0.15418974869023643374053993627e3),
        (6, -0.23152937917604549567536039109e3),
        (7, 0.35763911791061412378285349910e3),
        (8, 0.93405324183624310003907691704e2),
        (9, -0.37458323136451633156875139351e2),
        (10, 0.10409964950896230045147246184e3),
        (11, 0.29840293426660503123344363579e2),
        (12, -0.43533456590011143754432175058e2),
        (13, 0.96324553959188282948394950600e2),
        (14, -0.39177261675615439165231486172e2),
        (15, -0.14972683625798562581422125276e3),
    ],
];

/// The stages of a step: `k[0..12]` the derivatives of the twelve stages, `k[12]` the FSAL
/// derivative at the new point, `k[13..16]` the dense output's.
type Stages = [Vec<f64>; 16];

pub(super) fn run(driver: &mut Driver<'_>, observer: &mut Observer<'_>) -> StopReason {
    let n = driver.y.len();
    let mut pair = Dop853 {
        k: std::array::from_fn(|_| vec![0.0; n]),
        work: Work {
            stage: vec![0.0; n],
            y1: vec![0.0; n],
            dense: std::array::from_fn(|_| vec![0.0; n]),
        },
    };
    explicit::run(&mut pair, driver, observer)
}

/// Work vectors of a step besides the stages.
struct Work {
    /// The state of the stage being evaluated; after a step, stage 12's (at `t + h`).
    stage: Vec<f64>,
    /// The new point.
    y1: Vec<f64>,
    /// The dense output's coefficients over the last accepted step.
    dense: [Vec<f64>; 8],
}

/// The stages and work vectors of the method.
struct Dop853 {
    k: Stages,
    work: Work,
}

impl Pair for Dop853 {
    const ORDER: i32 = 8;
    const DENSE_COSTS_EVALUATIONS: bool = true;
    const STIFF_THRESHOLD: f64 = STIFF_H_LAMBDA;

    fn first_stage(&mut self) -> &mut [f64] {
        &mut self.k[0]
    }

    fn stages(&mut self, driver: &mut Driver<'_>, t: f64, hs: f64) -> Option<Failure> {
        stages(driver, &mut self.k, &mut self.work, t, hs)
    }

    fn error(&mut self, driver: &Driver<'_>, h: f64, _hs: f64) -> f64 {
        error_norm(driver, &self.k, &self.work.y1, h)
    }

    /// The FSAL stage `k[12]`, at the new point.
    fn new_point_rate(&mut self, driver: &mut Driver<'_>, t1: f64) -> Result<(), Failure> {
        driver.rhs(t1, &self.work.y1, &mut self.k[12])
    }

    /// Stage 12 (`work.stage`, derivative k₁₂) and the new point (y₁, its derivative k₁₃).
    fn stiffness_pair(&self) -> [&[f64]; 4] {
        [&self.k[12], &self.k[11], &self.work.y1, &self.work.stage]
    }

    fn dense(&mut self, driver: &mut Driver<'_>, t: f64, hs: f64) -> Result<(), Failure> {
        dense_output(driver, &mut self.k, &mut self.work, t, hs)
    }

    fn interpolate(&self, theta: f64, out: &mut [f64]) {
        evaluate_dense(&self.work.dense, theta, out);
    }

    fn new_point(&self) -> &[f64] {
        &self.work.y1
    }

    fn reuse_new_point_rate(&mut self) {
        let (first, rest) = self.k.split_at_mut(1);
        first[0].copy_from_slice(&rest[11]);
    }

    fn accepted_factor(err: f64, previous_error: f64, rejected_last: bool) -> f64 {
        accepted_factor(err, previous_error, rejected_last)
    }

    fn rejection_factor(err: f64) -> f64 {
        rejection_factor(err)
    }
}

/// `out = y + hs Σ_j a_j k_j`.
fn combine(out: &mut [f64], y: &[f64], k: &Stages, row: Row, hs: f64) {
    for (i, value) in out.iter_mut().enumerate() {
        let acc: f64 = row.iter().map(|&(j, a)| a * k[j][i]).sum();
        *value = y[i] + hs * acc;
    }
}

/// Stages 2…12 of a step of size `hs` from `(t, driver.y)` and the new point `work.y1`
/// (whose derivative, the FSAL stage, the caller evaluates). A failed evaluation is returned.
fn stages(
    driver: &mut Driver<'_>,
    k: &mut Stages,
    work: &mut Work,
    t: f64,
    hs: f64,
) -> Option<Failure> {
    for s in 1..12 {
        combine(&mut work.stage, &driver.y, k, A[s - 1], hs);
        if let Err(e) = driver.rhs(t + C[s] * hs, &work.stage, &mut k[s]) {
            return Some(e);
        }
    }
    combine(&mut work.y1, &driver.y, k, A[11], hs);
    None
}

/// Hairer's error measure for DOP853: with `e₅ = Σ(b − b̂₅)k` and `e₃ = Σ(b − b̂₃)k`
/// weighted by `sc = atol + rtol·max(|y₀|, |y₁|)`, `|h|·‖e₅‖² / √(n·(‖e₅‖² + 0.01‖e₃‖²))`:
/// the fifth-order estimate, damped by the third-order one where the two disagree (which
/// keeps the estimate honest when the fifth-order one is accidentally small).
fn error_norm(driver: &Driver<'_>, k: &Stages, y1: &[f64], h: f64) -> f64 {
    let (rtol, atol) = (driver.options.rtol, driver.options.atol);
    let (mut sum5, mut sum3) = (0.0, 0.0);
    for (i, (a, b)) in driver.y.iter().zip(y1).enumerate() {
        let scale = atol + rtol * a.abs().max(b.abs());
        let e5: f64 = E5.iter().map(|&(j, w)| w * k[j][i]).sum();
        let e3: f64 = E3.iter().map(|&(j, w)| w * k[j][i]).sum();
        sum5 += (e5 / scale).powi(2);
        sum3 += (e3 / scale).powi(2);
    }
    let denominator = sum5 + 0.01 * sum3;
    if denominator <= 0.0 {
        return 0.0;
    }
    h * sum5 / (denominator * y1.len().max(1) as f64).sqrt()
}

/// The step-size factor after a rejected step (a tenth after a failed evaluation).
fn rejection_factor(err: f64) -> f64 {
    if err.is_finite() {
        (0.9 * err.powf(-0.125)).clamp(1.0 / 3.0, 1.0)
    } else {
        0.1
    }
}

/// The step-size factor after an accepted step: Hairer's `0.9·err^(−1/8 + β/5)·err_prev^β`
/// (see [`BETA`]), between 1/3 and 6, not growing right after a rejection.
fn accepted_factor(err: f64, previous_error: f64, rejected_last: bool) -> f64 {
    let factor = if err == 0.0 {
        6.0
    } else {
        (0.9 * err.powf(-0.125 + 0.2 * BETA) * previous_error.powf(BETA)).clamp(1.0 / 3.0, 6.0)
    };
    if rejected_last {
        factor.min(1.0)
    } else {
        factor
    }
}

/// The three extra stages and the coefficients of the seventh-order continuous extension
/// over the accepted step from `driver.y` to `work.y1` (`k[12]` already holds the
/// derivative at `y1`).
fn dense_output(
    driver: &mut Driver<'_>,
    k: &mut Stages,
    work: &mut Work,
    t: f64,
    hs: f64,
) -> Result<(), Failure> {
    for (s, row) in A_DENSE.iter().enumerate() {
        combine(&mut work.stage, &driver.y, k, row, hs);
        driver.rhs(t + C[13 + s] * hs, &work.stage, &mut k[13 + s])?;
    }
    let dense = &mut work.dense;
    for i in 0..driver.y.len() {
        let (y0, y1) = (driver.y[i], work.y1[i]);
        let ydiff = y1 - y0;
        let bspl = hs * k[0][i] - ydiff;
        dense[0][i] = y0;
        dense[1][i] = ydiff;
        dense[2][i] = bspl;
        dense[3][i] = ydiff - hs * k[12][i] - bspl;
        for (r, row) in D.iter().enumerate() {
            dense[4 + r][i] = hs * row.iter().map(|&(j, d)| d * k[j][i]).sum::<f64>();
        }
    }
    Ok(())
}

/// The continuous extension at `θ = (t − t₀)/h`, Hairer's `CONTD8`:
/// `r₁ + θ(r₂ + θ₁(r₃ + θ(r₄ + θ₁(r₅ + θ(r₆ + θ₁(r₇ + θ r₈))))))`, `θ₁ = 1 − θ`.
fn evaluate_dense(dense: &[Vec<f64>; 8], theta: f64, out: &mut [f64]) {
    let theta1 = 1.0 - theta;
    for (i, value) in out.iter_mut().enumerate() {
        let inner =
            dense[4][i] + theta * (dense[5][i] + theta1 * (dense[6][i] + theta * dense[7][i]));
        *value = dense[0][i]
            + theta
                * (dense[1][i] + theta1 * (dense[2][i] + theta * (dense[3][i] + theta1 * inner)));
    }
}
