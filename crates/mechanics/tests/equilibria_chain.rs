//! Issue 14: `equilibria` on a planar pendulum chain of 9 or more links found nothing, not even
//! the hanging position. The rest equations of a chain are decoupled (`sin θ_j = 0` each): the
//! exact solver stopped at a fixed depth of 8 unknowns, and the numeric fallback put every
//! Newton start at ±π/2, where the Jacobian of `sin` vanishes, and for ten links or more ran
//! 2ⁿ starts.

use cas::Expr;
use mechanics::equilibria::{find_equilibria, rest_equations, Method, Values};
use mechanics::{derive, Load, Particle, System};

/// A planar chain of `n` point masses `m` on massless rods `l`, angles from the downward
/// vertical.
fn chain(n: usize) -> System {
    let (m, l, g) = (Expr::symbol("m"), Expr::symbol("l"), Expr::symbol("g"));
    let mut system = System::new();
    let (mut x, mut y) = (Expr::zero(), Expr::zero());
    for k in 1..=n {
        let name = format!("th{k}");
        system.add_coordinate(&name);
        let th = Expr::coordinate(&name);
        x += l * th.sin();
        y -= l * th.cos();
        system.add_particle(Particle {
            name: format!("P{k}"),
            mass: m,
            position: [x, y, Expr::zero()],
        });
    }
    system.add_load(Load::Gravity([Expr::zero(), -g, Expr::zero()]));
    system
}

fn values() -> Values {
    [("m", 1.0), ("l", 1.0), ("g", 9.81)]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect()
}

#[test]
fn a_nine_link_chain_has_all_its_equilibria_exactly() {
    let eq = derive(&chain(9)).unwrap();
    let rest = rest_equations(&eq).unwrap();
    let set = find_equilibria(&rest, &values(), &[]).unwrap();
    assert_eq!(set.method, Method::Exact);
    // Every link hanging down or standing up: 2⁹.
    assert_eq!(set.equilibria.len(), 512);
    assert!(set
        .equilibria
        .iter()
        .any(|e| e.values.iter().all(|v| *v == 0.0)));
    for e in &set.equilibria {
        for v in &e.values {
            assert!(v.abs() < 1e-12 || (v.abs() - std::f64::consts::PI).abs() < 1e-12);
        }
    }
}

#[test]
fn a_long_chain_is_searched_numerically_in_bounded_time() {
    // 2¹⁴ equilibria are more than are listed exactly: Newton from a bounded set of starts.
    let eq = derive(&chain(14)).unwrap();
    let rest = rest_equations(&eq).unwrap();
    assert!(rest.exact.is_none());
    let set = find_equilibria(&rest, &values(), &[]).unwrap();
    assert_eq!(set.method, Method::MultistartNewton);
    assert!(!set.equilibria.is_empty());
    for e in &set.equilibria {
        for v in &e.values {
            assert!(v.abs() < 1e-9 || (v.abs() - std::f64::consts::PI).abs() < 1e-9);
        }
    }
}
