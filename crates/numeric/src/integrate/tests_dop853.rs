//! Tests of [`Method::Dop853`] against exact solutions, against dopri5, and for its work:
//! the order of a step (8) and of its dense output (7), events on the dense output, long
//! runs, and fewer evaluations than dopri5 at tight tolerances.

use super::*;

/// `y' = y cos t`, exact `y = exp(sin t)`: a scalar problem whose every derivative is
/// nonzero, so that a step's error shows its leading term.
struct Growth;

impl OdeSystem for Growth {
    fn dimension(&self) -> usize {
        1
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        dy[0] = y[0] * t.cos();
        Ok(())
    }
}

/// The error of one step of size `h` from `t = 0.3` (the tolerances so loose that it is
/// accepted), at the step's end and, on the dense output, at its middle.
fn one_step_errors(h: f64) -> (f64, f64) {
    let options = IntegratorOptions {
        rtol: 1e6,
        atol: 1e6,
        step: Some(h),
        output_step: Some(0.5 * h),
        ..IntegratorOptions::default()
    };
    let t0 = 0.3;
    let mut rows = Vec::new();
    let outcome = integrate(
        &mut Growth,
        Method::Dop853,
        t0,
        &[t0.sin().exp()],
        t0 + h,
        &options,
        &mut |t, y| rows.push((t, y[0])),
    );
    assert_eq!(outcome.stop, StopReason::Finished);
    assert_eq!(outcome.stats.steps, 1, "h = {h}");
    assert_eq!(rows.len(), 3, "h = {h}: {rows:?}");
    let error = |(t, y): (f64, f64)| (y - f64::sin(t).exp()).abs();
    (error(rows[2]), error(rows[1]))
}

#[test]
fn a_step_is_of_order_eight_and_its_dense_output_of_order_seven() {
    // Local errors: h⁹ at the step's end, h⁸ between (the continuous extension's order 7);
    // halving h divides them by 2⁹ and 2⁸.
    let (end_coarse, middle_coarse) = one_step_errors(0.4);
    let (end_fine, middle_fine) = one_step_errors(0.2);
    let end_order = (end_coarse / end_fine).log2();
    let middle_order = (middle_coarse / middle_fine).log2();
    assert!(
        (8.3..9.7).contains(&end_order),
        "{end_coarse:e} → {end_fine:e}: h^{end_order}"
    );
    assert!(
        (7.4..8.6).contains(&middle_order),
        "{middle_coarse:e} → {middle_fine:e}: h^{middle_order}"
    );
}

/// The error at `t = 4` of `4/h` steps of size `h` from `t = 0`, each its own run of one step
/// (so that the step is fixed) started where the last ended.
fn fixed_step_error(h: f64) -> f64 {
    let options = IntegratorOptions {
        rtol: 1e6,
        atol: 1e6,
        step: Some(h),
        ..IntegratorOptions::default()
    };
    let steps = (4.0 / h).round() as u32;
    let mut y = [1.0];
    for step in 0..steps {
        let t0 = f64::from(step) * h;
        let mut last = y;
        let outcome = integrate(
            &mut Growth,
            Method::Dop853,
            t0,
            &y,
            t0 + h,
            &options,
            &mut |_, y| last[0] = y[0],
        );
        assert_eq!(outcome.stats.steps, 1);
        y = last;
    }
    (y[0] - 4.0f64.sin().exp()).abs()
}

#[test]
fn the_global_error_at_a_fixed_step_is_of_order_eight() {
    let (coarse, fine) = (fixed_step_error(0.4), fixed_step_error(0.2));
    let order = (coarse / fine).log2();
    assert!(
        (7.4..8.8).contains(&order),
        "{coarse:e} → {fine:e}: h^{order}"
    );
}

/// `x'' = −x`: `(cos t, −sin t)`.
struct Oscillator;

impl OdeSystem for Oscillator {
    fn dimension(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        dy[0] = y[1];
        dy[1] = -y[0];
        Ok(())
    }
    fn event_count(&self) -> usize {
        1
    }
    fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0];
    }
}

