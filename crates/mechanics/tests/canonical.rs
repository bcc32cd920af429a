//! The canonical systems' equations against their textbook forms: exactly (normal-form
//! equality) and by numbers at random states (the mass matrix as the Hessian of the kinetic
//! energy in the rates, the four-bar's constraint Jacobian by finite differences, energy
//! conserved along an integration of the closed form).

use std::collections::HashMap;

use cas::{Expr, Symbol};
use mechanics::{canonical, derive, Equations, System};

fn s(name: &str) -> Expr {
    Expr::symbol(name)
}

fn q(name: &str) -> Expr {
    Expr::coordinate(name)
}

fn qd(name: &str) -> Expr {
    Expr::rate(name, 1)
}

fn assert_equal(what: &str, got: Expr, want: Expr) {
    assert!(got.equals(want), "{what}: got {got}, want {want}");
}

fn assert_matrix(eq: &Equations, m: &[&[Expr]], f: &[Expr]) {
    assert_eq!(eq.mass_matrix().len(), m.len());
    for (i, row) in m.iter().enumerate() {
        for (j, want) in row.iter().enumerate() {
            assert_equal(&format!("M[{i}][{j}]"), eq.mass_matrix()[i][j], *want);
        }
        assert_equal(&format!("f[{i}]"), eq.forcing()[i], f[i]);
    }
}

/// A small deterministic generator (xorshift), uniform in `[lo, hi)`.
struct Random(u64);

