//! Dormand–Prince 5(4): explicit Runge–Kutta with local extrapolation, FSAL, a PI step size
//! controller, and Hairer's fourth-order continuous extension (Hairer, Nørsett & Wanner,
//! *Solving ODEs I*, §II.5 and the code DOPRI5).

use super::explicit::{self, Pair};
use super::{Driver, Failure, Observer, StopReason, STIFF_STEPS};

const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A21: f64 = 0.2;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339_200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
const D1: f64 = -12_715_105_075.0 / 11_282_082_432.0;
const D3: f64 = 87_487_479_700.0 / 32_700_410_799.0;
const D4: f64 = -10_690_763_975.0 / 1_880_347_072.0;
const D5: f64 = 701_980_252_875.0 / 199_316_789_632.0;
const D6: f64 = -1_453_857_185.0 / 822_651_844.0;
const D7: f64 = 69_997_945.0 / 29_380_423.0;

pub(super) fn run(driver: &mut Driver<'_>, observer: &mut Observer<'_>) -> StopReason {
    let n = driver.y.len();
    let mut pair = Dopri5 {
        k: std::array::from_fn(|_| vec![0.0; n]),
        stage: vec![0.0; n],
        y1: vec![0.0; n],
        error: vec![0.0; n],
        dense: std::array::from_fn(|_| vec![0.0; n]),
    };
    explicit::run(&mut pair, driver, observer)
}

/// The work vectors of a step: the seven stages' derivatives (`k[6]` at the new point, FSAL),
/// the state of the stage being evaluated (after a step, stage 6's), the new point, the error
/// estimate and the dense output's coefficients.
struct Dopri5 {
    k: [Vec<f64>; 7],
    stage: Vec<f64>,
    y1: Vec<f64>,
    error: Vec<f64>,
    dense: [Vec<f64>; 5],
}

impl Pair for Dopri5 {
    const ORDER: i32 = 5;
    const DENSE_COSTS_EVALUATIONS: bool = false;

    fn first_stage(&mut self) -> &mut [f64] {
        &mut self.k[0]
    }

    /// Stages 2…7; stage 7 is evaluated at the new point `y1` and reused as stage 1 of the
    /// next step (FSAL).
    fn stages(&mut self, driver: &mut Driver<'_>, t: f64, hs: f64) -> Option<Failure> {
        let rows: [&[(usize, f64)]; 6] = [
            &[(0, A21)],
            &[(0, A31), (1, A32)],
            &[(0, A41), (1, A42), (2, A43)],
            &[(0, A51), (1, A52), (2, A53), (3, A54)],
            &[(0, A61), (1, A62), (2, A63), (3, A64), (4, A65)],
            &[(0, A71), (2, A73), (3, A74), (4, A75), (5, A76)],
        ];
        for (s, row) in rows.iter().enumerate() {
            let out: &mut [f64] = if s == 5 {
                &mut self.y1
            } else {
                &mut self.stage
            };
            let k = &self.k;
            for (i, value) in out.iter_mut().enumerate() {
                let acc: f64 = row.iter().map(|&(j, a)| a * k[j][i]).sum();
                *value = driver.y[i] + hs * acc;
            }
            let ts = t + C[s + 1] * hs;
            let input: &[f64] = if s == 5 { &self.y1 } else { &self.stage };
            if let Err(e) = driver.rhs(ts, input, &mut self.k[s + 1]) {
                return Some(e);
            }
        }
        None
    }

    fn error(&mut self, driver: &Driver<'_>, _h: f64, hs: f64) -> f64 {
        for (i, e) in self.error.iter_mut().enumerate() {
            *e = hs * weighted(&self.k, [E1, 0.0, E3, E4, E5, E6, E7], i);
        }
        driver.error_norm(&driver.y, &self.y1, &self.error)
    }

    fn new_point_rate(&mut self, _driver: &mut Driver<'_>, _t1: f64) -> Result<(), Failure> {
        Ok(())
    }

    fn stiffness_pair(&self) -> [&[f64]; 4] {
        [&self.k[6], &self.k[5], &self.y1, &self.stage]
    }

    fn dense(&mut self, driver: &mut Driver<'_>, _t: f64, hs: f64) -> Result<(), Failure> {
        dense_coefficients(&mut self.dense, &driver.y, &self.y1, &self.k, hs);
        Ok(())
    }

    fn interpolate(&self, theta: f64, out: &mut [f64]) {
        let dense = &self.dense;
        let theta1 = 1.0 - theta;
        for (i, value) in out.iter_mut().enumerate() {
            *value = dense[0][i]
                + theta
                    * (dense[1][i]
                        + theta1 * (dense[2][i] + theta * (dense[3][i] + theta1 * dense[4][i])));
        }
    }

    fn new_point(&self) -> &[f64] {
        &self.y1
    }

    fn reuse_new_point_rate(&mut self) {
        let (first, rest) = self.k.split_at_mut(1);
        first[0].copy_from_slice(&rest[5]);
    }

    fn accepted_factor(err: f64, previous_error: f64, rejected_last: bool) -> f64 {
        pi_factor(err, previous_error, rejected_last)
    }

    fn rejection_factor(err: f64) -> f64 {
        rejection_factor(err)
    }
}

/// The step-size factor after a rejected step (a tenth after a failed evaluation).
fn rejection_factor(err: f64) -> f64 {
    if err.is_finite() {
        (0.9 * err.powf(-0.2)).clamp(0.2, 1.0)
    } else {
        0.1
    }
}

