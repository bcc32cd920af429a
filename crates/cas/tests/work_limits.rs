//! Issue 14: the symbolic core had no work limits — `sin(a + b + … + w)` with 21 terms used
//! 2.3 GB, `sin(x)^100000` ran for minutes. A conversion to normal form now stops at a limit
//! on terms or degree with a typed error that says which limit and how to raise it, and the
//! infallible `normal` returns its input unchanged (equal, not canonical).
//!
//! The limits are process-wide, so every check that changes them lives in this one test.

use cas::{set_work_limits, work_limits, Expr, WorkLimitError, WorkLimits};

fn long_angle(terms: usize) -> Expr {
    Expr::add_all((0..terms).map(|i| Expr::coordinate(&format!("q{i}"))))
}

#[test]
fn work_limits_stop_expansion_with_a_typed_error_and_can_be_raised() {
    assert_eq!(work_limits(), WorkLimits::default());

    // 2²¹ products in the expansion of a 21-term angle.
    let e = long_angle(21).sin();
    let err = e.try_normal().expect_err("past the default term limit");
    assert_eq!(err, WorkLimitError::Terms { limit: 500_000 });
    assert!(err.to_string().contains("max_terms"), "{err}");
    // The infallible form keeps its input: same value, no expansion.
    assert_eq!(e.normal(), e);

    // A power whose degree is past the limit.
    let x = Expr::coordinate("x");
    let err = x
        .sin()
        .powi(100_000)
        .try_normal()
        .expect_err("past the degree limit");
    assert!(
        matches!(
            err,
            WorkLimitError::Degree {
                degree: 100_000,
                limit: 10_000
            }
        ),
        "{err:?}"
    );
    assert!((1 + x).powi(20_000).try_normal().is_err());

    // Below the limits nothing changes, and limits are per conversion, not cumulative.
    let small = long_angle(6).sin();
    assert!(small.try_normal().is_ok());
    assert!((small.powi(2) + long_angle(6).cos().powi(2) - 1).try_is_zero() == Ok(true));

    // Lower limits make a smaller expansion fail; raising them again lets it finish.
    set_work_limits(WorkLimits::default().with_max_terms(16));
    let nine = long_angle(9).sin();
    assert_eq!(nine.try_normal(), Err(WorkLimitError::Terms { limit: 16 }));
    assert_eq!(nine.normal(), nine);
    assert_eq!(nine.try_is_zero(), Err(WorkLimitError::Terms { limit: 16 }));
    assert!(!nine.is_zero());
    set_work_limits(WorkLimits::default().with_max_degree(5));
    assert!(matches!(
        (1 + x).powi(6).try_normal(),
        Err(WorkLimitError::Degree {
            degree: 6,
            limit: 5
        })
    ));
    set_work_limits(WorkLimits::default());
    let n = nine.try_normal().expect("within the default limits");
    assert!((n - nine).try_is_zero() == Ok(true));
}
