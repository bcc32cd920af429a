//! Issue 14, edges of constraints kept with multipliers, found by the mutation fuzzer
//! (docs/reliability.md, case 9 and its neighbours).
//!
//! - The cartesian pendulum with its rod written `x^0.0000001 + y^2 = l^2` once left `ÿ` in
//!   the constraint's acceleration-level right-hand side, and the run asked for a value of
//!   `y_dd` (exit 4). The root `x^(1/10⁷)` is a power of degree 10⁷ in the normal form: the
//!   derivation now stops at the work limit, located at the constraint's statement, and with
//!   the limit raised it gives the right row (no acceleration on the right) and runs.
//! - With the rod written `x^3 + y^2 = l^2` the particle falls away for ever (the curve is
//!   unbounded); at x = −16 the projection onto the constraint "did not converge" because it
//!   held `Φ` to an absolute residual below its own rounding (the terms of `Φ` are 4,600
//!   there). The projection now judges `Φ` as the position error it stands for (`Φ/|∇Φ|`).

use lagrange::cas::{self, Expr};
use lagrange::{Analysis, Ending, SimulationOptions};

fn pendulum_with_rod(rod: &str) -> String {
    format!(
        "coordinates x, y
parameters  m = 1, l = 1, g = 9.81
frame N
point P = x*N.x + y*N.y
particle P mass m
gravity -g*N.y
constraint rod: {rod}
initial x = 0.5, y = -0.8660254037844386
"
    )
}

fn options(t_end: f64) -> SimulationOptions {
    SimulationOptions {
        t_end: Some(t_end),
        ..SimulationOptions::default()
    }
}

#[test]
fn a_root_of_huge_degree_stops_at_the_constraint_and_is_right_past_the_limit() {
    let mut analysis = Analysis::from_text(&pendulum_with_rod("x^0.0000001 + y^2 = l^2")).unwrap();
    let error = analysis.equations().unwrap_err();
    assert!(error.work_limit().is_some(), "{error}");
    let lagrange::Error::WorkLimit { at, message, .. } = &error else {
        panic!("{error:?}");
    };
    assert_eq!(*at, Some((7, 1)), "{message}");
    assert!(message.contains("constraint `rod`"), "{message}");

    analysis.set_work_limits(cas::work_limits().scaled(1e4));
    let equations = analysis.equations().unwrap();
    let accelerations = [Expr::rate("x", 2), Expr::rate("y", 2)];
    for rhs in equations.constraint_rhs() {
        for a in accelerations.iter().filter_map(|a| a.as_symbol()) {
            assert!(rhs.diff(a).is_zero(), "{rhs}");
        }
    }
    let run = analysis.simulate(&options(0.5)).unwrap();
    assert!(matches!(run.ending, Ending::Finished), "{:?}", run.ending);
}

#[test]
fn a_constraint_with_large_terms_is_projected_onto_where_the_motion_takes_it() {
    let analysis = Analysis::from_text(&pendulum_with_rod("x^3 + y^2 = l^2")).unwrap();
    let run = analysis.simulate(&options(5.0)).unwrap();
    assert!(matches!(run.ending, Ending::Finished), "{:?}", run.ending);
    let last = run.rows.last().unwrap();
    let (x, y) = (last[1], last[2]);
    // It has fallen far along the unbounded branch, and is still on the curve to within the
    // rounding of its terms.
    assert!(x < -10.0 && y < -30.0, "x = {x}, y = {y}");
    let residual = x.powi(3) + y * y - 1.0;
    assert!(residual.abs() <= 1e-9 * y * y, "Φ = {residual}");
}
