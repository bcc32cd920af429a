//! Integrator tests against exact solutions.

use super::*;

/// `x'' = −x`: y = (x, v), exact x = cos t, v = −sin t; an event at x = 0.
struct Oscillator {
    events: bool,
}

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
        usize::from(self.events)
    }
    fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0];
    }
}

fn run(
    method: Method,
    options: IntegratorOptions,
    events: bool,
) -> (Outcome, Vec<(f64, Vec<f64>)>) {
    let mut out = Vec::new();
    let outcome = integrate(
        &mut Oscillator { events },
        method,
        0.0,
        &[1.0, 0.0],
        10.0,
        &options,
        &mut |t, y| out.push((t, y.to_vec())),
    );
    (outcome, out)
}

#[test]
fn dopri5_meets_its_tolerance_at_every_dense_output() {
    let options = IntegratorOptions {
        rtol: 1e-10,
        atol: 1e-12,
        output_step: Some(0.1),
        ..IntegratorOptions::default()
    };
    let (outcome, out) = run(Method::Dopri5, options, false);
    assert_eq!(outcome.stop, StopReason::Finished);
    assert_eq!(out.len(), 101);
    for (t, y) in &out {
        assert!((y[0] - t.cos()).abs() < 1e-8, "t = {t}: {}", y[0] - t.cos());
        assert!((y[1] + t.sin()).abs() < 1e-8);
    }
    assert_eq!(out.last().map(|p| p.0), Some(10.0));
    assert!(outcome.stats.steps > 10 && outcome.stats.evaluations > 6 * outcome.stats.steps);
}

#[test]
fn dopri5_error_shrinks_with_the_tolerance() {
    let error = |rtol: f64| {
        let options = IntegratorOptions {
            rtol,
            atol: rtol,
            ..IntegratorOptions::default()
        };
        let (_, out) = run(Method::Dopri5, options, false);
        let (t, y) = out.last().cloned().unwrap();
        (y[0] - t.cos()).abs()
    };
    let (coarse, fine) = (error(1e-6), error(1e-10));
    assert!(fine < coarse / 100.0, "{coarse} vs {fine}");
}

#[test]
fn events_stop_at_the_zero_crossing() {
    let (outcome, out) = run(Method::Dopri5, IntegratorOptions::default(), true);
    let StopReason::Event { index: 0, t } = outcome.stop else {
        panic!("no event: {:?}", outcome.stop);
    };
    assert!((t - std::f64::consts::FRAC_PI_2).abs() < 1e-7, "{t}");
    assert_eq!(out.last().map(|p| p.0), Some(t));
}

/// The oscillator whose event `x = 0` is recorded instead of stopping the run.
struct RecordingOscillator;

impl OdeSystem for RecordingOscillator {
    fn dimension(&self) -> usize {
        2
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        Oscillator { events: false }.rhs(t, y, dy)
    }
    fn event_count(&self) -> usize {
        2
    }
    fn events(&mut self, t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0];
        // Stops the run at t = 8.
        g[1] = 8.0 - t;
    }
    fn event_stops(&self, index: usize) -> bool {
        index == 1
    }
}

#[test]
fn recorded_events_give_every_crossing_with_its_direction() {
    for method in [Method::Dopri5, Method::Dop853, Method::Gauss, Method::Sdirk] {
        let options = IntegratorOptions {
            rtol: 1e-10,
            atol: 1e-12,
            step: (method == Method::Gauss).then_some(0.05),
            ..IntegratorOptions::default()
        };
        let mut crossings = Vec::new();
        let outcome = integrate_with_crossings(
            &mut RecordingOscillator,
            method,
            0.0,
            &[1.0, 0.0],
            10.0,
            &options,
            &mut |_, _| {},
            &mut |c| crossings.push((c.index, c.t, c.rising, c.y[0])),
        );
        let StopReason::Event { index: 1, t } = outcome.stop else {
            panic!("{method}: no stop: {:?}", outcome.stop);
        };
        assert!((t - 8.0).abs() < 1e-12);
        // x = cos t crosses zero at π/2 + kπ, falling for even k; 8 s holds k = 0…2.
        assert_eq!(crossings.len(), 3, "{method}: {crossings:?}");
        // sdirk is of order 2: its crossings are as good as its solution.
        let tolerance = if method == Method::Sdirk { 1e-4 } else { 1e-8 };
        for (k, &(index, t, rising, x)) in crossings.iter().enumerate() {
            let exact = std::f64::consts::FRAC_PI_2 + k as f64 * std::f64::consts::PI;
            assert_eq!(index, 0);
            assert!((t - exact).abs() < tolerance, "{method}: {t} vs {exact}");
            assert_eq!(rising, k % 2 == 1, "{method}: crossing {k}");
            assert!(x.abs() < 1e-12, "{method}: x = {x} at the crossing");
        }
    }
}

