//! Property tests of the symbolic core over random expressions: the normal form has the value
//! of its input, derivatives match central finite differences, and a normal form of zero only
//! happens for expressions that evaluate to zero.

use cas::{Expr, Symbol};
use proptest::prelude::*;

const NAMES: [&str; 3] = ["x", "y", "a"];

fn leaf() -> impl Strategy<Value = Expr> {
    prop_oneof![
        (-5i64..6).prop_map(Expr::int),
        (-7i64..8, 1i64..6).prop_map(|(p, q)| Expr::rational(p, q).unwrap()),
        (0usize..3).prop_map(|i| Expr::symbol(NAMES[i])),
        Just(Expr::coordinate("theta")),
        Just(Expr::rate("theta", 1)),
        Just(Expr::coordinate("phi")),
    ]
}

/// A symbol or a coordinate (numeric angles such as `sin(1)` are atoms of their own).
fn symbol() -> impl Strategy<Value = Expr> {
    prop_oneof![
        (0usize..3).prop_map(|i| Expr::symbol(NAMES[i])),
        Just(Expr::coordinate("theta")),
        Just(Expr::coordinate("phi")),
    ]
}

/// An angle as mechanics writes them: a small integer combination of angles and parameters,
/// possibly shifted by a rational multiple of π. (Trigonometry of long sums expands
/// exponentially in any expanded normal form, so arbitrary nesting is not the class to test.)
fn angle() -> impl Strategy<Value = Expr> {
    (-2i64..3, -1i64..2, -4i64..5).prop_map(|(i, j, p)| {
        let th = Expr::coordinate("theta");
        let ph = Expr::coordinate("phi");
        i * th + j * ph + Expr::pi() * Expr::rational(p, 4).unwrap()
    })
}

/// Random expressions built so that they are defined near the sample points (denominators and
/// logarithm arguments are kept away from zero by construction).
fn expression() -> impl Strategy<Value = Expr> {
    let base = prop_oneof![
        3 => leaf(),
        1 => angle().prop_map(|a| a.sin()),
        1 => angle().prop_map(|a| a.cos()),
        1 => (0usize..2).prop_map(|i| (Expr::coordinate(["theta", "phi"][i]) / 3).tan()),
    ];
    base.prop_recursive(3, 16, 2, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(|(a, b)| a + b),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| a - b),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| a * b),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| a / (b.powi(2) + 1)),
            (inner.clone(), 0i64..3).prop_map(|(a, k)| a.powi(k)),
            inner.clone().prop_map(|a| (a.powi(2) + 2).sqrt()),
            inner.clone().prop_map(|a| (a.powi(2) + 1).ln()),
            inner.clone().prop_map(|a| (a / 3).exp()),
            inner.clone().prop_map(|a| a.atan()),
            (angle(), angle()).prop_map(|(a, b)| (a + b).sin() - a.sin() * b.cos()),
            (inner, angle()).prop_map(|(a, b)| a * (2 * b).cos() + a * b.sin().powi(2)),
        ]
    })
}

fn point() -> impl Strategy<Value = [f64; 6]> {
    [
        0.3f64..1.3,
        0.3f64..1.3,
        0.3f64..1.3,
        -1.5f64..1.5,
        -1.0f64..1.0,
        -1.5f64..1.5,
    ]
}

fn env(p: &[f64; 6]) -> impl Fn(Symbol) -> Option<f64> + '_ {
    move |s: Symbol| {
        Some(match (s.name(), s.order()) {
            ("x", _) => p[0],
            ("y", _) => p[1],
            ("a", _) => p[2],
            ("theta", 0) => p[3],
            ("theta", 1) => p[4],
            ("phi", 0) => p[5],
            _ => return None,
        })
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-7 * (1.0 + a.abs().max(b.abs()))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn normal_form_has_the_value_of_its_input(e in expression(), p in point()) {
        let v = e.eval(&env(&p)).unwrap();
        prop_assume!(v.is_finite() && v.abs() < 1e6);
        let n = e.normal();
        let w = n.eval(&env(&p)).unwrap();
        prop_assert!(close(v, w), "{e:?}\n  = {v}\nnormal {n:?}\n  = {w}");
        // The normal form is a fixed point.
        prop_assert_eq!(n.normal(), n);
    }

    #[test]
    fn derivative_matches_central_differences(e in expression(), p in point(), which in 0usize..4) {
        let (sym, index) = match which {
            0 => (Expr::symbol("x"), 0),
            1 => (Expr::symbol("a"), 2),
            2 => (Expr::coordinate("theta"), 3),
            _ => (Expr::rate("theta", 1), 4),
        };
        let d = e.diff(sym.as_symbol().unwrap());
        let h = 1e-5;
        let mut plus = p;
        plus[index] += h;
        let mut minus = p;
        minus[index] -= h;
        let (Ok(fp), Ok(fm), Ok(f0)) = (e.eval(&env(&plus)), e.eval(&env(&minus)), e.eval(&env(&p))) else {
            return Err(TestCaseError::fail("evaluation failed"));
        };
        prop_assume!(fp.is_finite() && fm.is_finite() && f0.abs() < 1e4);
        let fd = (fp - fm) / (2.0 * h);
        let exact = d.eval(&env(&p)).unwrap();
        prop_assume!(exact.is_finite());
        prop_assert!((fd - exact).abs() <= 1e-4 * (1.0 + exact.abs()), "d/d{sym:?} {e:?}: fd {fd} exact {exact}");
    }

    #[test]
    fn zero_normal_form_means_zero_value(e in expression(), p in point()) {
        if e.is_zero() {
            let v = e.eval(&env(&p)).unwrap();
            prop_assert!(v.abs() < 1e-8 || !v.is_finite(), "{e:?} normalised to 0 but is {v}");
        }
        // e − e is always zero; e − e + 1 never is.
        prop_assert!((e - e).is_zero());
        let shifted = (e + 1) - e;
        prop_assert!(!(shifted - 2).is_zero());
    }

    #[test]
    fn equal_expressions_written_differently_have_one_normal_form(a in symbol(), b in symbol(), c in expression()) {
        // (a + b)² and a² + 2ab + b² are the same expression.
        let lhs = (a + b).powi(2);
        let rhs = a.powi(2) + 2 * a * b + b.powi(2);
        prop_assert_eq!(lhs.normal(), rhs.normal());
        // sin(a + b) and its expansion are equal (identical normal forms are only promised
        // for denominators small enough to rationalise, so compare by `equals`).
        prop_assert!((a + b).sin().equals(a.sin() * b.cos() + a.cos() * b.sin()));
        // Multiplying out by a random expression and dividing again gives it back.
        prop_assert_eq!(((a + b) * c / (a + b + 7)).normal(), (c * (b + a) / (7 + a + b)).normal());
    }
}

proptest! {
    // Each case takes five derivatives besides the gradient: fewer cases keep CI bounded.
    #![proptest_config(ProptestConfig::with_cases(40))]

    #[test]
    fn a_gradient_is_the_partial_derivatives_one_by_one(e in expression()) {
        let vars: Vec<Symbol> = [Expr::symbol("x"), Expr::symbol("a"), Expr::coordinate("theta"),
            Expr::rate("theta", 1), Expr::coordinate("phi")]
            .iter()
            .filter_map(|v| v.as_symbol())
            .collect();
        let form = e.normal_form();
        let gradient = form.gradient(&vars);
        prop_assert_eq!(gradient.len(), vars.len());
        for (part, &v) in gradient.iter().zip(&vars) {
            prop_assert_eq!(part.to_expr(), e.diff(v), "d/d{:?} of {:?}", v, e);
        }
    }
}
