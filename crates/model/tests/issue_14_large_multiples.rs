//! Issue 14: with `potential 1 - cos(60*x)` a particle never moved, because `cos 60x` was
//! expanded into a polynomial of degree 60 in `cos x` whose evaluation cancelled to noise (and
//! from n ≈ 50 on the simulation hung). Large multiples are now angles of their own in the
//! symbolic core (docs/cas.md); the forcing evaluates to `−60 sin 60x` at every state.

use cas::{Symbol, SymbolKind};

#[test]
fn a_potential_in_a_large_multiple_gives_the_right_force() {
    for n in [60, 150, 1000] {
        let text = format!(
            "coordinates x\nparameters m = 1\nframe N\npoint P = x*N.x\nparticle P mass m\n\
             potential 1 - cos({n}*x)\n"
        );
        let model = model::load(&text).expect("loads");
        let system = model::lower(&model).expect("lowers");
        let eq = mechanics::derive(&system).expect("derives");
        for k in 1..10 {
            let x = 0.1 * k as f64;
            let env = |s: Symbol| match (s.name(), s.kind()) {
                ("x", SymbolKind::TimeFunction { order: 0 }) => Some(x),
                ("x", SymbolKind::TimeFunction { .. }) => Some(0.0),
                ("m", _) => Some(1.0),
                _ => None,
            };
            let f = eq.forcing()[0].eval(&env).expect("evaluates");
            let want = -(n as f64) * (n as f64 * x).sin();
            assert!(
                (f - want).abs() < 1e-9 * n as f64,
                "n = {n}, x = {x}: {f} vs {want}"
            );
            let v = eq.potential_energy().eval(&env).expect("evaluates");
            assert!((v - (1.0 - (n as f64 * x).cos())).abs() < 1e-12);
        }
    }
}
