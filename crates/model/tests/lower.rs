//! Lowering and Lagrange's equations on the seed's models: the 7.1 equations against the
//! seed's hand-written ones, 7.2's reduced equation, agreement with `Model::evaluate`, and a
//! singular mass matrix.

use cas::Expr;

fn load(path: &str) -> model::Model {
    let text = std::fs::read_to_string(format!("{}/../../{path}", env!("CARGO_MANIFEST_DIR")))
        .expect("example file");
    model::load(&text).expect("example model loads")
}

#[test]
fn seed_7_1_matches_the_seed() {
    let system = model::lower(&load("examples/seed/7.1-cart-pendulum.lag")).expect("lowers");
    let eq = mechanics::derive(&system).expect("derives");
    let s = Expr::symbol;
    let (x, th) = (Expr::coordinate("x"), Expr::coordinate("theta"));
    let (xd, thd) = (Expr::rate("x", 1), Expr::rate("theta", 1));
    let (xdd, thdd) = (Expr::rate("x", 2), Expr::rate("theta", 2));
    let (ma, mb, l, k, g) = (s("m_A"), s("m_B"), s("l"), s("k"), s("g"));
    // (m_A + m_B) ẍ + m_B ℓ θ̈ cos θ − m_B ℓ θ̇² sin θ + k x = F
    let e1 = (ma + mb) * xdd + mb * l * thdd * th.cos() - mb * l * thd.powi(2) * th.sin() + k * x;
    // m_B ℓ² θ̈ + m_B ℓ ẍ cos θ + m_B g ℓ sin θ = C
    let e2 = mb * l.powi(2) * thdd + mb * l * xdd * th.cos() + mb * g * l * th.sin();
    assert!(eq.lagrange_lhs()[0].equals(e1));
    assert!(eq.lagrange_lhs()[1].equals(e2));
    assert!(eq.generalized_forces()[0].equals(s("F")));
    assert!(eq.generalized_forces()[1].equals(s("C")));
    let _ = xd;
}

#[test]
fn seed_7_2_reduces_to_one_equation() {
    let system = model::lower(&load("examples/seed/7.2-rolling-cone.lag")).expect("lowers");
    let eq = mechanics::derive(&system).expect("derives");
    assert_eq!(eq.coordinates(), ["theta"]);
    assert_eq!(eq.eliminated().len(), 1);
    let s = Expr::symbol;
    let (m, d, alpha, ix, iz, g) = (s("m"), s("d"), s("alpha"), s("I_x"), s("I_z"), s("g"));
    let r = d * alpha.sin();
    let b = d * alpha.cos().powi(2);
    let inertia = m * b.powi(2) + ix * (b / r).powi(2) + iz * alpha.cos().powi(2);
    let th = Expr::coordinate("theta");
    // The seed's cone is a body of revolution: I_y = I_z. With I_y ≠ I_z the file's model
    // keeps a cos²φ term the seed drops.
    let symmetric = [(s("I_y"), iz)];
    assert!(eq.mass_matrix()[0][0].subs(&symmetric).equals(inertia));
    assert!(eq.forcing()[0]
        .subs(&symmetric)
        .equals(-(m * g * b * th.sin())));
    // φ = θ / sin α, i.e. R φ = (R sin α + b) θ.
    assert!(eq.eliminated()[0].value.equals(th / alpha.sin()));
}

#[test]
fn singular_mass_matrix_names_the_coordinate() {
    let m = model::load(
        "coordinates x, y\nparameters m = 1\nframe N\npoint P = x*N.x\nparticle P mass m\n",
    )
    .expect("loads");
    let system = model::lower(&m).expect("lowers");
    match mechanics::derive(&system) {
        Err(mechanics::MechanicsError::SingularMassMatrix { coordinates }) => {
            assert_eq!(coordinates, ["y"]);
        }
        other => panic!("expected a singular mass matrix, got {other:?}"),
    }
}

