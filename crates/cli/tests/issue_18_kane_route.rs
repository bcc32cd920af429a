//! Issue 18: `lagrange simulate` and `lagrange solve` on the Whipple bicycle spent 8–10 s
//! deriving Lagrange's equations with multipliers and then failed at the work limit. They
//! now go by Kane's route (the reduced equations evaluated numerically), run for real here:
//! the CSV has the usual columns, and the solution is written in every format.

mod common;
use common::lagrange;

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn the_bicycle_simulates_with_the_usual_columns() {
    let o = lagrange(&[
        "simulate",
        "examples/whipple-bicycle.lag",
        "--t-end",
        "0.5",
        "--output-step",
        "0.25",
        "--set",
        "phi'=0.1",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    let mut lines = out.lines();
    assert_eq!(
        lines.next(),
        Some("t,x,y,psi,phi,theta,thetaR,delta,thetaF,x_d,y_d,psi_d,phi_d,theta_d,thetaR_d,delta_d,thetaF_d,energy_error,constraint_drift")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().expect("a number")).collect())
        .collect();
    let times: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    assert_eq!(times, [0.0, 0.25, 0.5]);
    // It rides forward at v = 5 and leans at the rate given.
    assert_eq!((rows[0][9], rows[0][12]), (5.0, 0.1));
    assert!(rows[2][1] > 2.4 && rows.iter().all(|r| r[17].abs() < 1e-7));
}

#[test]
fn the_bicycle_solves_by_kane_in_every_format() {
    for format in ["text", "md", "tex", "json"] {
        let o = lagrange(&["solve", "examples/whipple-bicycle.lag", "--format", format]);
        assert!(o.status.success(), "{format}: {}", text(&o.stderr));
        let out = text(&o.stdout);
        assert!(out.contains("Kane"), "{format}: {out}");
        assert!(
            out.contains("14.07838969"),
            "{format}: no eigenvalue in {out}"
        );
    }
}