#[test]
fn gauss_is_order_six_and_conserves_the_quadratic_energy() {
    let options = IntegratorOptions {
        step: Some(0.1),
        ..IntegratorOptions::default()
    };
    let (outcome, out) = run(Method::Gauss, options, false);
    assert_eq!(outcome.stop, StopReason::Finished);
    assert_eq!(outcome.stats.steps, 100);
    let (t, y) = out.last().cloned().unwrap();
    assert_eq!(t, 10.0);
    assert!((y[0] - t.cos()).abs() < 1e-8, "{}", y[0] - t.cos());
    for (_, y) in &out {
        assert!((y[0] * y[0] + y[1] * y[1] - 1.0).abs() < 1e-13);
    }
}

/// `y' = 1/(1 − t)` blows up at t = 1: the run must stop there with a failure, keeping
/// what came before.
struct BlowUp;

impl OdeSystem for BlowUp {
    fn dimension(&self) -> usize {
        1
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        dy[0] = y[0] * y[0];
        Ok(())
    }
}

#[test]
fn a_blow_up_fails_near_its_time_and_keeps_the_data() {
    let mut out = Vec::new();
    let outcome = integrate(
        &mut BlowUp,
        Method::Dopri5,
        0.0,
        &[1.0],
        2.0,
        &IntegratorOptions::default(),
        &mut |t, y| out.push((t, y[0])),
    );
    let StopReason::Failed(failure) = outcome.stop else {
        panic!("no failure: {:?}", outcome.stop);
    };
    assert!((outcome.t - 1.0).abs() < 1e-3, "{failure} at {}", outcome.t);
    assert!(out.len() > 10);
    assert!(
        out.iter().all(|(t, _)| *t < 1.0 + 1e-6),
        "{failure}: {:?}",
        &out[out.len() - 3..]
    );
    assert!(out
        .iter()
        .filter(|(t, _)| *t < 0.99)
        .all(|(t, y)| (y - 1.0 / (1.0 - t)).abs() < 1e-5 * y));
}

/// `y₁' = −1000 (y₁ − cos t)`, `y₂' = y₁`: a stiff relaxation onto `cos t`.
struct Stiff;

impl OdeSystem for Stiff {
    fn dimension(&self) -> usize {
        2
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        dy[0] = -1000.0 * (y[0] - t.cos());
        dy[1] = y[0];
        Ok(())
    }
}

#[test]
fn sdirk_takes_large_steps_on_a_stiff_problem_and_stays_accurate() {
    let run = |method, rtol: f64| {
        let options = IntegratorOptions {
            rtol,
            atol: rtol * 1e-2,
            ..IntegratorOptions::default()
        };
        let mut last = Vec::new();
        let outcome = integrate(
            &mut Stiff,
            method,
            0.0,
            &[0.0, 0.0],
            10.0,
            &options,
            &mut |_, y| {
                last = y.to_vec();
            },
        );
        assert_eq!(outcome.stop, StopReason::Finished);
        (outcome.stats, last)
    };
    let (_, reference) = run(Method::Dopri5, 1e-10);
    let (implicit, y) = run(Method::Sdirk, 1e-4);
    // The explicit method is held to |hλ| ≲ 3.3 by stability whatever the tolerance.
    let (explicit, _) = run(Method::Dopri5, 1e-4);
    assert!((y[0] - reference[0]).abs() < 1e-3, "{y:?} vs {reference:?}");
    assert!((y[1] - reference[1]).abs() < 1e-3, "{y:?} vs {reference:?}");
    assert!(
        implicit.steps * 4 < explicit.steps,
        "sdirk {} steps, dopri5 {}",
        implicit.steps,
        explicit.steps
    );
}

