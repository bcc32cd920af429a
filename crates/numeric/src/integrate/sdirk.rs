//! A two-stage singly diagonally implicit Runge–Kutta method for stiff systems: Alexander's
//! L-stable, stiffly accurate SDIRK of order 2 with `γ = 1 − 1/√2` (Hairer & Wanner, *Solving
//! ODEs II*, §IV.6). The stage equations `Yᵢ = baseᵢ + hγ F(tᵢ, Yᵢ)` are solved by Newton's
//! method with the iteration matrix `I − hγ J`, `J` by finite differences once per step. The
//! error estimate compares with the embedded first-order solution `y + h K₁`; a Newton solve
//! that does not converge rejects the step and retries with a quarter of it.

use super::{hermite, Driver, Failure, Observer, StopReason};
use crate::linalg::solve_in_place;

const GAMMA: f64 = 1.0 - std::f64::consts::FRAC_1_SQRT_2;
const NEWTON_ITERATIONS: usize = 10;

pub(super) fn run(driver: &mut Driver<'_>, observer: &mut Observer<'_>) -> StopReason {
    match steps(driver, observer) {
        Ok(stop) => stop,
        Err(failure) => StopReason::Failed(failure),
    }
}

struct Work {
    n: usize,
    jacobian: Vec<f64>,
    matrix: Vec<f64>,
    residual: Vec<f64>,
    perturbed: Vec<f64>,
    value: Vec<f64>,
}

/// The states and derivatives of one step.
struct Step {
    /// `F(t, y)` at the step's start.
    f0: Vec<f64>,
    /// The stage derivatives `K₁ = F(t + γh, Y₁)` and `K₂ = F(t + h, y₁)`.
    k1: Vec<f64>,
    k2: Vec<f64>,
    stage1: Vec<f64>,
    /// The new state (stage 2: the method is stiffly accurate).
    y1: Vec<f64>,
    base: Vec<f64>,
    error: Vec<f64>,
}

impl Work {
    fn new(n: usize) -> Work {
        Work {
            n,
            jacobian: vec![0.0; n * n],
            matrix: vec![0.0; n * n],
            residual: vec![0.0; n],
            perturbed: vec![0.0; n],
            value: vec![0.0; n],
        }
    }
}

impl Step {
    fn new(n: usize) -> Step {
        Step {
            f0: vec![0.0; n],
            k1: vec![0.0; n],
            k2: vec![0.0; n],
            stage1: vec![0.0; n],
            y1: vec![0.0; n],
            base: vec![0.0; n],
            error: vec![0.0; n],
        }
    }
}

fn steps(driver: &mut Driver<'_>, observer: &mut Observer<'_>) -> Result<StopReason, Failure> {
    let n = driver.y.len();
    let mut work = Work::new(n);
    let mut step = Step::new(n);
    let y = driver.y.clone();
    driver.rhs(driver.t, &y, &mut step.f0)?;
    let span = (driver.t_end - driver.t).abs();
    let mut h = match driver.options.step {
        Some(h) if h.is_finite() && h > 0.0 => h,
        _ => (span * 1e-4).max(1e-8).min(span),
    };
    let mut jacobian_fresh = false;
    loop {
        let t = driver.t;
        let remaining = (driver.t_end - t).abs();
        let last = h >= remaining;
        if last {
            h = remaining;
        }
        if let Some(failure) = driver.too_small(t, h) {
            return Err(failure);
        }
        let hs = h * driver.direction;
        if !jacobian_fresh {
            let y = driver.y.clone();
            jacobian(driver, &mut work, t, &y, &step.f0)?;
            jacobian_fresh = true;
        }
        let Some(err) = attempt(driver, &mut work, &mut step, t, hs)? else {
            driver.stats.rejected += 1;
            h *= 0.25;
            jacobian_fresh = false;
            continue;
        };
        let factor = if err == 0.0 {
            5.0
        } else {
            (0.9 * err.powf(-0.5)).clamp(0.2, 5.0)
        };
        if err > 1.0 || !err.is_finite() {
            driver.stats.rejected += 1;
            h *= if err.is_finite() {
                factor.min(0.9)
            } else {
                0.25
            };
            continue;
        }
        let t1 = if last { driver.t_end } else { t + hs };
        if let Some(stop) = finish(driver, &mut step, t, t1, observer)? {
            return Ok(stop);
        }
        jacobian_fresh = false;
        h *= factor;
    }
}

