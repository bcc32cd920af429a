//! Equilibria, stability and linearization against closed forms: the bead on a rotating hoop
//! (bifurcation at Ω² R = g), a spring chain's frequencies, the seed's 7.1 cart pendulum
//! (characteristic polynomial) and 7.4 inverted pendulum (unstable upright, controllable),
//! completeness of the numerical search against a dense scan, and the linear response against
//! a small nonlinear RK4 simulation.

use lagrange::cas::{Expr, Symbol};
use lagrange::mechanics::equilibria::{
    find_equilibria, rest_equations, EquilibriumSet, Method, RestEquations, Values,
};
use lagrange::mechanics::linearize::{
    linear_model, linearize_at, Criterion, LinearModel, Linearized,
};
use lagrange::mechanics::Equations;
use lagrange::{mechanics, model};

struct Loaded {
    equations: Equations,
    rest: RestEquations,
    model: LinearModel,
    values: Values,
}

fn load_source(source: &str) -> Loaded {
    let model = model::load(source).expect("model loads");
    let system = model::lower(&model).expect("lowers");
    let equations = mechanics::derive(&system).expect("derives");
    let rest = rest_equations(&equations).expect("rest equations");
    let mut values = Values::new();
    for (name, value) in system.parameters().iter().chain(system.inputs()) {
        let v = match value {
            Some(e) => e
                .eval(&|s: Symbol| values.get(s.name()).copied())
                .expect("value"),
            None => 0.0,
        };
        values.insert(name.clone(), v);
    }
    let inputs: Vec<String> = system.inputs().iter().map(|(n, _)| n.clone()).collect();
    let model = linear_model(&equations, &rest, &inputs);
    Loaded {
        equations,
        rest,
        model,
        values,
    }
}

fn load(path: &str) -> Loaded {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../");
    load_source(&std::fs::read_to_string(format!("{root}{path}")).expect("reads"))
}

