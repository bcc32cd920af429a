//! The n-link pendulum's equations, derived with the core, equal their closed form exactly
//! (normal-form equality) for n up to 10, and numerically at a random state.

mod common;

use cas::Expr;
use common::nlink::NLink;

#[test]
fn nlink_equations_equal_the_closed_form() {
    for n in [1, 2, 3, 5, 10] {
        let system = NLink::new(n);
        let (mass, forcing) = system.equations();
        let (mass_ref, forcing_ref) = system.closed_form();
        for i in 0..n {
            for j in 0..n {
                assert_eq!(mass[i][j], mass_ref[i][j].normal(), "n = {n}: M[{i}][{j}]");
            }
            assert_eq!(forcing[i], forcing_ref[i].normal(), "n = {n}: f[{i}]");
        }
    }
}

#[test]
fn working_forms_give_the_same_equations_as_expression_operations() {
    for n in [1, 2, 4, 6] {
        let system = NLink::with_prefix(n, "working_");
        // Working forms first, so that their trees are not memoised results of the other route.
        let on_forms = system.equations_on_working_forms();
        assert_eq!(on_forms, system.equations(), "n = {n}");
    }
}

#[test]
fn nlink_equations_evaluate_like_the_closed_form() {
    let n = 4;
    let system = NLink::new(n);
    let (mass, forcing) = system.equations();
    let (mass_ref, forcing_ref) = system.closed_form();
    // A fixed pseudo-random state: every symbol gets a value from its name.
    let env = |s: cas::Symbol| {
        let h = s.name().bytes().fold(s.order() as u64 + 7, |h, b| {
            h.wrapping_mul(31).wrapping_add(b as u64)
        });
        Some(0.3 + (h % 997) as f64 / 997.0)
    };
    for i in 0..n {
        for j in 0..n {
            let (a, b) = (
                mass[i][j].eval(&env).unwrap(),
                mass_ref[i][j].eval(&env).unwrap(),
            );
            assert!(
                (a - b).abs() < 1e-12 * (1.0 + b.abs()),
                "M[{i}][{j}]: {a} vs {b}"
            );
        }
        let (a, b) = (
            forcing[i].eval(&env).unwrap(),
            forcing_ref[i].eval(&env).unwrap(),
        );
        assert!(
            (a - b).abs() < 1e-12 * (1.0 + b.abs()),
            "f[{i}]: {a} vs {b}"
        );
    }
}

#[test]
fn a_lagrangians_gradient_is_its_partial_derivatives() {
    // The gradient reads the terms once for all coordinates (or rates); each part must be the
    // partial derivative taken on its own, exactly.
    for n in [2, 5] {
        let system = NLink::with_prefix(n, "gradient_");
        let (kinetic, potential) = system.energies();
        let lagrangian = (kinetic - potential).normal();
        let symbols_of =
            |v: &[Expr]| -> Vec<cas::Symbol> { v.iter().filter_map(|e| e.as_symbol()).collect() };
        for symbols in [symbols_of(&system.angles), symbols_of(&system.rates)] {
            assert_eq!(symbols.len(), n);
            let gradient = lagrangian.normal_form().gradient(&symbols);
            for (part, &s) in gradient.iter().zip(&symbols) {
                assert_eq!(part.to_expr(), lagrangian.diff(s), "n = {n}: ∂L/∂{s:?}");
            }
        }
    }
}