#[test]
fn singular_mass_matrix_without_a_zero_row_is_found() {
    // Only x + y moves the particle: M = m [[1, 1], [1, 1]] has no zero row but det M = 0.
    let m = model::load(
        "coordinates x, y\nparameters m = 1\nframe N\npoint P = (x + y)*N.x\nparticle P mass m\n",
    )
    .expect("loads");
    let system = model::lower(&m).expect("lowers");
    match mechanics::derive(&system) {
        Err(mechanics::MechanicsError::SingularMassMatrix { coordinates }) => {
            assert_eq!(coordinates, ["x", "y"]);
        }
        other => panic!("expected a singular mass matrix, got {other:?}"),
    }
}

#[test]
fn explicit_accelerations_solve_the_equations_of_motion() {
    let root = format!("{}/../..", env!("CARGO_MANIFEST_DIR"));
    let mut checked = 0;
    for dir in ["examples", "examples/seed"] {
        for entry in std::fs::read_dir(format!("{root}/{dir}"))
            .expect("examples")
            .flatten()
        {
            let path = entry.path();
            if path.extension().and_then(|e| e.to_str()) != Some("lag") {
                continue;
            }
            let text = std::fs::read_to_string(&path).expect("readable");
            let Ok(m) = model::load(&text) else { continue };
            let Ok(system) = model::lower(&m) else {
                continue;
            };
            let Ok(eq) = mechanics::derive(&system) else {
                continue;
            };
            let Some(qdd) = eq.accelerations() else {
                continue;
            };
            // M q̈ − f = 0 exactly, row by row.
            for (i, row) in eq.mass_matrix().iter().enumerate() {
                let residual =
                    row.iter().zip(qdd).map(|(m, a)| *m * *a).sum::<cas::Expr>() - eq.forcing()[i];
                // Exact where the model is exact; a decimal the user wrote is a float, and
                // float terms cancel to 0.0 rather than vanish, so those are checked by value.
                let exact = residual.is_zero();
                let by_value = (1..=3).all(|k| {
                    let env = |s: cas::Symbol| {
                        let h = s.name().bytes().fold(k as u64, |h, b| {
                            h.wrapping_mul(31).wrapping_add(u64::from(b))
                        });
                        Some(0.3 + (h % 97) as f64 / 80.0 + f64::from(s.order()) * 0.1)
                    };
                    residual.eval(&env).is_ok_and(|v| v.abs() < 1e-9)
                });
                assert!(
                    exact || (cas::print::to_sympy(residual).contains('.') && by_value),
                    "{}: row {i}: residual {residual:?}",
                    path.display()
                );
            }
            checked += 1;
        }
    }
    assert!(
        checked >= 4,
        "only {checked} examples have explicit accelerations"
    );
}

#[test]
fn a_non_integrable_constraint_is_kept_with_a_multiplier() {
    // The knife edge: −ẋ sin θ + ẏ cos θ = 0 does not integrate, so no coordinate is
    // eliminated; it enters as A q̈ = b with M q̈ + Aᵀλ = f.
    let system = model::lower(&load("examples/knife-edge.lag")).expect("lowers");
    let eq = mechanics::derive(&system).expect("derives");
    let (m, j, t) = (Expr::symbol("m"), Expr::symbol("J"), Expr::symbol("T"));
    let th = Expr::coordinate("theta");
    let (xd, yd, thd) = (
        Expr::rate("x", 1),
        Expr::rate("y", 1),
        Expr::rate("theta", 1),
    );
    assert!(eq.eliminated().is_empty());
    assert_eq!(eq.coordinates(), ["x", "y", "theta"]);
    assert_eq!(eq.constraint_names(), ["blade"]);
    let zero = Expr::zero();
    let mass = [[m, zero, zero], [zero, m, zero], [zero, zero, j]];
    for (row, want) in eq.mass_matrix().iter().zip(&mass) {
        for (a, b) in row.iter().zip(want) {
            assert!(a.equals(*b), "{a:?} ≠ {b:?}");
        }
    }
    for (f, want) in eq.forcing().iter().zip([zero, zero, t]) {
        assert!(f.equals(want));
    }
    // A = ∂c/∂q̇ and b = −(ċ with q̈ = 0); the row may come with either sign.
    let a = &eq.constraint_matrix()[0];
    let b = eq.constraint_rhs()[0];
    let want_a = [-th.sin(), th.cos(), zero];
    let want_b = thd * (xd * th.cos() + yd * th.sin());
    let sign = if a[1].equals(th.cos()) {
        Expr::one()
    } else {
        -Expr::one()
    };
    for (x, w) in a.iter().zip(want_a) {
        assert!(x.equals(sign * w), "{x:?}");
    }
    assert!(b.equals(sign * want_b), "{b:?}");
    // With a multiplier there is no explicit q̈ from M alone.
    assert!(eq.accelerations().is_none());
}

