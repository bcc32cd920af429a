//! Reactions of the examples against independent SymPy data (`tests/data/reactions/*.json`,
//! Newton's law with accelerations from `LagrangesMethod`, written by
//! `tools/sympy_reference/reactions.py`), at every sample; and the two methods' agreement.

use cas::{Symbol, SymbolKind};
use mechanics::{Agreement, Reaction};
use serde_json::Value;

fn env_of(values: &serde_json::Map<String, Value>) -> impl Fn(Symbol) -> Option<f64> + '_ {
    move |s: Symbol| {
        let key = match s.kind() {
            SymbolKind::Time => "t".to_string(),
            SymbolKind::TimeFunction { order: 1 } => format!("{}_d", s.name()),
            SymbolKind::TimeFunction { order: 2 } => format!("{}_dd", s.name()),
            _ => s.name().to_string(),
        };
        values.get(&key).and_then(Value::as_f64)
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-8 * (1.0 + a.abs().max(b.abs()))
}

fn reactions_of(path: &str) -> Vec<Reaction> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let source = std::fs::read_to_string(format!("{root}/{path}")).expect("example");
    let model = model::load(&source).expect("valid model");
    let system = model::lower(&model).expect("lowers");
    let requests = model::reaction_requests(&model).expect("releases lower");
    mechanics::reactions(&system, &requests).expect("reactions")
}