/// `x'' = −ω² x` with a huge `ω` (the pendulum with `g = 1e300` near its bottom).
struct Fast {
    omega2: f64,
}

impl OdeSystem for Fast {
    fn dimension(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        dy[0] = y[1];
        dy[1] = -self.omega2 * y[0].sin();
        Ok(())
    }
}

/// Prothero–Robinson `y' = −λ (y − cos t) − sin t`, exact `y = cos t`: stiff for large λ.
struct ProtheroRobinson {
    lambda: f64,
}

impl OdeSystem for ProtheroRobinson {
    fn dimension(&self) -> usize {
        1
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        dy[0] = -self.lambda * (y[0] - t.cos()) - t.sin();
        Ok(())
    }
}

fn count_rows(
    system: &mut dyn OdeSystem,
    method: Method,
    y0: &[f64],
    t_end: f64,
    options: &IntegratorOptions,
) -> (Outcome, u64) {
    let mut rows = 0;
    let outcome = integrate(system, method, 0.0, y0, t_end, options, &mut |_, _| {
        rows += 1
    });
    (outcome, rows)
}

#[test]
fn a_runaway_stops_at_once_with_the_collapsed_step() {
    // g = 1e300: the step needed is ~1e-150 of the span; the run stops on the first step
    // instead of writing rows for ever.
    let options = IntegratorOptions::default();
    for method in [Method::Dopri5, Method::Dop853, Method::Sdirk, Method::Gauss] {
        let (outcome, rows) = count_rows(
            &mut Fast { omega2: 1e300 },
            method,
            &[0.5, 0.0],
            1.0,
            &options,
        );
        match outcome.stop {
            StopReason::Failed(Failure::StepCollapse {
                h, span, fraction, ..
            }) => {
                assert_eq!(span, 1.0);
                assert!(h < STEP_COLLAPSE_FRACTION * span, "{method}: h = {h}");
                assert_eq!(fraction, h / span);
            }
            other => panic!("{method}: {other:?}"),
        }
        assert!((1..1000).contains(&rows), "{method}: {rows} rows");
        assert!(
            outcome.stats.steps < 10_000,
            "{method}: {:?}",
            outcome.stats
        );
    }
}