#[test]
fn events_are_located_on_the_dense_output_to_1e_12() {
    // x = cos t first crosses zero at π/2, inside a step far longer than the tolerance
    // would allow a cubic interpolant.
    let options = IntegratorOptions {
        rtol: 1e-13,
        atol: 1e-15,
        ..IntegratorOptions::default()
    };
    let mut rows = Vec::new();
    let outcome = integrate(
        &mut Oscillator,
        Method::Dop853,
        0.0,
        &[1.0, 0.0],
        10.0,
        &options,
        &mut |t, y| rows.push((t, y.to_vec())),
    );
    let StopReason::Event { index: 0, t } = outcome.stop else {
        panic!("no event: {:?}", outcome.stop);
    };
    assert!((t - std::f64::consts::FRAC_PI_2).abs() < 1e-12, "{t}");
    let (last_t, last_y) = rows.last().cloned().unwrap_or_default();
    assert_eq!(last_t, t);
    assert!(last_y[0].abs() < 1e-12 && (last_y[1] + 1.0).abs() < 1e-12);
    // The crossing was found inside a step, not at one's end.
    assert!(outcome.stats.steps < 20, "{:?}", outcome.stats);
}

#[test]
fn dense_rows_between_steps_are_as_accurate_as_the_steps() {
    let options = IntegratorOptions {
        rtol: 1e-11,
        atol: 1e-13,
        output_step: Some(0.01),
        ..IntegratorOptions::default()
    };
    let mut rows = Vec::new();
    let outcome = integrate(
        &mut Growth,
        Method::Dop853,
        0.0,
        &[1.0],
        10.0,
        &options,
        &mut |t, y| rows.push((t, y[0])),
    );
    assert_eq!(outcome.stop, StopReason::Finished);
    assert_eq!(rows.len(), 1001);
    // Many rows per step: the dense output carries them.
    assert!(outcome.stats.steps < 200, "{:?}", outcome.stats);
    for (t, y) in rows {
        assert!((y - t.sin().exp()).abs() < 1e-9, "t = {t}: {y}");
    }
}

/// Kepler's problem, `r'' = −r/|r|³`, from perihelion of the orbit with eccentricity `e`
/// (semi-major axis 1, period 2π).
struct Kepler;

impl OdeSystem for Kepler {
    fn dimension(&self) -> usize {
        4
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        let r3 = y[0].hypot(y[1]).powi(3);
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = -y[0] / r3;
        dy[3] = -y[1] / r3;
        Ok(())
    }
}

#[test]
fn the_kepler_orbit_closes_after_fifty_periods() {
    let e: f64 = 0.5;
    let y0 = [1.0 - e, 0.0, 0.0, ((1.0 + e) / (1.0 - e)).sqrt()];
    let options = IntegratorOptions {
        rtol: 1e-12,
        atol: 1e-14,
        ..IntegratorOptions::default()
    };
    let mut last = Vec::new();
    let periods = 50.0;
    let outcome = integrate(
        &mut Kepler,
        Method::Dop853,
        0.0,
        &y0,
        periods * std::f64::consts::TAU,
        &options,
        &mut |_, y| last = y.to_vec(),
    );
    assert_eq!(outcome.stop, StopReason::Finished);
    let distance = last
        .iter()
        .zip(&y0)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    // The phase error grows along the orbit: ~1e-9 after 5 periods, ~1e-7 after 50.
    assert!(distance < 1e-6, "{distance:e} after {:?}", outcome.stats);
}

/// The planar n-link pendulum of unit masses and lengths (`bench/models/nlink.sh`):
/// `M q̈ = f` with `M_ij = (n − max(i, j)) cos(θᵢ − θⱼ)` and
/// `f_i = −Σⱼ (n − max(i, j)) sin(θᵢ − θⱼ) θ̇ⱼ² − (n − i) g sin θᵢ` (0-based `i`, `j`).
struct NLink {
    n: usize,
}

