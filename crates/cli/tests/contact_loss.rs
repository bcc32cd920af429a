//! A simulation stops where a one-sided constraint the model asks about is lost: the particle
//! sliding off a sphere leaves it where cos θ = ⅔ cos θ₀ (from rest at θ₀).

use std::process::Output;

mod common;
use common::{lagrange, lagrange_with, SPHERE_RUN};

fn last_row(o: &Output) -> Vec<f64> {
    let text = String::from_utf8_lossy(&o.stdout);
    let line = text.lines().last().expect("rows");
    line.split(',')
        .map(|x| x.parse().expect("a number"))
        .collect()
}

#[test]
fn the_particle_leaves_the_sphere_where_the_normal_force_vanishes() {
    for theta0 in ["0.01", "0.5"] {
        let o = lagrange_with(&SPHERE_RUN, &["--set", &format!("theta={theta0}")]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("the one-sided constraint `normal` is lost"),
            "{err}"
        );
        let row = last_row(&o);
        let theta0: f64 = theta0.parse().expect("a number");
        let want = (2.0 / 3.0 * theta0.cos()).acos();
        assert!((row[1] - want).abs() < 1e-7, "θ = {} vs {want}", row[1]);
        assert!(row[0] < 5.0);
    }
    // Asked to go on, it runs to the end.
    let o = lagrange(&[
        "simulate",
        "examples/particle-on-sphere.lag",
        "--t-end",
        "2",
        "--through-contact-loss",
    ]);
    assert!(o.status.success());
    assert_eq!(last_row(&o)[0], 2.0);
}

#[test]
fn a_stop_when_expression_does_not_hide_the_contact_events() {
    // Both are stop events; each is watched (once only the first one was).
    let o = lagrange(&[
        "simulate",
        "examples/particle-on-sphere.lag",
        "--t-end",
        "5",
        "--stop-when",
        "t - 100",
        "--set",
        "theta=0.5",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("the one-sided constraint `normal` is lost"),
        "{err}"
    );
    let want = (2.0 / 3.0 * 0.5f64.cos()).acos();
    assert!((last_row(&o)[1] - want).abs() < 1e-6);
}