/// `Σ_j w_j k_j[i]`.
fn weighted(k: &[Vec<f64>; 7], w: [f64; 7], i: usize) -> f64 {
    k.iter().zip(w).map(|(kj, wj)| wj * kj[i]).sum()
}

/// The step-size factor after an accepted step: a PI controller with the exponents of
/// Hairer's DOPRI5 (α = 0.2 − 0.75 β, β = 0.04), not growing right after a rejection.
fn pi_factor(err: f64, previous_error: f64, rejected_last: bool) -> f64 {
    let factor = if err == 0.0 {
        10.0
    } else {
        (0.9 * err.powf(-0.17) * previous_error.powf(0.04)).clamp(0.2, 10.0)
    };
    if rejected_last {
        factor.min(1.0)
    } else {
        factor
    }
}

/// The coefficients of the dense output (Hairer's continuous extension of order 4) over the
/// step from `y` to `y1`.
fn dense_coefficients(
    dense: &mut [Vec<f64>; 5],
    y: &[f64],
    y1: &[f64],
    k: &[Vec<f64>; 7],
    hs: f64,
) {
    for i in 0..y.len() {
        let ydiff = y1[i] - y[i];
        let bspl = hs * k[0][i] - ydiff;
        dense[0][i] = y[i];
        dense[1][i] = ydiff;
        dense[2][i] = bspl;
        dense[3][i] = ydiff - hs * k[6][i] - bspl;
        dense[4][i] = hs * weighted(k, [D1, 0.0, D3, D4, D5, D6, D7], i);
    }
}

/// Hairer's starting step for a method of order `order`: a first guess from `‖y‖/‖y'‖`,
/// refined with one Euler step's estimate of the second derivative.
pub(super) fn initial_step(
    driver: &mut Driver<'_>,
    f0: &[f64],
    order: i32,
) -> Result<f64, Failure> {
    let n = driver.y.len();
    let (rtol, atol) = (driver.options.rtol, driver.options.atol);
    let scale: Vec<f64> = driver.y.iter().map(|y| atol + rtol * y.abs()).collect();
    let rms = |v: &[f64]| -> f64 {
        (v.iter()
            .zip(&scale)
            .map(|(x, s)| (x / s).powi(2))
            .sum::<f64>()
            / n.max(1) as f64)
            .sqrt()
    };
    let d0 = rms(&driver.y);
    let d1 = rms(f0);
    let span = (driver.t_end - driver.t).abs();
    let h0 = if d0 < 1e-5 || d1 < 1e-5 {
        1e-6
    } else {
        0.01 * d0 / d1
    }
    .min(span);
    let y1: Vec<f64> = driver
        .y
        .iter()
        .zip(f0)
        .map(|(y, f)| y + driver.direction * h0 * f)
        .collect();
    let mut f1 = vec![0.0; n];
    driver.rhs(driver.t + driver.direction * h0, &y1, &mut f1)?;
    let diff: Vec<f64> = f1.iter().zip(f0).map(|(a, b)| (a - b) / h0).collect();
    let d2 = rms(&diff);
    let h1 = if d1.max(d2) <= 1e-15 {
        (h0 * 1e-3).max(1e-6)
    } else {
        (0.01 / d1.max(d2)).powf(1.0 / f64::from(order))
    };
    // A span so long (or a start time so large) that even the dynamics' own estimate `h1`
    // is below the step floor cannot be covered: say so now, with that step, rather than
    // start at the floor, where the state would overflow.
    if let Some(failure) = driver.too_small(driver.t, h1.min(span)) {
        return Err(failure);
    }
    // Not below the collapse floor: a guess that small is for the controller to shrink to.
    let floor = 10.0 * driver.step_floor(driver.t).0;
    Ok((100.0 * h0).min(h1).min(span).max(1e-12).max(floor))
}

/// Hairer's stiffness test (the codes DOPRI5 and DOP853): `h·|λ|`, estimated from the last
/// stage and the new point, both at `t + h` (`h‖k₇ − k₆‖ / ‖y₁ − Y₆‖` for dopri5), at the
/// boundary of the stability region many steps in a row means the step is held down by
/// stability: the problem is stiff for this method.
#[derive(Debug)]
pub(super) struct Stiffness {
    /// `h·|λ|` above this is near the boundary (the method's).
    threshold: f64,
    /// Consecutive steps near the boundary.
    stiff: u32,
    /// Consecutive steps away from it since the last one near it.
    calm: u32,
    /// The last estimate of `h·|λ|`.
    pub(super) last: f64,
}

impl Stiffness {
    /// A fresh test against `threshold`.
    pub(super) fn new(threshold: f64) -> Self {
        Stiffness {
            threshold,
            stiff: 0,
            calm: 0,
            last: 0.0,
        }
    }

    /// Takes the accepted step's estimate; returns the count when the run is judged stiff.
    pub(super) fn observe(
        &mut self,
        h: f64,
        k7: &[f64],
        k6: &[f64],
        y1: &[f64],
        y6: &[f64],
    ) -> Option<u32> {
        let numerator: f64 = k7.iter().zip(k6).map(|(a, b)| (a - b).powi(2)).sum();
        let denominator: f64 = y1.iter().zip(y6).map(|(a, b)| (a - b).powi(2)).sum();
        if denominator <= 0.0 || !numerator.is_finite() {
            return None;
        }
        self.last = h * (numerator / denominator).sqrt();
        if self.last > self.threshold {
            self.calm = 0;
            self.stiff += 1;
            if self.stiff >= STIFF_STEPS {
                return Some(self.stiff);
            }
        } else {
            self.calm += 1;
            if self.calm >= 6 {
                self.stiff = 0;
            }
        }
        None
    }
}