#[test]
fn reactions_match_sympy_newton_reference_data() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let mut files: Vec<_> = std::fs::read_dir(format!("{root}/tests/data/reactions"))
        .expect("tests/data/reactions")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    assert!(files.len() >= 6, "reference data for at least 6 systems");
    for file in files {
        let data: Value =
            serde_json::from_str(&std::fs::read_to_string(&file).expect("read")).expect("json");
        let model = data["model"].as_str().expect("model");
        let reactions = reactions_of(model);
        let kinds = data["kinds"].as_object().expect("kinds");
        for (key, kind) in kinds {
            // `NAME@couple` is the couple of reaction NAME, `NAME@friction` its friction.
            let name = key.split('@').next().unwrap_or(key);
            let reaction = reactions
                .iter()
                .find(|r| r.name == name)
                .unwrap_or_else(|| panic!("{model}: no reaction `{name}`"));
            assert!(
                matches!(reaction.agreement, Agreement::Exact | Agreement::Numeric),
                "{model}: `{name}`: Lagrange I and Newton–Euler disagree"
            );
            for sample in data["samples"].as_array().expect("samples") {
                let values = sample["values"].as_object().expect("values");
                let env = env_of(values);
                let expected = &sample["reactions"][key];
                let got: Vec<f64> = match kind.as_str() {
                    Some("friction") => reaction
                        .friction
                        .expect("a friction force")
                        .iter()
                        .map(|e| e.eval(&env).expect("evaluates"))
                        .collect(),
                    Some("couple") => reaction
                        .couple
                        .expect("a couple")
                        .iter()
                        .map(|e| e.eval(&env).expect("evaluates"))
                        .collect(),
                    Some("components") => reaction
                        .force
                        .expect("a force")
                        .iter()
                        .map(|e| e.eval(&env).expect("evaluates"))
                        .collect(),
                    _ => vec![reaction
                        .along
                        .expect("a scalar")
                        .0
                        .eval(&env)
                        .expect("evaluates")],
                };
                let want: Vec<f64> = match expected {
                    Value::Array(a) => a.iter().filter_map(Value::as_f64).collect(),
                    other => vec![other.as_f64().expect("number")],
                };
                assert_eq!(got.len(), want.len());
                for (g, w) in got.iter().zip(&want) {
                    assert!(
                        close(*g, *w),
                        "{model}: `{name}`: {got:?} vs SymPy {want:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn particle_leaves_the_sphere_where_the_normal_force_is_m_g_3cos_minus_2() {
    // Exact check of the form: N = m (g cos θ − r θ̇²).
    let reactions = reactions_of("examples/particle-on-sphere.lag");
    let normal = reactions[0].along.expect("a normal force").0;
    let (m, r, g) = (
        cas::Expr::symbol("m"),
        cas::Expr::symbol("r"),
        cas::Expr::symbol("g"),
    );
    let th = cas::Expr::coordinate("theta");
    let thd = cas::Expr::rate("theta", 1);
    assert!(normal.equals(m * (g * th.cos() - r * thd.powi(2))));
}

#[test]
fn constraint_multipliers_are_generalized_reactions() {
    // The Cartesian pendulum's rod: Q^R = −Aᵀλ with A = (2x, 2y); on the circle the tension
    // is m (v² − g y)/l² times the position, pulling towards the pivot.
    let reactions = reactions_of("examples/cartesian-pendulum.lag");
    let rod = &reactions[0];
    assert_eq!(rod.agreement, Agreement::Single);
    let (x, y) = (cas::Expr::coordinate("x"), cas::Expr::coordinate("y"));
    let (xd, yd) = (cas::Expr::rate("x", 1), cas::Expr::rate("y", 1));
    let (m, g) = (cas::Expr::symbol("m"), cas::Expr::symbol("g"));
    let lambda = m * (xd.powi(2) + yd.powi(2) - g * y) / (2 * (x.powi(2) + y.powi(2)));
    assert!(rod.multipliers[0].equals(lambda));
    assert!(rod.generalized[0].1.equals(-(2 * x * lambda)));
}

#[test]
fn the_torque_that_drives_the_hoop_is_the_rate_of_its_angular_momentum() {
    // T = ½ m R² (θ̇² + sin²θ Ω²): Q_ψ = d/dt(∂T/∂ψ̇) = 2 m R² Ω θ̇ sin θ cos θ.
    let reactions = reactions_of("examples/bead-on-rotating-hoop.lag");
    let psi = &reactions[0];
    assert!(psi.driving);
    let (m, r, omega) = (
        cas::Expr::symbol("m"),
        cas::Expr::symbol("R"),
        cas::Expr::symbol("Omega"),
    );
    let th = cas::Expr::coordinate("theta");
    let thd = cas::Expr::rate("theta", 1);
    let expected = 2 * m * r.powi(2) * omega * thd * th.sin() * th.cos();
    assert_eq!(psi.generalized.len(), 1);
    assert!(psi.generalized[0].1.equals(expected));
}

#[test]
fn a_rolling_disk_in_three_dimensions_has_a_consistent_contact_force() {
    // Upright disk rolling on a plane: the redundant normal row of the rolling constraint gets
    // a zero multiplier; the contact carries the weight, and both methods agree.
    let source = "coordinates x, y, psi, phi\nparameters m = 1, R = 0.5, g = 9.81\nframe N\n\
                  frame H = N rotated psi about z\nframe D = H rotated phi about x\n\
                  point C = x*N.x + y*N.y + R*N.z\npoint A = x*N.x + y*N.y\n\
                  body disk mass m at C frame D inertia m*R^2/2, m*R^2/4, m*R^2/4\n\
                  gravity -g*N.z\nconstraint roll: rolling disk at A\nreactions roll\n";
    let model = model::load(source).expect("valid model");
    let system = model::lower(&model).expect("lowers");
    let requests = model::reaction_requests(&model).expect("releases lower");
    let reactions = mechanics::reactions(&system, &requests).expect("reactions");
    let roll = &reactions[0];
    assert_eq!(roll.agreement, Agreement::Exact);
    let force = roll.force.expect("a force");
    assert!(force[2].equals(cas::Expr::symbol("m") * cas::Expr::symbol("g")));
}

#[test]
fn a_couple_a_hinge_cannot_transmit_is_reported() {
    // The inverted pendulum's hinge needs no couple; the seed's cone is also held by its apex,
    // so the translation of the cone releases both supports and a couple about A is needed.
    let hinge = &reactions_of("examples/seed/7.4-inverted-pendulum.lag")[0];
    assert!(hinge.unbalanced_couple.is_none());
    assert!(hinge.couple.is_none());
    let cone = &reactions_of("examples/seed/7.2-rolling-cone.lag")[0];
    assert!(cone.unbalanced_couple.is_some());
    // A clamp reports its couple and no unbalanced one.
    let weld = &reactions_of("examples/cart-with-mast.lag")[0];
    assert!(weld.couple.is_some() && weld.unbalanced_couple.is_none());
}
