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
