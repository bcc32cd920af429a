//! Issue 17: reactions of constrained systems, evaluated numerically.
//!
//! `lagrange reactions examples/four-bar.lag` took minutes and printed ~1 MB for two
//! multipliers; then it was refused as too large for closed form, and the multipliers alone
//! were solved numerically at the initial state on the compiled equations
//! (`[M Aᵀ; A 0] [q̈; λ] = [f; b]`, [`lagrange::Analysis::multipliers_at_start`]). Checked two
//! ways: against the closed form where there is one (the Atwood machine's rope and no-slip
//! multipliers, evaluated at the same state), and on the four-bar by the equations
//! themselves, evaluated as trees (not tapes): the accelerations that `M q̈ = f − Aᵀλ` gives
//! with the numeric `λ` must satisfy the constraints' `A q̈ = b`.
//!
//! Then every reaction kind: a released hinge or contact existed only as a closed form,
//! derived by deriving the released system again symbolically (the rolling cone's was 88 % of
//! its `solve`, issue 20), and no reaction could be followed along a simulation. Now every
//! kind is compiled once (`mechanics::ReactionEvaluator`: the released system's Lagrange
//! residuals by Kane's method with dual numbers, multipliers from the KKT solve) and
//! evaluated at any state; a size limit chooses it over the closed form
//! (`ReactionRoute::Auto`), and the CSV of a run, the solution and the JSON carry the values.
//! The numbers are checked against the closed form where it exists (which itself agrees with
//! the Newton–Euler balance of the released bodies), at pseudo-random states, to 1e-10.

use std::collections::HashMap;

use lagrange::cas::{Expr, Symbol};
use lagrange::mechanics::{Agreement, Quantity, Reaction, ReactionColumn};
use lagrange::{numeric, Analysis, NumericMultipliers, ReactionRoute, SimulationOptions};

fn example(name: &str) -> Analysis {
    let path = format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    Analysis::from_file(std::path::Path::new(&path)).unwrap()
}