#[test]
fn a_stiff_problem_stops_the_explicit_method_and_not_the_implicit_one() {
    let options = IntegratorOptions {
        rtol: 1e-6,
        atol: 1e-8,
        ..IntegratorOptions::default()
    };
    let (outcome, _) = count_rows(
        &mut ProtheroRobinson { lambda: 1e6 },
        Method::Dopri5,
        &[1.0],
        10.0,
        &options,
    );
    match outcome.stop {
        StopReason::Failed(Failure::Stiff {
            t,
            h,
            h_lambda,
            steps,
            remaining,
        }) => {
            assert!(remaining > STIFF_PROJECTED_STEPS, "{remaining}");
            assert!(h_lambda > STIFF_H_LAMBDA, "{h_lambda}");
            assert_eq!(steps, STIFF_STEPS);
            // Stability of Dormand–Prince on the real axis ends near h·λ = 3.3.
            assert!(h * 1e6 < 4.0 && h * 1e6 > 1.0, "h = {h}");
            assert!(t > 0.0 && t < 1e-2, "t = {t}");
            assert_eq!(outcome.t, t);
        }
        other => panic!("{other:?}"),
    }
    // Gauss's fixed-point iteration diverges at any step above ~1/λ: it stops at once,
    // saying so and naming sdirk (it used to diverge into "a value is not finite").
    let (outcome, rows) = count_rows(
        &mut ProtheroRobinson { lambda: 1e6 },
        Method::Gauss,
        &[1.0],
        10.0,
        &options,
    );
    match outcome.stop {
        StopReason::Failed(failure @ Failure::NotConverged { t, h }) => {
            assert_eq!(t, 0.0);
            assert!(h * 1e6 > 0.5, "h = {h}");
            assert!(failure.to_string().contains("sdirk"), "{failure}");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(rows, 1);
    assert!(outcome.stats.evaluations < 100_000, "{:?}", outcome.stats);
    // The same problem is routine for the L-stable method.
    let (outcome, _) = count_rows(
        &mut ProtheroRobinson { lambda: 1e6 },
        Method::Sdirk,
        &[1.0],
        10.0,
        &options,
    );
    assert_eq!(outcome.stop, StopReason::Finished);
    assert!(outcome.stats.steps < 100_000, "{:?}", outcome.stats);
}

#[test]
fn a_non_stiff_oscillation_is_not_called_stiff() {
    // Loose and tight tolerances: accuracy, not stability, limits the step.
    for rtol in [1e-3, 1e-6, 1e-12] {
        let options = IntegratorOptions {
            rtol,
            atol: rtol * 1e-2,
            ..IntegratorOptions::default()
        };
        let (outcome, _) = run(Method::Dopri5, options, false);
        assert_eq!(outcome.stop, StopReason::Finished, "rtol {rtol}");
    }
}

#[test]
fn the_step_and_row_limits_stop_the_run_with_the_rows_so_far() {
    let limited = |max_steps, max_outputs, output_step| IntegratorOptions {
        max_steps,
        max_outputs,
        output_step,
        ..IntegratorOptions::default()
    };
    // A row every step: 50 rows, then the 51st is due and the run stops.
    let (outcome, rows) = count_rows(
        &mut Oscillator { events: false },
        Method::Dopri5,
        &[1.0, 0.0],
        1e4,
        &limited(1_000_000, 50, None),
    );
    assert_eq!(rows, 50);
    match outcome.stop {
        StopReason::Failed(f @ Failure::TooManyOutputs { t, rows: 50 }) => {
            assert!(t > 0.0 && t < 1e4);
            assert_eq!(f.time(), t);
            assert_eq!(f.kind(), "too_many_outputs");
        }
        other => panic!("{other:?}"),
    }
    // Many rows inside one step (a fine output step) are limited as well.
    for method in [Method::Dopri5, Method::Dop853, Method::Gauss, Method::Sdirk] {
        let (outcome, rows) = count_rows(
            &mut Oscillator { events: false },
            method,
            &[1.0, 0.0],
            10.0,
            &limited(1_000_000, 200, Some(1e-3)),
        );
        assert_eq!(rows, 200, "{method}");
        assert!(
            matches!(
                outcome.stop,
                StopReason::Failed(Failure::TooManyOutputs { rows: 200, .. })
            ),
            "{method}: {:?}",
            outcome.stop
        );
    }
    // Exactly as many rows as the limit allows: finished.
    let (outcome, rows) = count_rows(
        &mut Oscillator { events: false },
        Method::Dopri5,
        &[1.0, 0.0],
        1.0,
        &limited(1_000_000, 11, Some(0.1)),
    );
    assert_eq!((outcome.stop, rows), (StopReason::Finished, 11));
    // The step limit.
    let (outcome, _) = count_rows(
        &mut Oscillator { events: false },
        Method::Dopri5,
        &[1.0, 0.0],
        1e4,
        &limited(100, 1_000_000, None),
    );
    assert!(matches!(
        outcome.stop,
        StopReason::Failed(Failure::TooManySteps { steps: 100, .. })
    ));
    assert_eq!(outcome.stats.steps, 100);
}

#[test]
fn gauss_chooses_its_step_from_the_dynamics_and_its_estimate_bounds_the_error() {
    // The same oscillator at ω = 1 and ω = 50: the step must follow the frequency, not the
    // span, and the estimate must bound the error against the exact solution.
    for omega in [1.0_f64, 50.0] {
        let mut system = Fast {
            omega2: omega * omega,
        };
        let y0 = [0.1, 0.0];
        let mut last = (0.0, vec![]);
        let options = IntegratorOptions::default();
        let outcome = integrate(
            &mut system,
            Method::Gauss,
            0.0,
            &y0,
            20.0,
            &options,
            &mut |t, y| {
                last = (t, y.to_vec());
            },
        );
        assert_eq!(outcome.stop, StopReason::Finished);
        assert_eq!(last.0, 20.0);
        let estimate = outcome.error_estimate.expect("gauss estimates its error");
        // The reference: dopri5 at tight tolerances (the pendulum is nonlinear).
        let mut reference = vec![];
        let tight = IntegratorOptions {
            rtol: 1e-13,
            atol: 1e-15,
            ..IntegratorOptions::default()
        };
        integrate(
            &mut system,
            Method::Dopri5,
            0.0,
            &y0,
            20.0,
            &tight,
            &mut |_, y| {
                reference = y.to_vec();
            },
        );
        let error = (last.1[0] - reference[0])
            .abs()
            .max((last.1[1] - reference[1]).abs());
        assert!(
            error <= estimate,
            "ω = {omega}: error {error:e} > estimate {estimate:e}"
        );
        // Within the tolerances (scale 1e-10 + 1e-8·|y|), not far below them.
        assert!(estimate < 1e-8, "ω = {omega}: estimate {estimate:e}");
        assert!(error < 1e-8, "ω = {omega}: error {error:e}");
        // The step follows the frequency: a sensible number of steps per period at both.
        let per_period = outcome.stats.steps as f64 / (20.0 * omega / std::f64::consts::TAU);
        assert!(
            (5.0..500.0).contains(&per_period),
            "ω = {omega}: {per_period} steps per period"
        );
    }
}

#[test]
fn a_span_far_too_long_for_the_motion_stops_at_once_at_the_motions_own_step() {
    // The oscillator's period is 2π: an end time of 1e29 (or 1e308, where stepping at the
    // floor overflowed the state into "not finite") would take ~1e30 steps.
    for t_end in [1e29, 1e308] {
        for method in [Method::Dopri5, Method::Dop853, Method::Gauss, Method::Sdirk] {
            let (outcome, rows) = count_rows(
                &mut Oscillator { events: false },
                method,
                &[1.0, 0.0],
                t_end,
                &IntegratorOptions::default(),
            );
            match outcome.stop {
                StopReason::Failed(Failure::StepCollapse { t, h, span, .. }) => {
                    assert_eq!((t, span), (0.0, t_end), "{method}");
                    assert!(h < STEP_COLLAPSE_FRACTION * span, "{method}: h = {h}");
                }
                other => panic!("{method} to {t_end}: {other:?}"),
            }
            assert_eq!(rows, 1, "{method}");
            assert!(outcome.stats.steps == 0, "{method}: {:?}", outcome.stats);
            assert!(
                outcome.stats.evaluations < 2_000,
                "{method}: {:?}",
                outcome.stats
            );
        }
        // The explicit method reports the step the dynamics ask for, not a step near the
        // floor: about a tenth of the motion's time scale.
        let (outcome, _) = count_rows(
            &mut Oscillator { events: false },
            Method::Dopri5,
            &[1.0, 0.0],
            t_end,
            &IntegratorOptions::default(),
        );
        let StopReason::Failed(Failure::StepCollapse { h, .. }) = outcome.stop else {
            unreachable!()
        };
        assert!(h > 1e-4 && h < 1.0, "h = {h}");
    }
}

#[test]
fn an_observer_that_breaks_halts_the_run_after_its_row() {
    for (method, output_step) in [
        (Method::Dopri5, None),
        (Method::Dopri5, Some(0.01)),
        (Method::Dop853, None),
        (Method::Dop853, Some(0.01)),
        (Method::Gauss, Some(0.01)),
        (Method::Sdirk, None),
    ] {
        let options = IntegratorOptions {
            output_step,
            ..IntegratorOptions::default()
        };
        let mut rows: Vec<(f64, f64)> = Vec::new();
        let outcome = integrate_observed(
            &mut Oscillator { events: false },
            method,
            0.0,
            &[1.0, 0.0],
            10.0,
            &options,
            &mut |t, y| {
                rows.push((t, y[0]));
                if rows.len() == 7 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            },
            &mut |_| {},
        );
        assert_eq!(rows.len(), 7, "{method}");
        let (t, x) = rows[6];
        assert_eq!(outcome.stop, StopReason::Halted { t }, "{method}");
        assert_eq!(outcome.t, t, "{method}");
        assert!(
            t > 0.0 && (x - t.cos()).abs() < 1e-5,
            "{method}: x({t}) = {x}"
        );
    }
    // Breaking at the initial row: nothing is integrated.
    let outcome = integrate_observed(
        &mut Oscillator { events: false },
        Method::Dopri5,
        0.0,
        &[1.0, 0.0],
        10.0,
        &IntegratorOptions::default(),
        &mut |_, _| ControlFlow::Break(()),
        &mut |_| {},
    );
    assert_eq!(outcome.stop, StopReason::Halted { t: 0.0 });
    assert_eq!(outcome.stats.evaluations, 0);
}
