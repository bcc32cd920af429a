//! Issue 14: `sin(n x)` and `cos(n x)` were expanded into polynomials of degree `n` in `sin x`,
//! `cos x`. The expansion's coefficients grow like `2^(n−1)`, so it evaluated with a
//! cancellation error near `2^n ε` (a particle in the potential `1 − cos 60x` never moved), and
//! building it cost work growing with `n` (`sin(1000000 x)` never finished). Multiples above a
//! documented bound (12, docs/cas.md) are now angles of their own, with the derivative rule
//! `d sin(n x) = n cos(n x) dx`; smaller ones still expand, so their identities stay exact.
//!
//! The text printer also printed a wrong coefficient for large polynomials in `cos`: rewriting
//! `cos^(2j)` as `(1 − sin²)^j` computed the binomials in `i64`, which wrapped from `j = 67` on
//! (a `cos 150x` potential printed V = 6e45 at x = 0.3, where the value is 0.47).

use cas::print::compact;
use cas::{Expr, Symbol, SymbolKind};

fn x() -> Expr {
    Expr::coordinate("x")
}

fn at(e: Expr, value: f64) -> f64 {
    let env =
        |s: Symbol| (s == Symbol::new("x", SymbolKind::TimeFunction { order: 0 })).then_some(value);
    e.eval(&env).expect("evaluates")
}

#[test]
fn a_huge_multiple_is_an_angle_of_its_own() {
    let e = (1_000_000 * x()).sin();
    let n = e.normal();
    assert!((at(n, 0.3) - (300_000.0f64).sin()).abs() < 1e-12);
    let d = e.diff(Symbol::new("x", SymbolKind::TimeFunction { order: 0 }));
    assert!(d.equals(1_000_000 * (1_000_000 * x()).cos()));
    // Parity and the Pythagorean identity still hold for it.
    assert!(((-1_000_000 * x()).sin() + e).is_zero());
    assert!((e.powi(2) + (1_000_000 * x()).cos().powi(2) - 1).is_zero());
}

#[test]
fn large_multiples_evaluate_to_their_value_at_every_n() {
    for n in [13i64, 50, 60, 150, 1000, 12345] {
        let potential = 1 - (n * x()).cos();
        let normal = potential.normal();
        let force = potential.diff(Symbol::new("x", SymbolKind::TimeFunction { order: 0 }));
        for k in 1..20 {
            let v = k as f64 * 0.137;
            let want = 1.0 - (n as f64 * v).cos();
            assert!((at(normal, v) - want).abs() < 1e-9, "n = {n}, x = {v}");
            let want_force = n as f64 * (n as f64 * v).sin();
            assert!(
                (at(force, v) - want_force).abs() < 1e-9 * n as f64,
                "n = {n}, x = {v}"
            );
        }
    }
}

#[test]
fn small_multiples_still_expand_exactly() {
    let a = x();
    assert!(((12 * a).sin() - 2 * (6 * a).sin() * (6 * a).cos()).is_zero());
    assert!(((3 * a).sin() - (3 * a.sin() - 4 * a.sin().powi(3))).is_zero());
    assert!(((Expr::rational(5, 2).unwrap() * a).cos()
        - (Expr::rational(5, 2).unwrap() * a).cos().normal())
    .is_zero());
    // Beyond the bound the expansion is not promised, but the value is the same.
    let e = (13 * a).sin() - (2 * (13 * a / 2).sin() * (13 * a / 2).cos());
    assert!(at(e.normal(), 0.7).abs() < 1e-12);
}

#[test]
fn the_compact_form_keeps_the_value_of_high_powers_of_cos() {
    // cos^(2j) rewritten with sin² = 1 − cos² needs binomials C(j, i) beyond i64.
    let c = x().cos();
    for e in [
        (1 - c.powi(2)).powi(75),
        (1 - c.powi(2)).powi(75) + c.powi(3),
        1 - (150 * x()).cos(),
    ] {
        let n = e.normal();
        let compacted = compact(n);
        for v in [0.3, 1.1, 2.0] {
            let (want, got) = (at(e, v), at(compacted, v));
            assert!(
                (got - want).abs() <= 1e-9 * want.abs().max(1.0),
                "{got} vs {want}"
            );
        }
    }
}