#[test]
fn workless_kept_constraints_keep_the_energy_integral() {
    // The Atwood machine keeps `rope` and `no_slip` with multipliers; both are A q̇ = 0, so
    // their reactions do no work and K + V is conserved. No coordinate is cyclic: each
    // appears in a constraint or in V.
    let system = model::lower(&load("examples/atwood-machine.lag")).expect("lowers");
    let eq = mechanics::derive(&system).expect("derives");
    assert!(!eq.constraint_names().is_empty());
    let kinds: Vec<&str> = eq.first_integrals().iter().map(|f| f.kind).collect();
    assert_eq!(kinds, ["energy"]);
    let h = eq.first_integrals()[0].value;
    assert!(h.equals(eq.kinetic_energy() + eq.potential_energy()));
    // The knife edge is steered by a couple T: its energy is conserved only while T = 0.
    let system = model::lower(&load("examples/knife-edge.lag")).expect("lowers");
    let eq = mechanics::derive(&system).expect("derives");
    let energy = eq
        .first_integrals()
        .iter()
        .find(|f| f.kind == "energy")
        .expect("a conditional energy integral");
    assert_eq!(energy.conditions, [Expr::symbol("T")]);
}

#[test]
fn integrals_that_hold_while_the_inputs_vanish_say_so() {
    // 7.3: φ1 is cyclic, but the couple C and the pull F act on it: p_φ1 is conserved while
    // Q_φ1 = C − F R1 = 0. An input-free system has no conditions (the double pendulum).
    let system = model::lower(&load("examples/seed/7.3-gears-pendulum.lag")).expect("lowers");
    let eq = mechanics::derive(&system).expect("derives");
    let momentum = eq
        .first_integrals()
        .iter()
        .find(|f| f.coordinate.as_deref() == Some("phi1"))
        .expect("p_phi1");
    let (c, f, r1) = (Expr::symbol("C"), Expr::symbol("F"), Expr::symbol("R1"));
    assert_eq!(momentum.conditions.len(), 1);
    assert!(momentum.conditions[0].equals(c - f * r1));
    // θ is not cyclic (spring, gravity), so it has no momentum integral.
    assert!(eq
        .first_integrals()
        .iter()
        .all(|f| f.coordinate.as_deref() != Some("theta")));
    // A damper's force depends on the state: no energy integral, not even a conditional one.
    let system = model::lower(&load("examples/damped-oscillator.lag")).expect("lowers");
    let eq = mechanics::derive(&system).expect("derives");
    assert!(eq.first_integrals().iter().all(|f| f.coordinate.is_some()));
    let system = model::lower(&load("examples/double-pendulum.lag")).expect("lowers");
    let eq = mechanics::derive(&system).expect("derives");
    assert!(eq.first_integrals().iter().all(|f| f.conditions.is_empty()));
    assert!(eq.first_integrals().iter().any(|f| f.kind == "energy"));
}