fn analyse(l: &Loaded, values: &Values) -> (EquilibriumSet, Vec<Linearized>) {
    let bounds = vec![(-10.0, 10.0); l.rest.coordinates.len()];
    let set = find_equilibria(&l.rest, values, &bounds).expect("equilibria");
    let lin = set
        .equilibria
        .iter()
        .map(|e| {
            linearize_at(&l.model, &l.rest, &e.values, e.exact.as_deref(), values)
                .expect("linearizes")
        })
        .collect();
    (set, lin)
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

#[test]
fn hoop_bifurcates_at_omega_squared_r_equal_g() {
    let l = load("examples/bead-on-rotating-hoop.lag");
    let (g, r): (f64, f64) = (9.81, 0.5);
    let critical = (g / r).sqrt();
    for omega in [
        0.5 * critical,
        0.99 * critical,
        1.01 * critical,
        2.0 * critical,
    ] {
        let mut v = l.values.clone();
        v.insert("Omega".into(), omega);
        let (set, lin) = analyse(&l, &v);
        assert_eq!(set.method, Method::Exact);
        let bottom = set
            .equilibria
            .iter()
            .position(|e| e.values[0].abs() < 1e-12)
            .expect("the bottom is always an equilibrium");
        let top = set
            .equilibria
            .iter()
            .position(|e| close(e.values[0].abs(), std::f64::consts::PI, 1e-12))
            .expect("the top is always an equilibrium");
        assert_eq!(lin[top].stable, Some(false));
        if omega < critical {
            assert_eq!(set.equilibria.len(), 2);
            assert_eq!(lin[bottom].stable, Some(true));
            // ω² = g/R − Ω² at the bottom.
            let w2 = lin[bottom].omega_squared.as_ref().unwrap()[0];
            assert!(close(w2, g / r - omega * omega, 1e-9), "{w2}");
        } else {
            assert_eq!(set.equilibria.len(), 4);
            assert_eq!(lin[bottom].stable, Some(false));
            let expected = (g / (omega * omega * r)).acos();
            for (e, li) in set.equilibria.iter().zip(&lin) {
                if close(e.values[0].abs(), expected, 1e-12) {
                    assert_eq!(li.stable, Some(true));
                    // ω² = Ω² sin² θ* off centre.
                    let w2 = li.omega_squared.as_ref().unwrap()[0];
                    let s = expected.sin();
                    assert!(close(w2, omega * omega * s * s, 1e-9), "{w2}");
                }
            }
        }
    }
    // At the bifurcation itself the bottom's Hessian is singular: undecided, never guessed.
    let mut v = l.values.clone();
    v.insert("Omega".into(), critical);
    let (set, lin) = analyse(&l, &v);
    let bottom = set
        .equilibria
        .iter()
        .position(|e| e.values[0].abs() < 1e-6)
        .unwrap();
    assert_eq!(lin[bottom].stable, None, "{}", lin[bottom].criterion);
    // The exact branch is ±acos(g/(Ω² R)), by normal-form equality.
    let branches = l.rest.exact.as_ref().expect("solved exactly");
    let target = (Expr::symbol("g") / (Expr::symbol("Omega").powi(2) * Expr::symbol("R"))).acos();
    assert!(branches.iter().any(|b| b.values[0].equals(target)));
    assert!(branches.iter().any(|b| b.values[0].equals(-target)));
}

#[test]
fn spring_chain_frequencies_are_the_closed_form() {
    let l = load("examples/spring-chain.lag");
    let (set, lin) = analyse(&l, &l.values);
    let origin = set
        .equilibria
        .iter()
        .position(|e| e.values.iter().all(|x| x.abs() < 1e-9))
        .expect("the rest configuration");
    let li = &lin[origin];
    assert_eq!(li.stable, Some(true));
    let (k, m) = (100.0, 1.0);
    let s2 = 2.0_f64.sqrt();
    let expected = [(2.0 - s2) * k / m, 2.0 * k / m, (2.0 + s2) * k / m];
    let w2 = li.omega_squared.as_ref().unwrap();
    for (a, b) in w2.iter().zip(expected) {
        assert!(close(*a, b, 1e-9), "{a} vs {b}");
    }
    // The first mode is (1, √2, 1) up to scale, M-normalized.
    let mode = &li.modes[0];
    assert!(close(mode[1] / mode[0], s2, 1e-9) && close(mode[2], mode[0], 1e-9));
    let norm: f64 = mode.iter().map(|x| x * x * m).sum();
    assert!(close(norm, 1.0, 1e-9));
}

#[test]
fn cart_pendulum_frequencies_solve_the_characteristic_polynomial() {
    let l = load("examples/seed/7.1-cart-pendulum.lag");
    let (set, lin) = analyse(&l, &l.values);
    assert_eq!(set.method, Method::Exact);
    assert_eq!(set.equilibria.len(), 2);
    let down = set
        .equilibria
        .iter()
        .position(|e| e.values[1].abs() < 1e-12)
        .unwrap();
    let (ma, mb, len, k, g): (f64, f64, f64, f64, f64) = (2.0, 1.0, 0.5, 30.0, 9.81);
    // det(K − ω² M) = a ω⁴ + b ω² + c with M = [[mA+mB, mB ℓ], [mB ℓ, mB ℓ²]], K = diag(k, mB g ℓ).
    let a = ma * mb * len * len;
    let b = -(k * mb * len * len + (ma + mb) * mb * g * len);
    let c = k * mb * g * len;
    let disc = (b * b - 4.0 * a * c).sqrt();
    let roots = [(-b - disc) / (2.0 * a), (-b + disc) / (2.0 * a)];
    let w2 = lin[down].omega_squared.as_ref().unwrap();
    assert!(
        close(w2[0], roots[0], 1e-9) && close(w2[1], roots[1], 1e-9),
        "{w2:?} vs {roots:?}"
    );
    assert_eq!(lin[down].stable, Some(true));
    // Upside down: unstable.
    assert_eq!(lin[1 - down].stable, Some(false));
    // Symbolic K0 at the hanging equilibrium: diag(k, m_B g ℓ), exactly.
    let [_, _, k0, _] = lin[down].exact.as_ref().expect("exact matrices");
    let s = Expr::symbol;
    assert!(k0[0][0].equals(s("k")) && k0[0][1].is_zero() && k0[1][0].is_zero());
    // K0_θθ = m_B g ℓ cos(asin(C/(m_B g ℓ))), which is m_B g ℓ for C = 0.
    let at_rest = k0[1][1].subs(&[(s("C"), Expr::zero())]);
    assert!(at_rest.equals(s("m_B") * s("g") * s("l")), "{at_rest:?}");
}

#[test]
fn inverted_pendulum_upright_is_unstable_and_controllable() {
    let l = load("examples/seed/7.4-inverted-pendulum.lag");
    let (set, lin) = analyse(&l, &l.values);
    let up = set
        .equilibria
        .iter()
        .position(|e| e.values[1].abs() < 1e-12)
        .expect("upright");
    let li = &lin[up];
    assert_eq!(li.stable, Some(false));
    // Closed form: λ² = (m g L/2) / (m L²/3 − (m L/2)²/(M + m)).
    let (cart, m, len, g): (f64, f64, f64, f64) = (1.0, 0.2, 0.6, 9.81);
    let reduced = m * len * len / 3.0 - (m * len / 2.0).powi(2) / (cart + m);
    let lambda = (m * g * len / 2.0 / reduced).sqrt();
    assert!(li
        .eigenvalues
        .iter()
        .any(|(re, im)| close(*re, lambda, 1e-9) && im.abs() < 1e-9));
    assert!(li
        .eigenvalues
        .iter()
        .any(|(re, im)| close(*re, -lambda, 1e-9) && im.abs() < 1e-9));
    assert_eq!(li.controllability_rank, Some(4));
    assert_eq!(li.b0, vec![vec![1.0], vec![0.0]]);
    // Hanging: stable once the free cart position is reduced away.
    assert_eq!(lin[1 - up].stable, Some(true));
    assert!(matches!(
        &lin[1 - up].criterion,
        Criterion::Reduced { criterion, free, .. }
            if **criterion == Criterion::LagrangeDirichlet && *free == ["x"]
    ));
    assert!(lin[1 - up].criterion.to_string().contains("Routh"));
}

#[test]
fn damped_systems_use_eigenvalues_and_damping_ratios() {
    let l = load_source(
        "coordinates x\nparameters m = 2, k = 8, c = 0.8\nframe N\npoint P = x*N.x\n\
         particle P mass m\nspring k from origin to P\ndamper c on x\n",
    );
    let (set, lin) = analyse(&l, &l.values);
    assert_eq!(set.equilibria.len(), 1);
    let li = &lin[0];
    assert_eq!(li.stable, Some(true));
    // ζ = c / (2 √(k m)).
    assert!(close(
        li.damping_ratios[0],
        0.8 / (2.0 * 16.0_f64.sqrt()),
        1e-9
    ));
    assert!(close(li.c0[0][0], 0.8, 1e-12));
}

/// Every root of a scalar function on [lo, hi] by a very fine sign scan (independent of the
/// search under test).
fn dense_sign_changes(f: &dyn Fn(f64) -> f64, lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let h = (hi - lo) / n as f64;
    let mut out = Vec::new();
    let mut prev = f(lo);
    for i in 1..=n {
        let x = lo + h * i as f64;
        let v = f(x);
        if prev * v < 0.0 {
            out.push(x - h / 2.0);
        }
        prev = v;
    }
    out
}

#[test]
fn numerical_search_misses_no_equilibrium_of_a_pendulum_on_a_torsion_spring() {
    // k θ² / 2 − m g ℓ cos θ with weak k: θ is not an angle (the spring is not periodic), the
    // rest equation k θ + m g ℓ sin θ = 0 is not solved exactly and has many roots.
    let l = load_source(
        "coordinates theta\nparameters m = 1, l = 1, g = 9.81, k = 0.7\nframe N\n\
         point P = l*sin(theta)*N.x - l*cos(theta)*N.y\nparticle P mass m\ngravity -g*N.y\n\
         spring k on theta\n",
    );
    assert!(l.rest.exact.is_none());
    assert!(!l.rest.periodic[0]);
    let (set, lin) = analyse(&l, &l.values);
    assert_eq!(set.method, Method::Scan);
    let reference = dense_sign_changes(&|t| 0.7 * t + 9.81 * t.sin(), -10.0, 10.0, 199_999);
    // θ = 0 is a root where the scan sees no sign change between samples only if it lands on
    // a sample; the reference scan is offset, so it sees all of them.
    assert_eq!(
        set.equilibria.len(),
        reference.len(),
        "{:?} vs {reference:?}",
        set.equilibria
    );
    for (e, r) in set.equilibria.iter().zip(&reference) {
        assert!((e.values[0] - r).abs() < 1e-4);
    }
    // Alternate stability along the chain of roots (minima and maxima of the potential).
    let stable: Vec<Option<bool>> = lin.iter().map(|l| l.stable).collect();
    for w in stable.windows(2) {
        assert_ne!(w[0], w[1]);
    }
}

#[test]
fn exact_and_numerical_equilibria_of_the_hoop_agree() {
    let l = load("examples/bead-on-rotating-hoop.lag");
    let (set, _) = analyse(&l, &l.values);
    let mut numeric_rest = l.rest.clone();
    numeric_rest.exact = None;
    numeric_rest.polynomial = None;
    let bounds = vec![(-10.0, 10.0)];
    let scanned = find_equilibria(&numeric_rest, &l.values, &bounds).unwrap();
    assert_eq!(scanned.method, Method::Scan);
    assert_eq!(set.equilibria.len(), scanned.equilibria.len());
    for (a, b) in set.equilibria.iter().zip(&scanned.equilibria) {
        assert!((a.values[0] - b.values[0]).abs() < 1e-8);
    }
}

/// `M(q) q̈ = f(q, q̇)` integrated by fixed-step RK4.
fn simulate(l: &Loaded, q0: &[f64], v0: &[f64], t_end: f64, steps: usize) -> Vec<f64> {
    let names = l.equations.coordinates().to_vec();
    let n = names.len();
    let accel = |q: &[f64], v: &[f64]| -> Vec<f64> {
        let env = |s: Symbol| {
            for (i, name) in names.iter().enumerate() {
                if Expr::coordinate(name).as_symbol() == Some(s) {
                    return Some(q[i]);
                }
                if Expr::rate(name, 1).as_symbol() == Some(s) {
                    return Some(v[i]);
                }
            }
            l.values.get(s.name()).copied()
        };
        let m: Vec<Vec<f64>> = l
            .equations
            .mass_matrix()
            .iter()
            .map(|r| r.iter().map(|e| e.eval(&env).unwrap()).collect())
            .collect();
        let f: Vec<f64> = l
            .equations
            .forcing()
            .iter()
            .map(|e| e.eval(&env).unwrap())
            .collect();
        solve(m, f)
    };
    let h = t_end / steps as f64;
    let (mut q, mut v) = (q0.to_vec(), v0.to_vec());
    let axpy = |x: &[f64], a: f64, y: &[f64]| -> Vec<f64> {
        x.iter().zip(y).map(|(x, y)| x + a * y).collect()
    };
    for _ in 0..steps {
        let k1v = accel(&q, &v);
        let k1q = v.clone();
        let (q2, v2) = (axpy(&q, h / 2.0, &k1q), axpy(&v, h / 2.0, &k1v));
        let k2v = accel(&q2, &v2);
        let k2q = v2.clone();
        let (q3, v3) = (axpy(&q, h / 2.0, &k2q), axpy(&v, h / 2.0, &k2v));
        let k3v = accel(&q3, &v3);
        let k3q = v3.clone();
        let (q4, v4) = (axpy(&q, h, &k3q), axpy(&v, h, &k3v));
        let k4v = accel(&q4, &v4);
        let k4q = v4;
        for i in 0..n {
            q[i] += h / 6.0 * (k1q[i] + 2.0 * k2q[i] + 2.0 * k3q[i] + k4q[i]);
            v[i] += h / 6.0 * (k1v[i] + 2.0 * k2v[i] + 2.0 * k3v[i] + k4v[i]);
        }
    }
    q
}

fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for c in 0..n {
        let p = (c..n)
            .max_by(|x, y| a[*x][c].abs().total_cmp(&a[*y][c].abs()))
            .unwrap();
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..n {
            let f = a[r][c] / a[c][c];
            let pivot = a[c].clone();
            for (x, p) in a[r].iter_mut().zip(&pivot).skip(c) {
                *x -= f * p;
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        x[i] = (b[i] - (i + 1..n).map(|k| a[i][k] * x[k]).sum::<f64>()) / a[i][i];
    }
    x
}

#[test]
fn linear_response_matches_the_nonlinear_motion_for_small_amplitudes() {
    let l = load("examples/seed/7.1-cart-pendulum.lag");
    let (set, lin) = analyse(&l, &l.values);
    let down = set
        .equilibria
        .iter()
        .position(|e| e.values[1].abs() < 1e-12)
        .unwrap();
    let eps = 1e-4;
    let (dq0, dv0) = ([eps, -eps], [0.0, 2.0 * eps]);
    let t = 1.3;
    let linear = lin[down].free_response(&dq0, &dv0, t).expect("undamped");
    let nonlinear = simulate(&l, &dq0, &dv0, t, 2000);
    for (a, b) in linear.iter().zip(&nonlinear) {
        // The nonlinear terms are O(ε³) against O(ε) motion.
        assert!((a - b).abs() < 1e-3 * eps, "{linear:?} vs {nonlinear:?}");
    }
}

#[test]
fn conical_motion_of_the_spherical_pendulum_by_routh() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../");
    let source = std::fs::read_to_string(format!("{root}examples/spherical-pendulum.lag")).unwrap();
    let model = model::load(&source).unwrap();
    let system = model::lower(&model).unwrap();
    let equations = mechanics::derive(&system).unwrap();
    let rest = mechanics::equilibria::steady_equations(&equations, &["phi".to_string()]).unwrap();
    let lm = linear_model(&equations, &rest, &[]);
    let (l, g, rate) = (1.0_f64, 9.81_f64, 5.0_f64);
    let mut values = Values::new();
    for (k, v) in [("m", 1.0), ("l", l), ("g", g), ("phi_d", rate)] {
        values.insert(k.to_string(), v);
    }
    let set = find_equilibria(&rest, &values, &[(-10.0, 10.0); 2]).unwrap();
    let cone = (g / (l * rate * rate)).acos();
    let e = set
        .equilibria
        .iter()
        .find(|e| close(e.values[1], cone, 1e-12))
        .expect("the conical motion cos θ = g/(ℓ φ̇²)");
    let li = linearize_at(&lm, &rest, &e.values, e.exact.as_deref(), &values).unwrap();
    assert_eq!(li.stable, Some(true));
    assert_eq!(li.criterion, Criterion::Routh);
    // Small oscillations about the cone: ω² = φ̇² (1 + 3 cos² θ0).
    let c = cone.cos();
    let expected = (rate * rate * (1.0 + 3.0 * c * c)).sqrt();
    assert!(
        li.eigenvalues
            .iter()
            .any(|(re, im)| re.abs() < 1e-9 && close(*im, expected, 1e-9)),
        "{:?}",
        li.eigenvalues
    );
    // A rate below √(g/ℓ) has no cone.
    values.insert("phi_d".into(), 2.0);
    let slow = find_equilibria(&rest, &values, &[(-10.0, 10.0); 2]).unwrap();
    assert_eq!(slow.equilibria.len(), 2);
    // Not cyclic: refused.
    assert!(mechanics::equilibria::steady_equations(&equations, &["theta".to_string()]).is_err());
}

#[test]
fn linearizations_agree_with_sympy() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../");
    for (model, data) in [
        ("examples/seed/7.1-cart-pendulum.lag", "7.1-cart-pendulum"),
        (
            "examples/seed/7.4-inverted-pendulum.lag",
            "7.4-inverted-pendulum",
        ),
        (
            "examples/bead-on-rotating-hoop.lag",
            "bead-on-rotating-hoop",
        ),
    ] {
        let l = load(model);
        let (set, lin) = analyse(&l, &l.values);
        let text =
            std::fs::read_to_string(format!("{root}tests/data/equilibria/{data}.json")).unwrap();
        let reference: serde_json::Value = serde_json::from_str(&text).unwrap();
        let expected = reference["equilibria"].as_array().unwrap();
        assert_eq!(set.equilibria.len(), expected.len(), "{model}");
        let number = |v: &serde_json::Value| v.as_f64().unwrap();
        for r in expected {
            let values: Vec<f64> = r["values"].as_array().unwrap().iter().map(number).collect();
            let i = set
                .equilibria
                .iter()
                .position(|e| {
                    e.values.iter().zip(&values).all(|(a, b)| {
                        let d = a - b;
                        d.abs() < 1e-9 || (d.abs() - std::f64::consts::TAU).abs() < 1e-9
                    })
                })
                .unwrap_or_else(|| panic!("{model}: no equilibrium at {values:?}"));
            for (key, ours) in [("M0", &lin[i].m0), ("C0", &lin[i].c0), ("K0", &lin[i].k0)] {
                for (row, ref_row) in ours.iter().zip(r[key].as_array().unwrap()) {
                    for (a, b) in row.iter().zip(ref_row.as_array().unwrap()) {
                        assert!(
                            close(*a, number(b), 1e-9),
                            "{model} {key}: {ours:?} vs {}",
                            r[key]
                        );
                    }
                }
            }
            let w2 = lin[i].omega_squared.as_ref().unwrap();
            for (a, b) in w2.iter().zip(r["omega_squared"].as_array().unwrap()) {
                assert!(
                    (a - number(b)).abs() < 1e-9 * (1.0 + a.abs()),
                    "{model}: {w2:?}"
                );
            }
            for (re, im) in &lin[i].eigenvalues {
                assert!(r["eigenvalues"].as_array().unwrap().iter().any(|z| {
                    (re - number(&z[0])).abs() < 1e-7 && (im - number(&z[1])).abs() < 1e-7
                }));
            }
        }
    }
}

