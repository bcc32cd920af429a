//! Issue 17: a coordinate without inertia of its own that the constraints kept with
//! multipliers fix (a massless slider tied to a block) was refused as "singular mass matrix",
//! although the constrained system is well posed: its matrix `[M Aᵀ; A 0]` is regular. The
//! mass matrix check now falls back on that matrix when constraints are kept; a coordinate
//! that nothing fixes is still refused.

use lagrange::{Analysis, ErrorKind, SimulationOptions};

/// A block `m` on a spring `k`, tied (`s = x`) to a massless slider held by a spring `k2`:
/// the block oscillates at `ω = √((k + k2)/m)`, and the tie carries the slider's spring force.
const TIED: &str = "coordinates x, s
parameters m = 2, k = 8, k2 = 10
frame N
point P = x*N.x
point W = N.y
point S = s*N.x + N.y
particle P mass m
spring k from origin to P
spring k2 from W to S
constraint tie: s - x = 0
reactions tie
initial x = 0.1, s = 0.1
simulate to 3
";

#[test]
fn a_massless_coordinate_fixed_by_a_kept_constraint_is_derived_and_simulated() {
    let analysis = Analysis::from_text(TIED).unwrap();
    let equations = analysis.equations().unwrap();
    assert_eq!(equations.degrees_of_freedom(), 1);
    let options = SimulationOptions {
        rtol: Some(1e-10),
        atol: Some(1e-12),
        output_step: Some(0.25),
        ..SimulationOptions::default()
    };
    let run = analysis.simulate(&options).unwrap();
    assert!(run.rows.len() > 10, "{} rows", run.rows.len());
    let omega = (18.0_f64 / 2.0).sqrt();
    let column = |name: &str| run.columns.iter().position(|c| c == name).unwrap();
    let (x, s) = (column("x"), column("s"));
    for row in &run.rows {
        let exact = 0.1 * (omega * row[0]).cos();
        assert!(
            (row[x] - exact).abs() < 1e-7,
            "t = {}: {} vs {exact}",
            row[0],
            row[x]
        );
        assert!(
            (row[s] - row[x]).abs() < 1e-9,
            "the tie holds at t = {}",
            row[0]
        );
    }
}

#[test]
fn the_tie_carries_the_massless_sliders_spring_force() {
    let analysis = Analysis::from_text(TIED).unwrap();
    let reactions = analysis.reactions().unwrap().expect("asked for");
    let text = reactions.to_text();
    // The slider's own equation `k2 s = −λ1`: the tie pulls the slider with the spring's force,
    // and pushes the block with its opposite.
    assert!(text.contains("λ1 = −k2 s"), "{text}");
    assert!(
        text.contains("Q^R_x = −k2 s") && text.contains("Q^R_s = k2 s"),
        "{text}"
    );
}

#[test]
fn a_massless_coordinate_that_nothing_fixes_is_still_refused() {
    let loose = TIED.replace("constraint tie: s - x = 0\nreactions tie\n", "");
    let error = Analysis::from_text(&loose)
        .unwrap()
        .equations()
        .unwrap_err()
        .clone();
    assert_eq!(error.kind(), ErrorKind::Mechanics);
    assert!(error.to_string().contains("singular"), "{error}");
}