impl OdeSystem for NLink {
    fn dimension(&self) -> usize {
        2 * self.n
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        let n = self.n;
        let (q, v) = y.split_at(n);
        let weight = |i: usize, j: usize| (n - i.max(j)) as f64;
        let mass = nalgebra::DMatrix::from_fn(n, n, |i, j| weight(i, j) * (q[i] - q[j]).cos());
        let force = nalgebra::DVector::from_fn(n, |i, _| {
            let coupling: f64 = (0..n)
                .map(|j| weight(i, j) * (q[i] - q[j]).sin() * v[j] * v[j])
                .sum();
            -coupling - (n - i) as f64 * 9.81 * q[i].sin()
        });
        let acceleration = mass
            .lu()
            .solve(&force)
            .ok_or(RhsError::SingularMatrix { column: 0 })?;
        dy[..n].copy_from_slice(v);
        dy[n..].copy_from_slice(acceleration.as_slice());
        Ok(())
    }
}

/// A 10 s run of the n-link pendulum from θ₁ = 0.5 at rest: the final state and the work.
fn nlink_run(n: usize, method: Method, rtol: f64, atol: f64) -> (Vec<f64>, Stats) {
    let mut y0 = vec![0.0; 2 * n];
    y0[0] = 0.5;
    let options = IntegratorOptions {
        rtol,
        atol,
        ..IntegratorOptions::default()
    };
    let mut last = Vec::new();
    let outcome = integrate(
        &mut NLink { n },
        method,
        0.0,
        &y0,
        10.0,
        &options,
        &mut |_, y| last = y.to_vec(),
    );
    assert_eq!(outcome.stop, StopReason::Finished, "{method}");
    (last, outcome.stats)
}

#[test]
fn dop853_agrees_with_dopri5_at_tight_tolerance() {
    let (a, _) = nlink_run(2, Method::Dop853, 1e-12, 1e-14);
    let (b, _) = nlink_run(2, Method::Dopri5, 1e-12, 1e-14);
    let difference = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(difference < 1e-8, "{a:?} vs {b:?}");
    // And it is no coincidence of two runs: a loose run differs visibly.
    let (c, _) = nlink_run(2, Method::Dop853, 1e-4, 1e-6);
    let loose = c
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(loose > 10.0 * difference, "{loose:e} vs {difference:e}");
}

#[test]
fn dop853_takes_fewer_evaluations_than_dopri5_on_the_nlink_pendulum_at_rtol_1e_9() {
    for n in [2, 5] {
        let (_, eighth) = nlink_run(n, Method::Dop853, 1e-9, 1e-11);
        let (_, fifth) = nlink_run(n, Method::Dopri5, 1e-9, 1e-11);
        assert!(
            (eighth.evaluations as f64) < 0.8 * fifth.evaluations as f64,
            "n = {n}: dop853 {eighth:?}, dopri5 {fifth:?}"
        );
    }
}

/// Prothero–Robinson `y' = −λ (y − cos t) − sin t`: stiff for large λ.
struct ProtheroRobinson;

impl OdeSystem for ProtheroRobinson {
    fn dimension(&self) -> usize {
        1
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        dy[0] = -1e6 * (y[0] - t.cos()) - t.sin();
        Ok(())
    }
}

#[test]
fn a_stiff_problem_is_reported_at_the_edge_of_the_stability_region() {
    let options = IntegratorOptions {
        rtol: 1e-6,
        atol: 1e-8,
        ..IntegratorOptions::default()
    };
    let outcome = integrate(
        &mut ProtheroRobinson,
        Method::Dop853,
        0.0,
        &[1.0],
        10.0,
        &options,
        &mut |_, _| {},
    );
    match outcome.stop {
        StopReason::Failed(Failure::Stiff {
            h, h_lambda, steps, ..
        }) => {
            assert!(h_lambda > 6.1, "{h_lambda}");
            assert_eq!(steps, STIFF_STEPS);
            // DOP853's real stability interval ends near h·λ = 6.
            assert!(h * 1e6 > 3.0 && h * 1e6 < 8.0, "h = {h}");
        }
        other => panic!("{other:?}"),
    }
}