#[test]
fn polynomial_rest_equations_are_solved_completely() {
    // V = a cos⁴θ/4 − b cos θ + c sin θ: the rest equation is of degree 4 in (sin, cos), beyond
    // the exact solver; the half-angle polynomial finds every root, checked by a dense scan.
    let l = load_source(
        "coordinates theta\nparameters m = 1, a = 3, b = 0.2, c = 0.1\nframe N\n\
         point P = sin(theta)*N.x - cos(theta)*N.y\nparticle P mass m\n\
         potential a*cos(theta)^4/4 - b*cos(theta) + c*sin(theta)\n",
    );
    assert!(l.rest.exact.is_none());
    assert!(l.rest.periodic[0]);
    let (set, _) = analyse(&l, &l.values);
    assert_eq!(set.method, Method::Polynomial);
    // −dV/dθ = a cos³θ sin θ − b sin θ − c cos θ.
    let f = |t: f64| 3.0 * t.cos().powi(3) * t.sin() - 0.2 * t.sin() - 0.1 * t.cos();
    let pi = std::f64::consts::PI;
    let reference = dense_sign_changes(&f, -pi + 1e-7, pi + 1e-7, 400_000);
    assert_eq!(
        set.equilibria.len(),
        reference.len(),
        "{:?} vs {reference:?}",
        set.equilibria
    );
    for r in &reference {
        let wrapped = r.sin().atan2(r.cos());
        assert!(set
            .equilibria
            .iter()
            .any(|e| (e.values[0] - wrapped).abs() < 1e-4));
    }
    // A cubic in a length (a tilted double well, V = x⁴/4 − x²/2 + x/10): three roots.
    let l = load_source(
        "coordinates x\nparameters m = 1\nframe N\npoint P = x*N.x\nparticle P mass m\n\
         potential x^4/4 - x^2/2 + x/10\n",
    );
    let (set, lin) = analyse(&l, &l.values);
    assert_eq!(set.method, Method::Polynomial);
    assert_eq!(set.equilibria.len(), 3);
    for e in &set.equilibria {
        let x = e.values[0];
        assert!((x.powi(3) - x + 0.1).abs() < 1e-12);
    }
    let stable: Vec<Option<bool>> = lin.iter().map(|l| l.stable).collect();
    assert_eq!(stable, vec![Some(true), Some(false), Some(true)]);
}
