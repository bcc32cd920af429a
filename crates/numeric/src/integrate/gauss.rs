//! Three-stage Gauss–Legendre collocation (order 6) with a fixed step. The method is
//! symplectic and symmetric: applied to Hamilton's equations its energy error does not drift
//! but oscillates, bounded, over very long runs (Hairer, Lubich & Wanner, *Geometric Numerical
//! Integration*, §VI.4 and §X.3). The stage equations are solved by fixed-point iteration to
//! rounding level (right for the non-stiff mechanics it is meant for), and the update uses
//! compensated summation so rounding does not drift over 10⁶ steps either.

use super::{hermite, Driver, Failure, StopReason};

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

pub(super) fn run(driver: &mut Driver<'_>, observer: &mut dyn FnMut(f64, &[f64])) -> StopReason {
    match steps(driver, observer) {
        Ok(stop) => stop,
        Err(failure) => StopReason::Failed(failure),
    }
}

fn steps(
    driver: &mut Driver<'_>,
    observer: &mut dyn FnMut(f64, &[f64]),
) -> Result<StopReason, Failure> {
    let n = driver.y.len();
    let span = (driver.t_end - driver.t).abs();
    if span == 0.0 {
        return Ok(StopReason::Finished);
    }
    let requested = match driver.options.step {
        Some(h) if h.is_finite() && h > 0.0 => h,
        _ => driver.options.output_step.unwrap_or(span / 100.0).min(span) / 10.0,
    };
    // A whole number of equal steps lands exactly on the end time.
    let count = (span / requested).ceil().max(1.0);
    let h = driver.direction * span / count;
    let t0 = driver.t;
    let mut k: [Vec<f64>; 3] = std::array::from_fn(|_| vec![0.0; n]);
    let mut next: [Vec<f64>; 3] = std::array::from_fn(|_| vec![0.0; n]);
    let mut stage = vec![0.0; n];
    let mut f0 = vec![0.0; n];
    let mut f1 = vec![0.0; n];
    let mut y1 = vec![0.0; n];
    let mut compensation = vec![0.0; n];
    let y = driver.y.clone();
    driver.rhs(driver.t, &y, &mut f0)?;
    let mut step_index = 0.0;
    loop {
        let t = driver.t;
        for ki in &mut k {
            ki.copy_from_slice(&f0);
        }
        let mut previous = f64::INFINITY;
        let mut converged = false;
        for iteration in 0..MAX_ITERATIONS {
            for s in 0..3 {
                for i in 0..n {
                    stage[i] = driver.y[i]
                        + h * (A[s][0] * k[0][i] + A[s][1] * k[1][i] + A[s][2] * k[2][i]);
                }
                driver.rhs(t + C[s] * h, &stage, &mut next[s])?;
            }
            let mut change: f64 = 0.0;
            for s in 0..3 {
                for i in 0..n {
                    let scale = 1.0 + driver.y[i].abs();
                    change = change.max((h * (next[s][i] - k[s][i])).abs() / scale);
                }
            }
            std::mem::swap(&mut k, &mut next);
            // Iterate to rounding level: stop when the change is negligible, or when it no
            // longer shrinks once it is small (rounding noise).
            if change <= 4.0 * f64::EPSILON
                || (iteration > 2 && change >= previous && change < 1e-10)
            {
                converged = true;
                break;
            }
            previous = change;
        }
        if !converged {
            return Err(Failure::NotConverged { t, h: h.abs() });
        }
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
        let y0 = driver.y.clone();
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
