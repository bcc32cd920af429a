//! Issue 23: a decimal written in a model (`point P = 0.7*B.y`, `rotated th + 0.3`,
//! `spring 2e0 on x`) was a float inside the symbolic core: the mass matrix came out as
//! `0.48999999999999994*m + (1.0*m*cos(th)**2 - 1.0*m*cos(th)**2)`, the accelerations as NaN,
//! and the energy integral was lost. The cause: `cas::Number::parse_literal` read a literal
//! with a point or an exponent as an `f64`. The fix: every literal is its exact rational
//! (`0.7` = 7/10, `9.81` = 981/100, `1e-3` = 1/1000), so the derivation is exact; numbers a
//! double cannot hold (`1e-320`, `1e400`) are errors at the literal, and so are values that
//! divide by zero, overflow or underflow.

use cas::{Expr, Number};

fn derive(source: &str) -> mechanics::Equations {
    let model = model::load(source).unwrap_or_else(|d| panic!("{d}"));
    let system = model::lower(&model).expect("lowers");
    mechanics::derive(&system).expect("derives")
}

fn q(n: i64, d: i64) -> Expr {
    Expr::rational(n, d).unwrap()
}

/// No float anywhere in `e`.
fn exact(e: Expr) -> bool {
    let mut stack = vec![e];
    while let Some(x) = stack.pop() {
        if x.as_number().is_some_and(Number::is_float) {
            return false;
        }
        stack.extend_from_slice(x.children());
    }
    true
}

fn has_energy_integral(eq: &mechanics::Equations) -> bool {
    eq.first_integrals().iter().any(|i| i.kind == "energy")
}

const PENDULUM: &str = "coordinates th
parameters m = 1, g = 9.81
frame N
frame B = N rotated th about z
point P = 0.7*B.y
particle P mass m
gravity -g*N.y
";

#[test]
fn a_decimal_length_gives_an_exact_mass_matrix_and_the_energy_integral() {
    let eq = derive(PENDULUM);
    let (m, g, th) = (Expr::symbol("m"), Expr::symbol("g"), Expr::coordinate("th"));
    let mass = eq.mass_matrix()[0][0];
    assert_eq!(mass.normal(), (q(49, 100) * m).normal());
    assert!(exact(mass) && exact(eq.forcing()[0]));
    // P = 0.7 (−sin θ, cos θ): V = m g 0.7 cos θ, f = 0.7 m g sin θ.
    assert!(eq.forcing()[0].equals(q(7, 10) * m * g * th.sin()));
    let acc = eq.accelerations().expect("explicit accelerations")[0];
    assert!(acc.equals(q(10, 7) * g * th.sin()));
    assert!(exact(acc));
    // By numbers, at θ = 0.4 with m = 1, g = 9.81.
    let value = acc
        .eval(&|s| match s.name() {
            "th" => Some(0.4),
            "g" => Some(9.81),
            _ => Some(1.0),
        })
        .unwrap();
    assert!((value - 9.81 / 0.7 * 0.4_f64.sin()).abs() < 1e-12);
    assert!(has_energy_integral(&eq));
}

#[test]
fn a_decimal_angle_offset_is_exact() {
    let eq = derive(&PENDULUM.replace("rotated th about z", "rotated th + 0.3 about z"));
    let th = Expr::coordinate("th");
    let mass = eq.mass_matrix()[0][0];
    assert_eq!(mass.normal(), (q(49, 100) * Expr::symbol("m")).normal());
    assert!(exact(eq.forcing()[0]));
    let angle = th + q(3, 10);
    let f = q(7, 10) * Expr::symbol("m") * Expr::symbol("g") * angle.sin();
    assert!(eq.forcing()[0].equals(f));
    assert!(has_energy_integral(&eq));
}

#[test]
fn a_spring_constant_written_with_an_exponent_is_an_integer() {
    let eq = derive(
        "coordinates x
parameters m = 1
frame N
point P = x*N.x
particle P mass m
spring 2e0 on x
",
    );
    let x = Expr::coordinate("x");
    assert_eq!(eq.potential_energy().normal(), x.powi(2).normal());
    assert!(has_energy_integral(&eq));
}

