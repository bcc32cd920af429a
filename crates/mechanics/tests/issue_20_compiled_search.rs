//! Issue 20: `solve` on `examples/spring-chain.lag` (three masses between four springs with
//! rest lengths) took 0.7 s of CPU, nearly all of it in the equilibrium search: the rest
//! equations hold `√((a + x1)²)`, so they are searched numerically, and the multistart Newton
//! evaluated the residuals and their Jacobian by walking expression trees with a hash-map
//! lookup per symbol, thousands of times. The search now compiles them once to a tape
//! (`numeric::Tape`) and falls back on the trees only where they do not compile; the run takes
//! 0.06 s. This checks the search still finds the equilibria, each a rest state when checked
//! on the trees, and only rest states.

use cas::Expr;
use mechanics::equilibria::{find_equilibria, rest_equations, Method, Values};
use mechanics::{derive, Load, Particle, System};

/// Masses on a line between walls at 0 and 3a, joined by springs of rest length `a`, written
/// with the springs' true lengths `√(d²)` as a model's `spring … length a` is.
fn spring_chain() -> System {
    let (m, k, a) = (Expr::symbol("m"), Expr::symbol("k"), Expr::symbol("a"));
    let mut system = System::new();
    let mut ends = vec![Expr::zero()];
    for (i, name) in ["x1", "x2"].iter().enumerate() {
        system.add_coordinate(name);
        let x = Expr::int(i as i64 + 1) * a + Expr::coordinate(name);
        system.add_particle(Particle {
            name: format!("P{}", i + 1),
            mass: m,
            position: [x, Expr::zero(), Expr::zero()],
        });
        ends.push(x);
    }
    ends.push(Expr::int(3) * a);
    for pair in ends.windows(2) {
        let d = pair[1] - pair[0];
        let stretch = (d * d).sqrt() - a;
        system.add_load(Load::Potential(
            Expr::rational(1, 2).unwrap() * k * stretch * stretch,
        ));
    }
    system
}

#[test]
fn the_compiled_search_finds_the_rest_states_of_springs_with_rest_lengths() {
    let equations = derive(&spring_chain()).unwrap();
    let rest = rest_equations(&equations).unwrap();
    assert!(
        rest.exact.is_none(),
        "the roots keep it from the exact solver"
    );
    let values: Values = [("m", 1.0), ("k", 100.0), ("a", 1.0)]
        .into_iter()
        .map(|(n, v)| (n.to_string(), v))
        .collect();
    let set = find_equilibria(&rest, &values, &[(-2.0, 2.0), (-2.0, 2.0)]).unwrap();
    assert_eq!(set.method, Method::MultistartNewton);
    assert!(
        set.equilibria
            .iter()
            .any(|e| e.values.iter().all(|v| v.abs() < 1e-9)),
        "the natural state x = 0: {:?}",
        set.equilibria
    );
    let env_at = |x: &[f64]| {
        let values = values.clone();
        let x = x.to_vec();
        move |s: cas::Symbol| match s.name() {
            "x1" => Some(x[0]),
            "x2" => Some(x[1]),
            name => values.get(name).copied(),
        }
    };
    for e in &set.equilibria {
        let env = env_at(&e.values);
        for r in &rest.residuals {
            let v = r.eval(&env).unwrap();
            assert!(v.abs() < 1e-7, "{:?} leaves {v}", e.values);
        }
    }
}
