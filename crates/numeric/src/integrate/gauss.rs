//! Three-stage Gauss–Legendre collocation (order 6) with a fixed step. The method is
//! symplectic and symmetric: applied to Hamilton's equations its energy error does not drift
//! but oscillates, bounded, over very long runs (Hairer, Lubich & Wanner, *Geometric Numerical
//! Integration*, §VI.4 and §X.3). The stage equations are solved by fixed-point iteration to
//! rounding level (right for the non-stiff mechanics it is meant for), and the update uses
//! compensated summation so rounding does not drift over 10⁶ steps either.
//!
//! The step stays fixed (a varying step breaks the symplectic structure), but unless the user
//! gives one it is chosen from the dynamics by a pilot: a window of [`PILOT_STEPS`] steps of
//! `h` and twice as many of `h/2` from the start; their difference (Richardson, order 6) is the
//! error of the `h` run over the window, extrapolated linearly in time to the whole span (the
//! global error of a symplectic method on a near-integrable system grows linearly: a phase
//! error). `h` is shrunk or grown until that extrapolated error is within the tolerances. The
//! pilot's number for the step used (the run's step is that one or slightly shorter, to land
//! on the end time) is reported as [`super::Outcome::error_estimate`]. A chosen step below
//! [`super::STEP_COLLAPSE_FRACTION`] of the span stops the run as a collapse, as for the
//! adaptive methods.

use super::{hermite, Driver, Failure, Observer, RhsError, StopReason, STIFF_PROJECTED_STEPS};

const SQRT15: f64 = 3.872_983_346_207_417;
const C: [f64; 3] = [0.5 - SQRT15 / 10.0, 0.5, 0.5 + SQRT15 / 10.0];
const B: [f64; 3] = [5.0 / 18.0, 4.0 / 9.0, 5.0 / 18.0];
const A: [[f64; 3]; 3] = [
    [
        5.0 / 36.0,
        2.0 / 9.0 - SQRT15 / 15.0,
        5.0 / 36.0 - SQRT15 / 30.0,
    ],
    [
        5.0 / 36.0 + SQRT15 / 24.0,
        2.0 / 9.0,
        5.0 / 36.0 - SQRT15 / 24.0,
    ],
    [
        5.0 / 36.0 + SQRT15 / 30.0,
        2.0 / 9.0 + SQRT15 / 15.0,
        5.0 / 36.0,
    ],
];
const MAX_ITERATIONS: usize = 100;
/// Steps of `h` in the pilot window (and twice as many of `h/2`).
pub const PILOT_STEPS: usize = 64;
/// Pilot rounds before the step is taken as it is.
const PILOT_ROUNDS: usize = 12;

/// Buffers of one step.
struct Stepper {
    k: [Vec<f64>; 3],
    next: [Vec<f64>; 3],
    stage: Vec<f64>,
}

impl Stepper {
    fn new(n: usize) -> Stepper {
        Stepper {
            k: std::array::from_fn(|_| vec![0.0; n]),
            next: std::array::from_fn(|_| vec![0.0; n]),
            stage: vec![0.0; n],
        }
    }

    /// Solves the stage equations of a step `h` from `(t, y)` (with `f0 = F(t, y)` as the
    /// first guess), leaving the stage derivatives in `self.k`.
    fn solve(
        &mut self,
        driver: &mut Driver<'_>,
        t: f64,
        y: &[f64],
        f0: &[f64],
        h: f64,
    ) -> Result<(), Failure> {
        for ki in &mut self.k {
            ki.copy_from_slice(f0);
        }
        let mut previous = f64::INFINITY;
        for iteration in 0..MAX_ITERATIONS {
            for s in 0..3 {
                for (i, (stage, yi)) in self.stage.iter_mut().zip(y).enumerate() {
                    *stage = yi
                        + h * (A[s][0] * self.k[0][i]
                            + A[s][1] * self.k[1][i]
                            + A[s][2] * self.k[2][i]);
                }
                // A stage that is not finite is the iteration diverging (a step beyond the
                // fastest time scale: stiffness), unless the state itself is not.
                match driver.rhs(t + C[s] * h, &self.stage, &mut self.next[s]) {
                    Err(Failure::Rhs {
                        error: RhsError::NotFinite,
                        ..
                    }) if y.iter().all(|v| v.is_finite()) => {
                        return Err(Failure::NotConverged { t, h: h.abs() });
                    }
                    other => other?,
                }
            }
            let mut change: f64 = 0.0;
            for s in 0..3 {
                for (i, yi) in y.iter().enumerate() {
                    let scale = 1.0 + yi.abs();
                    change = change.max((h * (self.next[s][i] - self.k[s][i])).abs() / scale);
                }
            }
            std::mem::swap(&mut self.k, &mut self.next);
            // Iterate to rounding level: stop when the change is negligible, or when it no
            // longer shrinks once it is small (rounding noise).
            if change <= 4.0 * f64::EPSILON
                || (iteration > 2 && change >= previous && change < 1e-10)
            {
                return Ok(());
            }
            // Growing changes well above rounding: the iteration diverges; no use going on.
            if iteration > 2 && change > 2.0 * previous {
                return Err(Failure::NotConverged { t, h: h.abs() });
            }
            previous = change;
        }
        Err(Failure::NotConverged { t, h: h.abs() })
    }

