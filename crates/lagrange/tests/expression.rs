//! One expression on its own (`lagrange::expression`, what `lagrange simplify` and `lagrange
//! diff` print): coordinates read as functions of time, the normal form, derivatives by a
//! variable or by time, and each mistake a typed error of the user's kind.

use lagrange::expression::{diff, simplify};
use lagrange::{cas, Error, ErrorKind};

#[test]
fn simplify_and_diff_read_coordinates_and_refuse_what_is_no_variable() {
    let one = simplify("sin(x)^2 + cos(x)^2", &[]).unwrap();
    assert_eq!(cas::print::to_sympy(one), "1");
    let d = diff("theta^2", "t", &["theta".into()]).unwrap();
    assert_eq!(cas::print::to_sympy(d), "2*theta*theta_d");
    // `theta` is the coordinate of the expression, so ∂/∂θ of θ̇·θ is θ̇.
    let d = diff("theta_d*theta", "theta", &[]).unwrap();
    assert_eq!(cas::print::to_sympy(d), "theta_d");
    let e = diff("x*y", "2*x", &[]).unwrap_err();
    assert!(matches!(e, Error::NotAVariable { .. }), "{e}");
    assert_eq!(e.kind(), ErrorKind::Input);
    let e = simplify("2 +", &[]).unwrap_err();
    assert!(e.to_string().contains("column"), "{e}");
    assert_eq!(e.kind(), ErrorKind::Input);
}