#[test]
fn a_constant_decimal_rotation_derives_exactly() {
    let eq = derive(
        "coordinates th, x
parameters m = 1
frame N
frame B = N rotated th about z
frame D = B rotated 1.39 about z
point P = B.y + x*D.x
particle P mass m
",
    );
    assert!(eq.mass_matrix().iter().flatten().all(|e| exact(*e)));
    assert!(eq.forcing().iter().all(|e| exact(*e)));
    // P = B.y + x D.x: M₂₂ = m, M₁₂ = m (∂P/∂θ · ∂P/∂x) = −m cos(139/100), the angle exact.
    let m = Expr::symbol("m");
    assert!(eq.mass_matrix()[1][1].equals(m));
    assert!(eq.mass_matrix()[0][1].equals(-(m * q(139, 100).cos())));
}

fn first_error(source: &str) -> model::Diagnostic {
    let diagnostics = model::load(source).expect_err("an error").0;
    diagnostics
        .into_iter()
        .find(model::Diagnostic::is_error)
        .expect("an error")
}

#[test]
fn numbers_a_double_cannot_hold_are_errors_at_the_literal() {
    for (literal, code) in [
        ("1e-320", "E009"),
        ("4.9e-324", "E009"),
        ("1e-400", "E009"),
        ("1e400", "E006"),
        ("1e1000000000", "E006"),
    ] {
        let source = format!("coordinates x\nparameters m = 1, g = {literal}\nframe N\npoint P = x*N.x\nparticle P mass m\ngravity -g*N.y\n");
        let d = first_error(&source);
        assert_eq!(d.kind.code(), code, "{literal}");
        let at = source.find(literal).unwrap();
        assert_eq!(d.span.start, at, "{literal}");
    }
    // Zero itself, however written, is fine.
    assert!(model::load("coordinates x\nparameters m = 1, k = 0e-500\nframe N\npoint P = x*N.x\nparticle P mass m\nspring k on x\n").is_ok());
}

#[test]
fn values_that_divide_by_zero_overflow_or_underflow_are_errors_where_they_happen() {
    for (value, bad) in [
        ("1/0", "1/0"),
        ("0/0", "0/0"),
        ("2*(1/(1 - 1))", "(1/(1 - 1))"),
        ("1e200*1e200", "1e200*1e200"),
        ("1e-200*1e-200", "1e-200*1e-200"),
        ("exp(-1000)", "exp(-1000)"),
        ("sqrt(-1)", "sqrt(-1)"),
    ] {
        let source = format!("coordinates x\nparameters m = 1, k = {value}\nframe N\npoint P = x*N.x\nparticle P mass m\nspring k on x\n");
        let d = first_error(&source);
        assert_eq!(d.kind.code(), "E403", "{value}: {d}");
        let at = source.find(bad).unwrap();
        assert_eq!((d.span.start, d.span.end), (at, at + bad.len()), "{value}");
    }
}

#[test]
fn masses_too_small_to_compute_with_are_errors() {
    let d = first_error("coordinates x\nframe N\npoint P = x*N.x\nparticle P mass 1e-300*1e-10\n");
    assert_eq!(d.kind.code(), "E311");
}

#[test]
fn overrides_that_make_values_unusable_are_refused() {
    let model = model::load(
        "coordinates x\nparameters m = 2, l = 1, I = m*l^2\nframe N\npoint P = x*N.x\nparticle P mass m\nspring I on x\n",
    )
    .unwrap();
    let set = |name: &str, v: f64| model.with_overrides(&[(name.to_owned(), v)]);
    assert!(matches!(
        set("m", 4.9e-324),
        Err(model::OverrideError::TooSmall { .. })
    ));
    assert!(matches!(
        set("m", 0.0),
        Err(model::OverrideError::UnusableValue { .. })
    ));
    assert!(matches!(
        set("l", 1e200),
        Err(model::OverrideError::UnusableValue { reason, .. }) if reason.contains("overflows")
    ));
    assert!(set("m", 0.7).is_ok());
}