    /// `count` plain steps of `h` from `(t, y)`: the state at the end, in `y`.
    fn advance(
        &mut self,
        driver: &mut Driver<'_>,
        t: f64,
        y: &mut [f64],
        h: f64,
        count: usize,
    ) -> Result<(), Failure> {
        let mut f = vec![0.0; y.len()];
        for j in 0..count {
            let tj = t + h * j as f64;
            driver.rhs(tj, y, &mut f)?;
            let start = y.to_vec();
            self.solve(driver, tj, &start, &f, h)?;
            for (i, yi) in y.iter_mut().enumerate() {
                *yi += h * (B[0] * self.k[0][i] + B[1] * self.k[1][i] + B[2] * self.k[2][i]);
            }
        }
        Ok(())
    }
}

/// The pilot's measure for a step `h` (with sign): the error of the `h` run over the window,
/// by Richardson against `h/2`, extrapolated linearly to the whole span — in units of the
/// tolerances (the weighted RMS norm) and as a bound of the absolute error of any component
/// at the end (twice the error vector's Euclidean length).
fn pilot(
    driver: &mut Driver<'_>,
    stepper: &mut Stepper,
    h: f64,
    span: f64,
) -> Result<(f64, f64), Failure> {
    let window = (PILOT_STEPS as f64 * h.abs()).min(span);
    let steps = ((window / h.abs()).round() as usize).max(1);
    let h = driver.direction * window / steps as f64;
    let (t, y0) = (driver.t, driver.y.clone());
    let mut coarse = y0.clone();
    stepper.advance(driver, t, &mut coarse, h, steps)?;
    let mut fine = y0.clone();
    stepper.advance(driver, t, &mut fine, 0.5 * h, 2 * steps)?;
    // y_h − y = 64/63 (y_h − y_{h/2}) for a method of order 6.
    let error: Vec<f64> = coarse
        .iter()
        .zip(&fine)
        .map(|(a, b)| (a - b) * 64.0 / 63.0 * (span / window))
        .collect();
    // The error moves between components as the motion turns (a phase error of an
    // oscillation shows in x, then in v): the whole vector's length bounds each component
    // at any later time, and a factor 2 covers the extrapolation's slack.
    let largest = 2.0 * error.iter().map(|e| e * e).sum::<f64>().sqrt();
    Ok((driver.error_norm(&y0, &fine, &error), largest))
}

/// A first guess of the step: a hundredth of the time `‖y‖/‖F(y)‖` in which the state
/// changes by its own size (at least not longer than the span).
fn first_guess(y: &[f64], f0: &[f64], span: f64) -> f64 {
    let size = y.iter().fold(0.0_f64, |m, v| m.max(v.abs())).max(1e-3);
    let rate = f0.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if rate > 0.0 {
        (0.01 * size / rate).min(span / 10.0)
    } else {
        span / 10.0
    }
}

