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
    assert_eq!(err, WorkLimitError::Terms { limit: 100_000 });
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
                limit: 2_000
            }
        ),
        "{err:?}"
    );
    assert!((1 + x).powi(20_000).try_normal().is_err());
    // A million products of 300-digit coefficients: the total work stops it before any size
    // limit (the product has only 1 999 terms).
    let w = Expr::symbol("w");
    assert_eq!(
        ((1 + w).powi(999) * (2 + w).powi(999)).try_normal(),
        Err(WorkLimitError::Work { limit: 50_000_000 })
    );

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

    // A scope around several conversions fails when one inside hit a limit, even when the
    // code inside ignored it (an infallible `normal`), and shares one budget of work.
    set_work_limits(WorkLimits::default().with_max_terms(16));
    let ten = long_angle(10).sin();
    let inside = cas::limited(|| {
        let ignored = ten.normal();
        (ignored == ten, long_angle(2).sin().normal() == ten)
    });
    assert_eq!(inside, Err(WorkLimitError::Terms { limit: 16 }));
    assert_eq!(cas::limit_hit(), None, "the scope is over");
    // `with_work_limits` chooses limits for the scopes inside it, on this thread only.
    let raised = cas::with_work_limits(WorkLimits::default(), || {
        ten.try_normal().map(|r| (r - ten).is_zero())
    });
    assert_eq!(raised, Ok(true));
    set_work_limits(WorkLimits::default());
    let budget = WorkLimits::default().with_max_work(1_000);
    let spent = cas::with_work_limits(budget, || {
        cas::limited(|| long_angle(7).sin().normal() == long_angle(8).cos().normal())
    });
    assert_eq!(spent, Err(WorkLimitError::Work { limit: 1_000 }));
    assert_eq!(
        WorkLimits::default().scaled(10.0),
        WorkLimits::default()
            .with_max_terms(1_000_000)
            .with_max_degree(20_000)
            .with_max_work(500_000_000)
    );
}

/// Powers of a binomial and of `sin` are expanded term by term (`C(k, i)`), not by squaring
/// sums: `sin(x)^2000` took 12 s of products of 600-digit coefficients, `sin(x)^10000` minutes.
/// The result is the same polynomial, checked exactly and by numbers.
#[test]
fn binomial_powers_are_exact_and_fast() {
    let x = Expr::coordinate("bx");
    let y = Expr::symbol("by");
    for k in [3, 7, 20] {
        let direct = (2 * x + 3 * y).powi(k).normal();
        let by_products = (0..k)
            .fold(Expr::one(), |acc, _| (acc * (2 * x + 3 * y)).normal())
            .normal();
        assert_eq!(direct, by_products, "k = {k}");
        let sines = x.sin().powi(k).normal();
        let sine_products = (0..k).fold(Expr::one(), |acc, _| (acc * x.sin()).normal());
        assert_eq!(sines, sine_products, "k = {k}");
    }
    // Two independent ways: the binomial rule, and a product of two binomial powers.
    let half = x.sin().powi(200).normal();
    assert_eq!(x.sin().powi(400).normal(), (half * half).normal());
    let s = x.sin().powi(20).normal();
    let at = |e: Expr, v: f64| {
        e.eval(&|sym| (sym.name() == "bx").then_some(v))
            .expect("a number")
    };
    for v in [0.3_f64, 1.2, 2.9] {
        let exact = v.sin().powi(20);
        assert!((at(s, v) - exact).abs() <= 1e-12, "{v}");
    }
    assert!(x.sin().powi(2000).try_normal().is_ok());
}
