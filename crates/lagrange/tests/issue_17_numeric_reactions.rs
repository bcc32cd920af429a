//! Issue 17: `lagrange reactions examples/four-bar.lag` took minutes and printed ~1 MB for two
//! multipliers; then it was refused as too large for closed form. Now the multipliers are
//! also solved numerically at the initial state on the compiled equations
//! (`[M Aᵀ; A 0] [q̈; λ] = [f; b]`, [`lagrange::Analysis::multipliers_at_start`]), which is what
//! `lagrange reactions` prints when the closed form is refused.
//!
//! Checked two ways: against the closed form where there is one (the Atwood machine's rope and
//! no-slip multipliers, evaluated at the same state), and on the four-bar by the equations
//! themselves, evaluated as trees (not tapes): the accelerations that `M q̈ = f − Aᵀλ` gives
//! with the numeric `λ` must satisfy the constraints' `A q̈ = b`.

use std::collections::HashMap;

use lagrange::cas::{Expr, Symbol};
use lagrange::{numeric, Analysis, NumericMultipliers};

fn example(name: &str) -> Analysis {
    let path = format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    Analysis::from_file(std::path::Path::new(&path)).unwrap()
}

/// Values of the parameters, and of the coordinates and rates at the multipliers' state.
fn environment(at: &NumericMultipliers, parameters: &[(&str, f64)]) -> HashMap<(String, u8), f64> {
    let n = at.coordinates.len();
    let mut values: HashMap<(String, u8), f64> = parameters
        .iter()
        .map(|(name, value)| (((*name).to_owned(), 0), *value))
        .collect();
    for (k, q) in at.coordinates.iter().enumerate() {
        values.insert((q.clone(), 0), at.state[k]);
        values.insert((q.clone(), 1), at.state[n + k]);
    }
    values
}

fn eval(e: Expr, values: &HashMap<(String, u8), f64>) -> f64 {
    e.eval(&|s: Symbol| values.get(&(s.name().to_owned(), s.order())).copied())
        .unwrap()
}

#[test]
fn numeric_multipliers_equal_the_closed_form_where_there_is_one() {
    let atwood = example("atwood-machine.lag");
    let numeric = atwood.multipliers_at_start().unwrap();
    let parameters = [
        ("m1", 2.0),
        ("m2", 1.0),
        ("M", 0.5),
        ("R", 0.1),
        ("I", 0.0025),
        ("L", 2.0),
        ("g", 9.81),
    ];
    let values = environment(&numeric, &parameters);
    let reactions = atwood.reactions().unwrap().expect("rope and no_slip");
    let mut compared = 0;
    for reaction in &reactions.reactions {
        let Some(closed) = reaction.multipliers.first() else {
            continue;
        };
        let (_, value) = numeric
            .multipliers
            .iter()
            .find(|(name, _)| *name == reaction.name)
            .expect("the same constraint");
        let expected = eval(*closed, &values);
        assert!(
            (value - expected).abs() < 1e-9 * (1.0 + expected.abs()),
            "{}: {value} against the closed form's {expected}",
            reaction.name
        );
        compared += 1;
    }
    assert_eq!(compared, 2);
}

#[test]
fn the_four_bar_s_numeric_multipliers_make_the_accelerations_keep_the_loop_closed() {
    let four_bar = example("four-bar.lag");
    let numeric = four_bar.multipliers_at_start().unwrap();
    let names: Vec<&str> = numeric
        .multipliers
        .iter()
        .map(|(n, _)| n.as_str())
        .collect();
    assert_eq!(names, ["loop_x", "loop_y"]);
    let parameters = [
        ("a", 0.3),
        ("b", 1.0),
        ("c", 0.8),
        ("d", 1.0),
        ("m1", 1.0),
        ("m2", 2.0),
        ("m3", 1.5),
        ("g", 9.81),
    ];
    let values = environment(&numeric, &parameters);
    let equations = four_bar.equations().unwrap();
    let n = equations.coordinates().len();
    let lambda: Vec<f64> = numeric.multipliers.iter().map(|(_, v)| *v).collect();
    let a: Vec<Vec<f64>> = equations
        .constraint_matrix()
        .iter()
        .map(|row| row.iter().map(|e| eval(*e, &values)).collect())
        .collect();
    let mut mass: Vec<f64> = equations
        .mass_matrix()
        .iter()
        .flatten()
        .map(|e| eval(*e, &values))
        .collect();
    // M q̈ = f − Aᵀλ.
    let mut accelerations: Vec<f64> = (0..n)
        .map(|i| {
            eval(equations.forcing()[i], &values)
                - (0..lambda.len()).map(|k| a[k][i] * lambda[k]).sum::<f64>()
        })
        .collect();
    numeric::solve_in_place(n, &mut mass, &mut accelerations).unwrap();
    for (k, row) in a.iter().enumerate() {
        let lhs: f64 = row.iter().zip(&accelerations).map(|(x, y)| x * y).sum();
        let rhs = eval(equations.constraint_rhs()[k], &values);
        assert!((lhs - rhs).abs() < 1e-9, "row {k}: A q̈ = {lhs}, b = {rhs}");
    }
    // Not a vacuous check: the loop's multipliers hold the linkage up against gravity.
    assert!(lambda.iter().any(|l| l.abs() > 1.0), "{lambda:?}");
}