fn analysis(name: &str, route: ReactionRoute) -> Analysis {
    let mut analysis = example(name);
    analysis.set_reaction_route(route);
    analysis
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
    let atwood = analysis("atwood-machine.lag", ReactionRoute::ClosedForm);
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

/// A reproducible value in `[-1, 1]`.
fn draw(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

/// The closed form of a column, as the numeric route names it.
fn closed_form(reactions: &[Reaction], column: &ReactionColumn, index: usize) -> Expr {
    let r = reactions
        .iter()
        .find(|r| r.name == column.reaction)
        .unwrap_or_else(|| panic!("no closed form for {}", column.name));
    match column.quantity {
        Quantity::Force(k) => r.force.unwrap()[k],
        Quantity::Along => r.along.unwrap().0,
        Quantity::Couple(k) => r.couple.unwrap()[k],
        Quantity::Multiplier => r.multipliers[index],
        Quantity::Generalized => {
            let found = r.generalized.iter().find(|(q, _)| {
                column.name == format!("Q_{}", r.name) || column.name == format!("Q_{}_{q}", r.name)
            });
            found.unwrap_or_else(|| panic!("{}", column.name)).1
        }
        other => panic!("{other:?}"),
    }
}

/// The numeric route against the closed form at a few random states (each coordinate and
/// rate drawn in [-1, 1] about the model's initial state), relative 1e-10.
fn numbers_match_the_closed_form(name: &str) {
    let symbolic = analysis(name, ReactionRoute::ClosedForm);
    let reactions = symbolic.reactions().unwrap().unwrap();
    assert!(reactions.numeric.is_none(), "{name}");
    assert!(
        reactions
            .reactions
            .iter()
            .all(|r| r.agreement != Agreement::Disagree),
        "{name}"
    );
    let numeric = analysis(name, ReactionRoute::Numeric);
    let probe = numeric.reaction_probe().unwrap().unwrap();
    let columns = probe.described().to_vec();
    assert!(!columns.is_empty(), "{name}");
    let mut simulation = numeric
        .simulation(&SimulationOptions {
            t_end: Some(1.0),
            through_contact_loss: true,
            ..SimulationOptions::default()
        })
        .unwrap();
    let coordinates = reactions.coordinates.clone();
    let values = numeric.values().unwrap();
    let mut seed = name.len() as u64;
    for _ in 0..4 {
        let mut state = simulation.initial_state().to_vec();
        for x in &mut state {
            *x += draw(&mut seed);
        }
        let t = 0.3;
        let got = probe.at(&mut simulation, t, &state);
        let n = coordinates.len();
        let env = |s: Symbol| {
            use lagrange::cas::SymbolKind;
            match s.kind() {
                SymbolKind::TimeFunction { order } => {
                    let k = coordinates.iter().position(|q| q == s.name())?;
                    match order {
                        0 => Some(state[k]),
                        1 => Some(state[n + k]),
                        _ => None,
                    }
                }
                _ if s.name() == "t" => Some(t),
                _ => values.iter().find(|(v, _)| v == s.name()).map(|(_, x)| *x),
            }
        };
        let mut index = std::collections::HashMap::new();
        for (column, value) in columns.iter().zip(&got) {
            let i = index.entry(column.reaction.clone()).or_insert(0usize);
            let expected = closed_form(&reactions.reactions, column, *i)
                .eval(&env)
                .unwrap();
            if column.quantity == Quantity::Multiplier {
                *i += 1;
            }
            assert!(
                (value - expected).abs() <= 1e-10 * (1.0 + expected.abs()),
                "{name} {}: {value} numerically, {expected} in closed form",
                column.name
            );
        }
    }
}

#[test]
fn hinges_give_the_closed_forms_numbers() {
    numbers_match_the_closed_form("double-pendulum.lag");
    numbers_match_the_closed_form("simple-pendulum.lag");
}

#[test]
fn contacts_and_ropes_give_the_closed_forms_numbers() {
    numbers_match_the_closed_form("particle-on-sphere.lag");
    numbers_match_the_closed_form("ladder.lag");
    numbers_match_the_closed_form("atwood-machine.lag");
}

#[test]
fn rolling_contacts_and_clamps_give_the_closed_forms_numbers() {
    numbers_match_the_closed_form("seed/7.2-rolling-cone.lag");
    numbers_match_the_closed_form("cart-with-mast.lag");
    numbers_match_the_closed_form("rolling-disk-incline.lag");
}

#[test]
fn multipliers_and_driving_forces_give_the_closed_forms_numbers() {
    numbers_match_the_closed_form("cartesian-pendulum.lag");
    numbers_match_the_closed_form("driven-pivot-pendulum.lag");
    numbers_match_the_closed_form("bead-on-rotating-hoop.lag");
    numbers_match_the_closed_form("seed/7.3-gears-pendulum.lag");
}

#[test]
fn the_size_limit_chooses_numbers_for_large_closed_forms_only() {
    // Large: the rolling disk's contact on the incline, the four-bar's loop (refused in
    // closed form).
    for name in ["rolling-disk-incline.lag", "four-bar.lag"] {
        let analysis = example(name);
        let reactions = analysis.reactions().unwrap().unwrap();
        assert!(reactions.reactions.is_empty(), "{name}");
        let start = reactions.numeric.as_ref().expect(name);
        assert!(start.values.iter().all(|(_, v)| v.is_finite()), "{name}");
        assert_eq!(analysis.reaction_derivations(), 0, "{name}");
        let text = reactions.to_text();
        assert!(text.contains("evaluated numerically"), "{name}: {text}");
        let json = reactions.to_json();
        assert!(json["numeric"]["values"].is_object(), "{name}: {json}");
    }
    // Small: a course's pendulum, a contact, an Atwood machine (constant constraint rows),
    // the double pendulum's hinges, and the seed's rolling cone, whose closed form its course
    // solution prints.
    for name in [
        "double-pendulum.lag",
        "seed/7.2-rolling-cone.lag",
        "simple-pendulum.lag",
        "particle-on-sphere.lag",
        "atwood-machine.lag",
    ] {
        let analysis = example(name);
        let reactions = analysis.reactions().unwrap().unwrap();
        assert!(reactions.numeric.is_none(), "{name}");
        assert!(!reactions.reactions.is_empty(), "{name}");
    }
}

#[test]
fn the_four_bar_s_numeric_reactions_are_its_multipliers() {
    let four_bar = example("four-bar.lag");
    let numeric = four_bar.multipliers_at_start().unwrap();
    let reactions = four_bar.reactions().unwrap().unwrap();
    let values = &reactions.numeric.as_ref().unwrap().values;
    let names: Vec<&str> = values.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["lambda_loop_x", "lambda_loop_y"]);
    for ((_, a), (_, b)) in values.iter().zip(&numeric.multipliers) {
        assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{a} against {b}");
    }
}

#[test]
fn a_run_writes_each_reaction_component_as_a_column_by_name() {
    let dir = std::env::temp_dir().join(format!("lagrange-i17r-csv-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let pendulum = example("double-pendulum.lag");
    let options = SimulationOptions {
        t_end: Some(0.5),
        output_step: Some(0.1),
        ..SimulationOptions::default()
    };
    let files = lagrange::RunFiles {
        model: "double-pendulum.lag".into(),
        plot: Some(dir.join("plot.svg")),
        ..lagrange::RunFiles::default()
    };
    let prepared = pendulum.prepare_run(&options, files).unwrap();
    assert_eq!(prepared.warning(), None);
    let mut csv = Vec::new();
    prepared.run(&mut csv, &mut |_| {}).unwrap();
    let csv = String::from_utf8(csv).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert_eq!(
        &header[header.len() - 6..],
        ["top_x", "top_y", "top_z", "middle_x", "middle_y", "middle_z"]
    );
    // Each row's reactions are those at its state: the closed form there.
    let symbolic = analysis("double-pendulum.lag", ReactionRoute::ClosedForm);
    let closed = symbolic.reactions().unwrap().unwrap();
    let values = symbolic.values().unwrap();
    for line in csv.lines().skip(1) {
        let row: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let env = |s: Symbol| {
            let k = ["theta1", "theta2"].iter().position(|q| *q == s.name());
            match (k, s.order()) {
                (Some(k), 0) => Some(row[1 + k]),
                (Some(k), 1) => Some(row[3 + k]),
                _ => values.iter().find(|(v, _)| v == s.name()).map(|(_, x)| *x),
            }
        };
        let middle_y = closed.reactions[1].force.unwrap()[1].eval(&env).unwrap();
        let got = row[row.len() - 2];
        assert!(
            (got - middle_y).abs() <= 1e-9 * (1.0 + middle_y.abs()),
            "{got} against {middle_y}"
        );
    }
    let svg = std::fs::read_to_string(dir.join("plot.svg")).unwrap();
    assert!(svg.contains("reactions"), "no reactions panel");
    assert!(svg.contains("middle_y"), "no legend for middle_y");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_solution_gives_the_numeric_reactions_at_the_start_and_at_each_equilibrium() {
    let mut analysis = example("double-pendulum.lag");
    analysis.set_reaction_route(ReactionRoute::Numeric);
    let text = analysis.solution(None).unwrap().document.to_text();
    let section = &text[text
        .find("Constraint reactions")
        .expect("a reactions section")..];
    assert!(section.contains("evaluated numerically"), "{section}");
    assert!(section.contains("middle_y"), "{section}");
    // The double pendulum has four equilibria; hanging straight down (the first found or
    // not), the top hinge carries both weights: |top_y| = (m1 + m2) g at one of them.
    let (names, at) = analysis.reactions_at_equilibria().unwrap();
    assert_eq!(at.len(), 4);
    let top_y = names.iter().position(|n| n == "top_y").unwrap();
    let middle_y = names.iter().position(|n| n == "middle_y").unwrap();
    for values in at.iter().map(|v| v.as_ref().unwrap()) {
        assert!(
            (values[top_y].abs() - 2.0 * 9.81).abs() < 1e-9,
            "{values:?}"
        );
        assert!((values[middle_y].abs() - 9.81).abs() < 1e-9, "{values:?}");
    }
    assert!(section.contains("equilibrium 4"), "{section}");
}

#[test]
fn a_contact_lost_numerically_stops_the_run_where_the_closed_form_does() {
    let options = SimulationOptions {
        t_end: Some(5.0),
        ..SimulationOptions::default()
    };
    let closed = analysis("particle-on-sphere.lag", ReactionRoute::ClosedForm)
        .simulate(&options)
        .unwrap();
    let numeric_analysis = analysis("particle-on-sphere.lag", ReactionRoute::Numeric);
    let numeric = numeric_analysis.simulate(&options).unwrap();
    assert_eq!(numeric_analysis.reaction_derivations(), 0);
    assert!(
        matches!(&numeric.ending, lagrange::Ending::ContactLost { constraint } if constraint == "normal"),
        "{:?}",
        numeric.ending
    );
    assert_eq!(numeric.ending, closed.ending);
    assert!(
        (numeric.t - closed.t).abs() < 1e-8,
        "{} against {}",
        numeric.t,
        closed.t
    );
}
