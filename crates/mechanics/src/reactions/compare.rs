//! Whether the two methods agree: by exact normal-form equality, or by values at a few
//! pseudo-random states.

use cas::{Expr, Symbol};

use super::Agreement;

/// Above this many terms the exact comparison is skipped for the numeric one: the normal form
/// of a difference of two large rational functions costs far more than five evaluations.
const EXACT_TERMS: usize = 4000;

/// Whether `a` and `b` agree: exactly, or at a few pseudo-random points.
pub(super) fn compare(a: Expr, b: Expr) -> Agreement {
    if a.term_count() + b.term_count() <= EXACT_TERMS && (a - b).normal().is_zero() {
        return Agreement::Exact;
    }
    let agree = (0..5u64).all(|round| {
        let env = |s: Symbol| Some(sample(s, round));
        match (a.eval(&env), b.eval(&env)) {
            (Ok(x), Ok(y)) => (x - y).abs() <= 1e-9 * (1.0 + x.abs().max(y.abs())),
            _ => false,
        }
    });
    if agree {
        Agreement::Numeric
    } else {
        Agreement::Disagree
    }
}

/// A value in `[0.35, 1.65]` drawn from a symbol's name, order and a round number.
pub(super) fn sample(s: Symbol, round: u64) -> f64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325 ^ round.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    for b in s.name().bytes().chain([s.order()]) {
        h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
    }
    0.35 + 1.3 * ((h >> 11) as f64 / (1u64 << 53) as f64)
}

pub(super) fn worst(a: Agreement, b: Agreement) -> Agreement {
    let rank = |x: Agreement| match x {
        Agreement::Exact => 0,
        Agreement::Numeric => 1,
        Agreement::Single => 2,
        Agreement::Unattributed => 3,
        Agreement::Disagree => 4,
    };
    if rank(a) >= rank(b) {
        a
    } else {
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comparison_is_exact_then_numeric_then_a_disagreement() {
        let x = Expr::coordinate("x");
        let one = x.sin().powi(2) + x.cos().powi(2);
        assert_eq!(compare(one, Expr::one()), Agreement::Exact);
        // √(x²) is not reduced to x by the normal form, but the two agree for x > 0, where
        // the random states are drawn.
        let root = x.powi(2).sqrt();
        if !(root - x).normal().is_zero() {
            assert_eq!(compare(root, x), Agreement::Numeric);
        }
        assert_eq!(compare(x, x + Expr::one()), Agreement::Disagree);
    }
}
