//! Issue 15: the seed 7.1/7.2 reactions and solved accelerations repeated one long denominator
//! (`ℓ (m_B sin² θ + m_A)`) under every term and every equation, 20–40 lines a reaction. The
//! report now names a long sum that the denominators of a display share (`Δ = m_B sin² θ +
//! m_A`), defines it once before its first use, and writes `…/(ℓ Δ)`. These tests check that
//! the named forms are shorter and that substituting the definitions back gives the same
//! expressions, exactly (normal forms) and in numbers at random points.

use std::path::Path;

use cas::{Expr, Symbol};
use lagrange::Analysis;
use report::document::Notation;

fn seed(name: &str) -> Analysis {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/seed")
        .join(name);
    Analysis::from_file(&path).expect("the seed model checks")
}

/// A value in [0.5, 2.5) for each symbol, from its name and `seed` (no zero denominators).
fn point(seed: u64) -> impl Fn(Symbol) -> Option<f64> {
    move |s: Symbol| {
        let mut h = seed ^ 0x9e37_79b9_7f4a_7c15;
        for b in s.name().bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
        Some(0.5 + 2.0 * ((h >> 11) as f64 / (1u64 << 53) as f64))
    }
}

fn printed(exprs: &[Expr], notation: &Notation) -> usize {
    exprs
        .iter()
        .map(|e| notation.math(*e).unicode.chars().count())
        .sum()
}

/// Names the shared sums of `exprs` and checks the named forms: shorter when `shorter` (a sum
/// under one expression only is named to break a long display, which costs its definition),
/// and equal to the originals once the definitions are put back.
fn check_named(exprs: &[Expr], notation: &Notation, shorter: bool) {
    let before = printed(exprs, notation);
    let named = notation.name_shared(exprs);
    assert!(!named.used.is_empty(), "nothing named");
    let definitions: usize = named
        .definitions
        .iter()
        .map(|d| d.rhs.unicode.chars().count() + 4)
        .sum();
    let after = printed(&named.exprs, notation) + definitions;
    assert!(
        !shorter || after < before,
        "{after} glyphs named, {before} before"
    );
    for (original, rewritten) in exprs.iter().zip(&named.exprs) {
        let back = rewritten.subs(&named.used);
        assert!(back.equals(*original), "{back} ≠ {original}");
        for seed in 1..=5 {
            let (a, b) = (original.eval(&point(seed)), back.eval(&point(seed)));
            let (Ok(a), Ok(b)) = (a, b) else {
                panic!("not evaluable at point {seed}");
            };
            assert!((a - b).abs() <= 1e-9 * (1.0 + a.abs()), "{a} vs {b}");
        }
    }
}

#[test]
fn the_cart_pendulum_names_its_denominator_once() {
    let analysis = seed("7.1-cart-pendulum.lag");
    let notation = Notation::of(analysis.system());
    let equations = analysis.equations().expect("equations");
    let accelerations = report::accelerations::for_report(equations).expect("accelerations");
    check_named(&accelerations, &notation, true);
    let reactions = analysis
        .reactions()
        .expect("reactions")
        .expect("the model asks for reactions");
    for r in &reactions.reactions {
        let mut exprs: Vec<Expr> = r.force.iter().flatten().copied().collect();
        exprs.extend(r.along.iter().map(|(n, _)| *n));
        check_named(&exprs, &notation, true);
    }

    let text = analysis
        .solution(None)
        .expect("solution")
        .document
        .to_text();
    assert_eq!(
        text.matches("  Δ = m_B sin² θ + m_A\n").count(),
        1,
        "{text}"
    );
    assert!(text.contains("/(ℓ Δ)"), "{text}");
    assert!(!text.contains("(m_B sin² θ + m_A))"), "{text}");
    // Defined before its first use.
    let defined = text.find("Δ = ").unwrap_or(usize::MAX);
    let used = text.find("/(ℓ Δ)").unwrap_or(0);
    assert!(defined < used, "{text}");
}

#[test]
fn the_rolling_cone_names_its_denominators() {
    let analysis = seed("7.2-rolling-cone.lag");
    let notation = Notation::of(analysis.system());
    let equations = analysis.equations().expect("equations");
    let accelerations = report::accelerations::for_report(equations).expect("accelerations");
    check_named(&accelerations, &notation, false);
    let reactions = analysis
        .reactions()
        .expect("reactions")
        .expect("the model asks for reactions");
    for r in &reactions.reactions {
        let force: Vec<Expr> = r.force.iter().flatten().copied().collect();
        check_named(&force, &notation, true);
    }
    let solution = analysis.solution(None).expect("solution");
    let text = solution.document.to_text();
    assert_eq!(text.matches("\n  Δ = ").count(), 1, "{text}");
    for out in [
        solution.document.to_markdown(),
        solution.document.to_latex(),
    ] {
        assert_eq!(out.matches("\\Delta &= ").count(), 1, "{out}");
        assert!(out.contains("}{\\Delta}"), "{out}");
    }
}

#[test]
fn a_name_never_takes_a_model_symbol() {
    let analysis = seed("7.1-cart-pendulum.lag");
    let notation = Notation::of(analysis.system());
    let equations = analysis.equations().expect("equations");
    let accelerations = report::accelerations::for_report(equations).expect("accelerations");
    // Δ is taken by an expression of the display: the name is Δ2.
    let with_delta: Vec<Expr> = accelerations
        .iter()
        .map(|a| *a + Expr::symbol("Delta") - Expr::symbol("Delta"))
        .chain([Expr::symbol("Delta")])
        .collect();
    let named = notation.name_shared(&with_delta);
    assert_eq!(named.used.len(), 1);
    assert_eq!(named.used[0].0, Expr::symbol("Delta2"));
}
