//! The adaptive loop shared by the explicit embedded Runge–Kutta pairs (dopri5, dop853):
//! choose the first step, try a step, accept or reject it by its error estimate, test for
//! stiffness, hand the accepted step and its dense output to the driver, and reuse the last
//! stage's derivative as the next step's first (FSAL). Each pair supplies its stages, its
//! error measure, its continuous extension and its step-size factors ([`Pair`]).

use super::{
    initial_step, Driver, Failure, Observer, Stiffness, StopReason, STIFF_H_LAMBDA,
    STIFF_PROJECTED_STEPS,
};

/// One explicit embedded pair with FSAL and a continuous extension.
pub(super) trait Pair {
    /// The order that sets the starting step.
    const ORDER: i32;
    /// Whether the continuous extension costs evaluations of the right-hand side (then it is
    /// built only for a step that holds an output row or an event).
    const DENSE_COSTS_EVALUATIONS: bool;
    /// `h·|λ|` above which a step is near the boundary of the stability region.
    const STIFF_THRESHOLD: f64 = STIFF_H_LAMBDA;

    /// The derivative at the step's start (the first stage).
    fn first_stage(&mut self) -> &mut [f64];
    /// The stages of a step of size `hs` from `(t, driver.y)` and the new point; a failed
    /// evaluation is returned.
    fn stages(&mut self, driver: &mut Driver<'_>, t: f64, hs: f64) -> Option<Failure>;
    /// The error of the step just tried, in units of the tolerance (≤ 1 accepts it).
    fn error(&mut self, driver: &Driver<'_>, h: f64, hs: f64) -> f64;
    /// Evaluates the derivative at the new point where the stages did not (FSAL).
    fn new_point_rate(&mut self, driver: &mut Driver<'_>, t1: f64) -> Result<(), Failure>;
    /// `(f(y₁), f(Y_s), y₁, Y_s)`: the new point and the last stage, both at `t + h`, with
    /// their derivatives, for the stiffness test.
    fn stiffness_pair(&self) -> [&[f64]; 4];
    /// Builds the continuous extension over the accepted step.
    fn dense(&mut self, driver: &mut Driver<'_>, t: f64, hs: f64) -> Result<(), Failure>;
    /// The continuous extension at `θ = (t − t₀)/h`.
    fn interpolate(&self, theta: f64, out: &mut [f64]);
    /// The new point.
    fn new_point(&self) -> &[f64];
    /// The new point's derivative becomes the next step's first stage.
    fn reuse_new_point_rate(&mut self);
    /// The step-size factor after an accepted step.
    fn accepted_factor(err: f64, previous_error: f64, rejected_last: bool) -> f64;
    /// The step-size factor after a rejected step (a tenth after a failed evaluation).
    fn rejection_factor(err: f64) -> f64;
}

/// Integrates with `pair` to the driver's end, an event, or a failure.
pub(super) fn run<P: Pair>(
    pair: &mut P,
    driver: &mut Driver<'_>,
    observer: &mut Observer<'_>,
) -> StopReason {
    match steps(pair, driver, observer) {
        Ok(stop) => stop,
        Err(failure) => StopReason::Failed(failure),
    }
}

fn steps<P: Pair>(
    pair: &mut P,
    driver: &mut Driver<'_>,
    observer: &mut Observer<'_>,
) -> Result<StopReason, Failure> {
    let direction = driver.direction;
    let y0 = driver.y.clone();
    driver.rhs(driver.t, &y0, pair.first_stage())?;
    let mut h = match driver.options.step {
        Some(h) if h.is_finite() && h > 0.0 => h,
        _ => {
            let f0 = pair.first_stage().to_vec();
            initial_step(driver, &f0, P::ORDER)?
        }
    };
    let mut previous_error: f64 = 1e-4;
    let mut rejected_last = false;
    let mut stiffness = Stiffness::new(P::STIFF_THRESHOLD);
    loop {
        let t = driver.t;
        let span = (driver.t_end - t).abs();
        if h >= span {
            h = span;
        }
        if let Some(failure) = driver.too_small(t, h) {
            return Err(failure);
        }
        let (min_step, _) = driver.step_floor(t);
        let hs = h * direction;
        let err = match pair.stages(driver, t, hs) {
            // A failed evaluation inside the step (NaN, a singular matrix met on the way) is
            // treated as a rejection with a much smaller step; only at the step floor is it
            // reported, with the time of the step (the next try, a tenth of this one,
            // would be below the floor).
            Some(e) => {
                if h <= 1e3 * min_step || 0.1 * h < min_step {
                    return Err(match e {
                        Failure::Rhs { error, .. } => Failure::Rhs { t, error },
                        other => other,
                    });
                }
                f64::INFINITY
            }
            None => pair.error(driver, h, hs),
        };
        if err > 1.0 {
            driver.stats.rejected += 1;
            rejected_last = true;
            h *= P::rejection_factor(err);
            continue;
        }
        let factor = P::accepted_factor(err, previous_error, rejected_last);
        previous_error = err.max(1e-4);
        rejected_last = false;
        let t1 = if h == span { driver.t_end } else { t + hs };
        if let Err(e) = pair.new_point_rate(driver, t1) {
            // The new point itself cannot be evaluated: retry with a tenth of the step.
            if 0.1 * h < min_step {
                return Err(e);
            }
            driver.stats.rejected += 1;
            rejected_last = true;
            h *= 0.1;
            continue;
        }
        let [rate, stage_rate, y1, stage] = pair.stiffness_pair();
        if let Some(steps) = stiffness.observe(h, rate, stage_rate, y1, stage) {
            let remaining = (driver.t_end - t).abs() / h;
            if remaining > STIFF_PROJECTED_STEPS {
                return Err(Failure::Stiff {
                    t,
                    h,
                    h_lambda: stiffness.last,
                    steps,
                    remaining,
                });
            }
        }
        if !P::DENSE_COSTS_EVALUATIONS || driver.interpolation_needed(t1, pair.new_point()) {
            pair.dense(driver, t, hs)?;
        }
        let accepted = {
            let pair = &*pair;
            let interpolate = |at: f64, out: &mut [f64]| pair.interpolate((at - t) / hs, out);
            driver.accept(t1, pair.new_point(), &interpolate, observer)
        };
        if let Some(stop) = accepted {
            return Ok(stop);
        }
        if driver.project()? {
            let y = driver.y.clone();
            driver.rhs(driver.t, &y, pair.first_stage())?;
        } else {
            pair.reuse_new_point_rate();
        }
        h *= factor;
    }
}