/// One try of a step `hs` from `(t, driver.y)` with the Jacobian in `work`: both stages by
/// Newton; the error norm, or `None` when a Newton solve did not converge.
fn attempt(
    driver: &mut Driver<'_>,
    work: &mut Work,
    step: &mut Step,
    t: f64,
    hs: f64,
) -> Result<Option<f64>, Failure> {
    let n = work.n;
    for i in 0..n {
        for j in 0..n {
            let identity = if i == j { 1.0 } else { 0.0 };
            work.matrix[i * n + j] = identity - hs * GAMMA * work.jacobian[i * n + j];
        }
    }
    // Stage 1 from y, stage 2 from y + h(1 − γ) K₁; the predictor is y (then stage 1).
    step.base.copy_from_slice(&driver.y);
    step.stage1.copy_from_slice(&driver.y);
    let solved = newton(
        driver,
        work,
        t + GAMMA * hs,
        hs,
        &step.base,
        &mut step.stage1,
        &mut step.k1,
    )?;
    let solved = solved && {
        for i in 0..n {
            step.base[i] = driver.y[i] + hs * (1.0 - GAMMA) * step.k1[i];
        }
        step.y1.copy_from_slice(&step.stage1);
        newton(
            driver,
            work,
            t + hs,
            hs,
            &step.base,
            &mut step.y1,
            &mut step.k2,
        )?
    };
    if !solved {
        return Ok(None);
    }
    for i in 0..n {
        step.error[i] = hs * GAMMA * (step.k2[i] - step.k1[i]);
    }
    Ok(Some(driver.error_norm(&driver.y, &step.y1, &step.error)))
}

/// Hands the accepted step from `t` to `t1` to the driver, then projects and takes the
/// new start's derivative; `Some` when the run stops.
fn finish(
    driver: &mut Driver<'_>,
    step: &mut Step,
    t: f64,
    t1: f64,
    observer: &mut Observer<'_>,
) -> Result<Option<StopReason>, Failure> {
    let y0 = driver.y.clone();
    // Stiffly accurate: K₂ = F(t + h, y₁), the derivative at the new point.
    let (f0, y1, k2) = (&step.f0, &step.y1, &step.k2);
    let interpolate = |at: f64, out: &mut [f64]| hermite((t, &y0, f0), (t1, y1, k2), at, out);
    if let Some(stop) = driver.accept(t1, y1, &interpolate, observer) {
        return Ok(Some(stop));
    }
    if driver.project()? {
        let y = driver.y.clone();
        driver.rhs(driver.t, &y, &mut step.f0)?;
    } else {
        step.f0.copy_from_slice(&step.k2);
    }
    Ok(None)
}

/// `J = ∂F/∂y` at `(t, y)` by forward differences.
fn jacobian(
    driver: &mut Driver<'_>,
    work: &mut Work,
    t: f64,
    y: &[f64],
    f0: &[f64],
) -> Result<(), Failure> {
    let n = work.n;
    for j in 0..n {
        work.perturbed.copy_from_slice(y);
        let delta = f64::EPSILON.sqrt() * y[j].abs().max(1e-5);
        work.perturbed[j] += delta;
        let perturbed = work.perturbed.clone();
        driver.rhs(t, &perturbed, &mut work.value)?;
        for (i, (value, base)) in work.value.iter().zip(f0).enumerate() {
            work.jacobian[i * n + j] = (value - base) / delta;
        }
    }
    Ok(())
}

/// Solves `Y = base + hγ F(t, Y)` from the guess in `stage`; leaves `F(t, Y)` in `derivative`.
/// Returns whether Newton converged.
fn newton(
    driver: &mut Driver<'_>,
    work: &mut Work,
    t: f64,
    hs: f64,
    base: &[f64],
    stage: &mut [f64],
    derivative: &mut [f64],
) -> Result<bool, Failure> {
    let n = work.n;
    let (rtol, atol) = (driver.options.rtol, driver.options.atol);
    let mut matrix = vec![0.0; n * n];
    for _ in 0..NEWTON_ITERATIONS {
        if driver.rhs(t, stage, derivative).is_err() {
            return Ok(false);
        }
        for i in 0..n {
            work.residual[i] = -(stage[i] - base[i] - hs * GAMMA * derivative[i]);
        }
        matrix.copy_from_slice(&work.matrix);
        if solve_in_place(n, &mut matrix, &mut work.residual).is_err() {
            return Ok(false);
        }
        let mut size: f64 = 0.0;
        for (x, dx) in stage.iter_mut().zip(&work.residual) {
            *x += dx;
            let scale = atol + rtol * x.abs();
            size = size.max((dx / scale).abs());
        }
        if !size.is_finite() {
            return Ok(false);
        }
        if size < 1e-2 {
            return Ok(driver.rhs(t, stage, derivative).is_ok());
        }
    }
    Ok(false)
}