impl Random {
    fn next(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// Values of the parameters (their model values), inputs (0) and a state.
#[derive(Clone)]
struct Point(HashMap<Symbol, f64>);

impl Point {
    fn of(system: &System) -> Point {
        let mut map = HashMap::new();
        for (name, value) in system.parameters() {
            let v = value
                .expect("canonical parameters have values")
                .eval(&|_| None)
                .expect("a constant");
            map.insert(s(name).as_symbol().expect("a symbol"), v);
        }
        for (name, _) in system.inputs() {
            map.insert(s(name).as_symbol().expect("a symbol"), 0.0);
        }
        Point(map)
    }

    fn set(&mut self, e: Expr, v: f64) {
        self.0.insert(e.as_symbol().expect("a symbol"), v);
    }

    fn get(&self, e: Expr) -> f64 {
        self.0[&e.as_symbol().expect("a symbol")]
    }

    fn eval(&self, e: Expr) -> f64 {
        e.eval(&|s| self.0.get(&s).copied())
            .unwrap_or_else(|err| panic!("{e}: {err}"))
    }

    fn random_state(&mut self, coordinates: &[String], rng: &mut Random) {
        for c in coordinates {
            self.set(q(c), rng.next(-3.0, 3.0));
            self.set(qd(c), rng.next(-2.0, 2.0));
        }
    }
}

#[test]
fn pendulum_is_textbook() {
    let eq = derive(&canonical::pendulum()).unwrap();
    let (m, l, g, th) = (s("m"), s("l"), s("g"), q("theta"));
    assert_matrix(&eq, &[&[m * l.powi(2)]], &[-(m * g * l * th.sin())]);
    assert_eq!(eq.first_integrals()[0].kind, "energy");
}

fn double_pendulum_textbook() -> (Vec<Vec<Expr>>, Vec<Expr>) {
    let (m1, m2, l1, l2, g) = (s("m1"), s("m2"), s("l1"), s("l2"), s("g"));
    let (t1, t2) = (q("theta1"), q("theta2"));
    let delta = t1 - t2;
    let c = m2 * l1 * l2 * delta.cos();
    let sn = m2 * l1 * l2 * delta.sin();
    (
        vec![vec![(m1 + m2) * l1.powi(2), c], vec![c, m2 * l2.powi(2)]],
        vec![
            -(sn * qd("theta2").powi(2)) - (m1 + m2) * g * l1 * t1.sin(),
            sn * qd("theta1").powi(2) - m2 * g * l2 * t2.sin(),
        ],
    )
}

#[test]
fn double_pendulum_is_textbook() {
    let eq = derive(&canonical::double_pendulum()).unwrap();
    let (m, f) = double_pendulum_textbook();
    let rows: Vec<&[Expr]> = m.iter().map(Vec::as_slice).collect();
    assert_matrix(&eq, &rows, &f);
    assert_eq!(eq.coordinates(), ["theta1", "theta2"]);
}

#[test]
fn cart_pendulum_is_textbook() {
    let eq = derive(&canonical::cart_pendulum()).unwrap();
    let (ma, mb, l, k, g) = (s("m_A"), s("m_B"), s("l"), s("k"), s("g"));
    let (x, th) = (q("x"), q("theta"));
    let c = mb * l * th.cos();
    assert_matrix(
        &eq,
        &[&[ma + mb, c], &[c, mb * l.powi(2)]],
        &[
            mb * l * th.sin() * qd("theta").powi(2) - k * x + s("F"),
            -(mb * g * l * th.sin()) + s("C"),
        ],
    );
    // Energy is conserved while the inputs vanish.
    let energy = &eq.first_integrals()[0];
    assert_eq!(energy.kind, "energy");
    assert_eq!(energy.conditions.len(), 2);
}

#[test]
fn rolling_disk_eliminates_phi_and_is_textbook() {
    let eq = derive(&canonical::rolling_disk()).unwrap();
    assert_eq!(eq.coordinates(), ["x"]);
    let [e] = eq.eliminated() else {
        panic!("one elimination, got {:?}", eq.eliminated())
    };
    assert_eq!(e.coordinate, "phi");
    assert_equal("phi", e.value, q("x") / s("R"));
    assert!(eq.constraint_matrix().is_empty());
    let (m, g, alpha) = (s("m"), s("g"), s("alpha"));
    assert_matrix(&eq, &[&[m * 3 / 2]], &[m * g * alpha.sin()]);
}

/// `(M, f, A, b)` of the four-bar, by hand.
type Closed = (Vec<Vec<Expr>>, Vec<Expr>, Vec<Vec<Expr>>, Vec<Expr>);

fn four_bar_textbook() -> Closed {
    let (m1, m2, m3, g) = (s("m1"), s("m2"), s("m3"), s("g"));
    let (l1, l2, l3) = (s("l1"), s("l2"), s("l3"));
    let [t1, t2, t3] = ["theta1", "theta2", "theta3"].map(q);
    let [w1, w2, w3] = ["theta1", "theta2", "theta3"].map(qd);
    let z = Expr::zero();
    let c = m2 * l1 * l2 * (t1 - t2).cos() / 2;
    let sn = m2 * l1 * l2 * (t1 - t2).sin() / 2;
    let mass = vec![
        vec![m1 * l1.powi(2) / 3 + m2 * l1.powi(2), c, z],
        vec![c, m2 * l2.powi(2) / 3, z],
        vec![z, z, m3 * l3.powi(2) / 3],
    ];
    let forcing = vec![
        -(sn * w2.powi(2)) - g * (m1 / 2 + m2) * l1 * t1.cos(),
        sn * w1.powi(2) - g * m2 * l2 * t2.cos() / 2,
        -(g * m3 * l3 * t3.cos() / 2),
    ];
    let a = vec![
        vec![-(l1 * t1.sin()), -(l2 * t2.sin()), l3 * t3.sin()],
        vec![l1 * t1.cos(), l2 * t2.cos(), -(l3 * t3.cos())],
    ];
    let b = vec![
        l1 * t1.cos() * w1.powi(2) + l2 * t2.cos() * w2.powi(2) - l3 * t3.cos() * w3.powi(2),
        l1 * t1.sin() * w1.powi(2) + l2 * t2.sin() * w2.powi(2) - l3 * t3.sin() * w3.powi(2),
    ];
    (mass, forcing, a, b)
}

#[test]
fn four_bar_is_textbook() {
    let eq = derive(&canonical::four_bar()).unwrap();
    let (m, f, a, b) = four_bar_textbook();
    let rows: Vec<&[Expr]> = m.iter().map(Vec::as_slice).collect();
    assert_matrix(&eq, &rows, &f);
    assert_eq!(eq.constraint_names(), ["loop_x", "loop_y"]);
    for (i, row) in a.iter().enumerate() {
        for (j, want) in row.iter().enumerate() {
            assert_equal(&format!("A[{i}][{j}]"), eq.constraint_matrix()[i][j], *want);
        }
        assert_equal(&format!("b[{i}]"), eq.constraint_rhs()[i], b[i]);
    }
    assert_eq!(eq.first_integrals()[0].kind, "energy");
}

/// `M` is the Hessian of `K` in the rates: checked by central differences of the derived `K`
/// at random states, for every canonical system.
#[test]
fn mass_matrices_are_hessians_of_the_kinetic_energy() {
    let mut rng = Random(0x9e37_79b9_7f4a_7c15);
    for c in canonical::all() {
        let eq = derive(&c.system).unwrap();
        let coordinates = eq.coordinates().to_vec();
        for _ in 0..5 {
            let mut p = Point::of(&c.system);
            p.random_state(&coordinates, &mut rng);
            let h = 1e-3;
            for (i, a) in coordinates.iter().enumerate() {
                for (j, b) in coordinates.iter().enumerate() {
                    let k = |da: f64, db: f64| {
                        let mut x = p.clone();
                        x.set(qd(a), p.get(qd(a)) + da);
                        x.set(qd(b), x.get(qd(b)) + db);
                        x.eval(eq.kinetic_energy())
                    };
                    let fd = (k(h, h) - k(h, -h) - k(-h, h) + k(-h, -h)) / (4.0 * h * h);
                    let m = p.eval(eq.mass_matrix()[i][j]);
                    assert!(
                        (fd - m).abs() <= 1e-6 * (1.0 + m.abs()),
                        "{}: M[{i}][{j}] = {m}, Hessian {fd}",
                        c.name
                    );
                }
            }
        }
    }
}

/// The textbook forms, written again as plain floating-point code, agree with the derived
/// `M`, `f` at random states (double pendulum).
#[test]
fn double_pendulum_numbers_match_plain_code() {
    let system = canonical::double_pendulum();
    let eq = derive(&system).unwrap();
    let mut rng = Random(7);
    for _ in 0..20 {
        let mut p = Point::of(&system);
        p.set(s("m1"), rng.next(0.5, 2.0));
        p.set(s("l2"), rng.next(0.5, 2.0));
        p.random_state(eq.coordinates(), &mut rng);
        let (m1, m2, l1, l2, g) = (
            p.get(s("m1")),
            p.get(s("m2")),
            p.get(s("l1")),
            p.get(s("l2")),
            p.get(s("g")),
        );
        let (t1, t2) = (p.get(q("theta1")), p.get(q("theta2")));
        let (w1, w2) = (p.get(qd("theta1")), p.get(qd("theta2")));
        let d = t1 - t2;
        let want_m = [
            [(m1 + m2) * l1 * l1, m2 * l1 * l2 * d.cos()],
            [m2 * l1 * l2 * d.cos(), m2 * l2 * l2],
        ];
        let want_f = [
            -m2 * l1 * l2 * d.sin() * w2 * w2 - (m1 + m2) * g * l1 * t1.sin(),
            m2 * l1 * l2 * d.sin() * w1 * w1 - m2 * g * l2 * t2.sin(),
        ];
        for i in 0..2 {
            for (j, want) in want_m[i].iter().enumerate() {
                let got = p.eval(eq.mass_matrix()[i][j]);
                assert!((got - want).abs() < 1e-12 * (1.0 + got.abs()));
            }
            let got = p.eval(eq.forcing()[i]);
            assert!((got - want_f[i]).abs() < 1e-11 * (1.0 + got.abs()));
        }
    }
}

/// The four-bar's constraint matrix is the Jacobian of the loop functions (central
/// differences at random configurations).
#[test]
fn four_bar_constraint_jacobian_matches_finite_differences() {
    let system = canonical::four_bar();
    let eq = derive(&system).unwrap();
    let loops = canonical::four_bar_loop();
    let mut rng = Random(11);
    for _ in 0..20 {
        let mut p = Point::of(&system);
        p.random_state(eq.coordinates(), &mut rng);
        for (i, phi) in loops.iter().enumerate() {
            for (j, c) in eq.coordinates().iter().enumerate() {
                let h = 1e-5;
                let at = |dx: f64| {
                    let mut x = p.clone();
                    x.set(q(c), p.get(q(c)) + dx);
                    x.eval(*phi)
                };
                let fd = (at(h) - at(-h)) / (2.0 * h);
                let a = p.eval(eq.constraint_matrix()[i][j]);
                assert!((fd - a).abs() < 1e-7, "A[{i}][{j}] = {a}, difference {fd}");
            }
        }
    }
}

/// Accelerations (and multipliers) of the closed form at a state: `[M Aᵀ; A 0] [q̈; λ] =
/// [f; b]`, solved numerically.
fn accelerations(eq: &Equations, p: &Point) -> Vec<f64> {
    let n = eq.coordinates().len();
    let m = eq.constraint_matrix().len();
    let size = n + m;
    let mut a = vec![0.0; size * size];
    let mut rhs = vec![0.0; size];
    for i in 0..n {
        for j in 0..n {
            a[i * size + j] = p.eval(eq.mass_matrix()[i][j]);
        }
        rhs[i] = p.eval(eq.forcing()[i]);
    }
    for k in 0..m {
        for j in 0..n {
            let x = p.eval(eq.constraint_matrix()[k][j]);
            a[(n + k) * size + j] = x;
            a[j * size + n + k] = x;
        }
        rhs[n + k] = p.eval(eq.constraint_rhs()[k]);
    }
    numeric::solve_in_place(size, &mut a, &mut rhs).expect("a regular state");
    rhs.truncate(n);
    rhs
}

/// Integrates the closed form with classical RK4 from the system's initial state and returns
/// the largest change of the energy integral, relative to its scale, and the point reached.
fn energy_drift(c: &canonical::Canonical, t_end: f64, steps: usize) -> (f64, Point) {
    let eq = derive(&c.system).unwrap();
    let names = eq.coordinates().to_vec();
    let energy = eq.first_integrals()[0].value;
    let mut p = Point::of(&c.system);
    let mut y: Vec<f64> = Vec::new();
    for name in &names {
        let (_, x, _) = c.initial.iter().find(|(q, ..)| q == name).unwrap();
        y.push(*x);
    }
    for name in &names {
        let (_, _, v) = c.initial.iter().find(|(q, ..)| q == name).unwrap();
        y.push(*v);
    }
    let n = names.len();
    let load = |p: &mut Point, y: &[f64]| {
        for (i, name) in names.iter().enumerate() {
            p.set(q(name), y[i]);
            p.set(qd(name), y[n + i]);
        }
    };
    let rate = |p: &mut Point, y: &[f64]| -> Vec<f64> {
        load(p, y);
        let mut d = y[n..].to_vec();
        d.extend(accelerations(&eq, p));
        d
    };
    load(&mut p, &y);
    let e0 = p.eval(energy);
    let scale = 1.0 + e0.abs();
    let h = t_end / steps as f64;
    let mut worst = 0.0f64;
    for _ in 0..steps {
        let add = |y: &[f64], k: &[f64], s: f64| -> Vec<f64> {
            y.iter().zip(k).map(|(a, b)| a + s * b).collect()
        };
        let k1 = rate(&mut p, &y);
        let k2 = rate(&mut p, &add(&y, &k1, h / 2.0));
        let k3 = rate(&mut p, &add(&y, &k2, h / 2.0));
        let k4 = rate(&mut p, &add(&y, &k3, h));
        for i in 0..y.len() {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        load(&mut p, &y);
        worst = worst.max((p.eval(energy) - e0).abs() / scale);
    }
    (worst, p)
}

/// The energy integral reported for each conservative canonical system stays constant along
/// an integration of the closed form (which it would not if `M`, `f`, `A` or `b` were wrong);
/// the four-bar also stays on its loop.
#[test]
fn energy_is_conserved_along_the_closed_form() {
    for c in canonical::all() {
        let (drift, end) = energy_drift(&c, 1.0, 400);
        assert!(drift < 1e-6, "{}: energy drift {drift}", c.name);
        if c.name == "four-bar" {
            for phi in canonical::four_bar_loop() {
                let r = end.eval(phi);
                assert!(r.abs() < 1e-6, "loop residual {r}");
            }
        }
    }
}

#[test]
fn initial_states_satisfy_the_constraints() {
    let c = canonical::all()
        .into_iter()
        .find(|c| c.name == "four-bar")
        .unwrap();
    let eq = derive(&c.system).unwrap();
    let mut p = Point::of(&c.system);
    for (name, x, v) in &c.initial {
        p.set(q(name), *x);
        p.set(qd(name), *v);
    }
    for phi in canonical::four_bar_loop() {
        assert!(p.eval(phi).abs() < 1e-12);
    }
    for row in eq.constraint_matrix() {
        let rate: f64 = row
            .iter()
            .zip(eq.coordinates())
            .map(|(a, name)| p.eval(*a) * p.get(qd(name)))
            .sum();
        assert!(rate.abs() < 1e-12);
    }
}
