//! Issue 23, reproduction 3: constant angle offsets between links (`frame B3 = B2 rotated
//! al + th3 about z`) made a four-link chain take 12 s and a five-link chain of particles and
//! bodies with springs never finish. The cause was in the polynomial arithmetic, not in the
//! offsets themselves: a product rewrote every `sin²` product and added each rewritten piece to
//! a sorted result one at a time, and exact division subtracted from the whole remainder at each
//! quotient term — both quadratic in the size of the operands, which offsets double. Products now
//! gather raw monomials and rewrite each distinct one once; division updates only the terms it
//! touches.
//!
//! The derived energies are checked against an independent route: the kinetic energy written
//! with the absolute angles `φ_j = th1 + … + th_j (+ al from link 3 on)` whole,
//! `T = ½ Σ_k m_k Σ_{i,j ≤ k} l_i l_j φ̇_i φ̇_j cos(φ_i − φ_j)`, compared exactly and at random
//! points.

use cas::{Expr, Symbol, SymbolKind};

const OFFSET_CHAIN4: &str = include_str!("../../../bench/models/offset-chain4.lag");
const OFFSET_CHAIN5: &str = include_str!("../../../bench/models/offset-chain5.lag");

fn absolute_angles(links: usize) -> (Vec<Expr>, Vec<Expr>) {
    let al = Expr::symbol("al");
    let mut angle = Expr::zero();
    let mut rate = Expr::zero();
    let (mut angles, mut rates) = (Vec::new(), Vec::new());
    for j in 1..=links {
        angle += Expr::coordinate(&format!("th{j}"));
        rate += Expr::rate(&format!("th{j}"), 1);
        if j == 3 {
            angle += al;
        }
        angles.push(angle);
        rates.push(rate);
    }
    (angles, rates)
}

#[test]
fn a_four_link_chain_with_an_offset_has_the_closed_form_energies() {
    let model = model::load(OFFSET_CHAIN4).expect("the bench model loads");
    let system = model::lower(&model).expect("lowers");
    let eq = mechanics::derive(&system).expect("derives");
    let (phi, phid) = absolute_angles(4);
    let l: Vec<Expr> = (1..=4).map(|i| Expr::symbol(&format!("l{i}"))).collect();
    let g = Expr::symbol("g");
    // Particles of masses m1, m2, m3 at the ends of links 2, 3, 4.
    let mut kinetic = Expr::zero();
    let mut potential = Expr::zero();
    for (k, mass) in [(2usize, "m1"), (3, "m2"), (4, "m3")] {
        let m = Expr::symbol(mass);
        for i in 0..k {
            for j in 0..k {
                kinetic += Expr::rational(1, 2).expect("non-zero")
                    * m
                    * l[i]
                    * l[j]
                    * phid[i]
                    * phid[j]
                    * (phi[i] - phi[j]).cos();
            }
            potential += m * g * l[i] * phi[i].sin();
        }
    }
    assert!(eq.kinetic_energy().equals(kinetic), "T differs");
    assert!(eq.potential_energy().equals(potential), "V differs");
    // And by numbers, at a few states.
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % 2000) as f64 / 1000.0 - 1.0
    };
    for _ in 0..5 {
        let mut values: Vec<(Symbol, f64)> = Vec::new();
        for i in 1..=4 {
            let name = format!("th{i}");
            for order in [0, 1] {
                values.push((
                    Symbol::new(&name, SymbolKind::TimeFunction { order }),
                    next(),
                ));
            }
            values.push((
                Symbol::new(&format!("l{i}"), SymbolKind::Constant),
                1.0 + next(),
            ));
        }
        for name in ["m1", "m2", "m3", "al", "g"] {
            values.push((Symbol::new(name, SymbolKind::Constant), 2.0 + next()));
        }
        let env = |s: Symbol| values.iter().find(|(v, _)| *v == s).map(|(_, x)| *x);
        let at = |e: Expr| e.eval(&env).expect("evaluates");
        let (got, want) = (at(eq.kinetic_energy()), at(kinetic));
        assert!(
            (got - want).abs() <= 1e-12 * want.abs().max(1.0),
            "{got} vs {want}"
        );
    }
}

#[test]
fn a_five_link_chain_of_bodies_springs_and_an_offset_derives() {
    let model = model::load(OFFSET_CHAIN5).expect("the bench model loads");
    let system = model::lower(&model).expect("lowers");
    let eq = mechanics::derive(&system).expect("derives");
    // The mass matrix is symmetric and each entry is the second rate derivative of T.
    let rates: Vec<Symbol> = (1..=5)
        .map(|i| Symbol::new(&format!("th{i}"), SymbolKind::TimeFunction { order: 1 }))
        .collect();
    let t = eq.kinetic_energy();
    for i in 0..5 {
        for j in 0..5 {
            let want = t.diff(rates[i]).diff(rates[j]);
            assert!(eq.mass_matrix()[i][j].equals(want), "M[{i}][{j}]");
        }
    }
}
