//! Issue 14: with `g = 1e308` the linearization of the inverted cart–pendulum never ended (the
//! state matrix overflows to infinity and the eigenvalue iteration had no end). It is now a
//! typed error, returned at once; with a large but representable `g` the answer is right.

use mechanics::equilibria::{find_equilibria, rest_equations, Values};
use mechanics::linearize::{linear_model, linearize_at, LinearizeError};
use mechanics::{canonical, derive};
use numeric::eigen::EigenError;

fn values(g: f64) -> Values {
    [
        ("m_A", 2.0),
        ("m_B", 1.0),
        ("l", 0.5),
        ("k", 30.0),
        ("g", g),
        ("F", 0.0),
        ("C", 0.0),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect()
}

#[test]
fn an_overflowing_state_matrix_is_an_error() {
    let eq = derive(&canonical::cart_pendulum()).unwrap();
    let rest = rest_equations(&eq).unwrap();
    let model = linear_model(&eq, &rest, &["F".into(), "C".into()]);
    let values = values(1e308);
    let set = find_equilibria(&rest, &values, &[]).unwrap();
    // Hanging and inverted.
    assert_eq!(set.equilibria.len(), 2);
    for e in &set.equilibria {
        let result = linearize_at(&model, &rest, &e.values, e.exact.as_deref(), &values);
        assert!(
            matches!(
                result,
                Err(LinearizeError::Eigen(EigenError::NonFinite { .. }))
            ),
            "{:?}",
            result.map(|l| l.eigenvalues)
        );
    }
}

#[test]
fn a_large_representable_gravity_is_linearized() {
    let eq = derive(&canonical::cart_pendulum()).unwrap();
    let rest = rest_equations(&eq).unwrap();
    let model = linear_model(&eq, &rest, &["F".into(), "C".into()]);
    let values = values(1e200);
    let set = find_equilibria(&rest, &values, &[]).unwrap();
    for e in &set.equilibria {
        let l = linearize_at(&model, &rest, &e.values, e.exact.as_deref(), &values).unwrap();
        assert!(l
            .eigenvalues
            .iter()
            .all(|(re, im)| re.is_finite() && im.is_finite()));
    }
}