/// The step chosen from the dynamics by the pilot (see the module doc), and the pilot's
/// estimate of the error at the end for it.
fn choose_step(
    driver: &mut Driver<'_>,
    stepper: &mut Stepper,
    f0: &[f64],
    span: f64,
) -> Result<(f64, f64), Failure> {
    let mut h = first_guess(&driver.y, f0, span);
    // The motion's own time scale already below the step floor: the span is far too long.
    if let Some(failure) = driver.too_small(driver.t, h) {
        return Err(failure);
    }
    let mut last = (h, f64::INFINITY);
    // The smallest step at which the iteration did not converge.
    let mut diverged: Option<Failure> = None;
    for _ in 0..PILOT_ROUNDS {
        let (norm, largest) = match pilot(driver, stepper, driver.direction * h, span) {
            Ok(measure) => measure,
            // Too large a step for the fixed-point iteration: try a quarter.
            Err(failure @ Failure::NotConverged { .. }) => {
                diverged = Some(failure);
                h *= 0.25;
                continue;
            }
            Err(other) => return Err(other),
        };
        last = (h, largest);
        // Aim at half the tolerance; accept anything between 1/100 and 1 of it.
        if (0.01..=1.0).contains(&norm) || (norm < 1.0 && h >= span) {
            break;
        }
        let factor = if norm == 0.0 {
            4.0
        } else {
            (0.5 / norm).powf(1.0 / 6.0).clamp(0.1, 4.0)
        };
        h = (h * factor).min(span);
    }
    // A step held down by the iteration's convergence (the problem is stiff for it) that
    // would take very many steps, or no step that converged at all: say so now.
    if let Some(failure) = diverged {
        if last.1.is_infinite() || span / last.0 > STIFF_PROJECTED_STEPS {
            return Err(failure);
        }
    }
    Ok(last)
}

pub(super) fn run(driver: &mut Driver<'_>, observer: &mut Observer<'_>) -> StopReason {
    match steps(driver, observer) {
        Ok(stop) => stop,
        Err(failure) => StopReason::Failed(failure),
    }
}

fn steps(driver: &mut Driver<'_>, observer: &mut Observer<'_>) -> Result<StopReason, Failure> {
    let n = driver.y.len();
    let span = (driver.t_end - driver.t).abs();
    if span == 0.0 {
        return Ok(StopReason::Finished);
    }
    let mut stepper = Stepper::new(n);
    let mut f0 = vec![0.0; n];
    let y = driver.y.clone();
    driver.rhs(driver.t, &y, &mut f0)?;
    let requested = match driver.options.step {
        Some(h) if h.is_finite() && h > 0.0 => {
            // The user's step, measured the same way.
            let (_, largest) = pilot(driver, &mut stepper, driver.direction * h.min(span), span)?;
            driver.error_estimate = Some(largest);
            h
        }
        _ => {
            let (h, largest) = choose_step(driver, &mut stepper, &f0, span)?;
            driver.error_estimate = Some(largest);
            if let Some(failure) = driver.too_small(driver.t, h) {
                return Err(failure);
            }
            h
        }
    };
    // A whole number of equal steps lands exactly on the end time.
    let count = (span / requested).ceil().max(1.0);
    let h = driver.direction * span / count;
    let t0 = driver.t;
    let mut f1 = vec![0.0; n];
    let mut y1 = vec![0.0; n];
    let mut compensation = vec![0.0; n];
    let mut step_index = 0.0;
    loop {
        let t = driver.t;
        let y0 = driver.y.clone();
        stepper.solve(driver, t, &y0, &f0, h)?;
        let k = &stepper.k;
        // y₁ = y₀ + h Σ bᵢ kᵢ with Kahan compensation.
        for i in 0..n {
            let increment =
                h * (B[0] * k[0][i] + B[1] * k[1][i] + B[2] * k[2][i]) + compensation[i];
            let sum = driver.y[i] + increment;
            compensation[i] = increment - (sum - driver.y[i]);
            y1[i] = sum;
        }
        step_index += 1.0;
        let t1 = if step_index >= count {
            driver.t_end
        } else {
            t0 + h * step_index
        };
        driver.rhs(t1, &y1, &mut f1)?;
        let interpolate =
            |at: f64, out: &mut [f64]| hermite((t, &y0, &f0), (t1, &y1, &f1), at, out);
        if let Some(stop) = driver.accept(t1, &y1, &interpolate, observer) {
            return Ok(stop);
        }
        if driver.project()? {
            let y = driver.y.clone();
            driver.rhs(driver.t, &y, &mut f1)?;
            compensation.iter_mut().for_each(|c| *c = 0.0);
        }
        std::mem::swap(&mut f0, &mut f1);
    }
}
