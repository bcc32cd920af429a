//! The register tape on the double pendulum's equations written out by hand in `cas`
//! (`M q̈ = f`, unit masses and lengths): compile once, then one evaluation of `M` and `f`.
//! `cargo bench -p lagrange-numeric --bench tape`.

use cas::{Expr, Symbol};
use numeric::Tape;

fn main() {
    divan::main();
}

fn double_pendulum() -> (Vec<Expr>, Vec<Symbol>) {
    let (a, b) = (Expr::coordinate("a"), Expr::coordinate("b"));
    let (ad, bd) = (Expr::rate("a", 1), Expr::rate("b", 1));
    let g = Expr::symbol("g");
    let c = (a - b).cos();
    let s = (a - b).sin();
    let outputs = vec![
        Expr::int(2),
        c,
        c,
        Expr::one(),
        (-(s * bd.powi(2)) - g * a.sin() * 2).normal(),
        (s * ad.powi(2) - g * b.sin()).normal(),
    ];
    let inputs = [a, b, ad, bd, g]
        .iter()
        .filter_map(|e| e.as_symbol())
        .collect();
    (outputs, inputs)
}

#[divan::bench]
fn compile(bencher: divan::Bencher) {
    let (outputs, inputs) = double_pendulum();
    bencher.bench(|| Tape::compile(divan::black_box(&outputs), &inputs));
}

#[divan::bench]
fn evaluate(bencher: divan::Bencher) {
    let (outputs, inputs) = double_pendulum();
    let Ok(tape) = Tape::compile(&outputs, &inputs) else {
        return;
    };
    let mut registers = tape.registers();
    let mut out = vec![0.0; tape.output_count()];
    let state = [0.3, -0.2, 1.0, 0.5, 9.81];
    bencher.bench_local(|| {
        tape.eval(divan::black_box(&state), &mut registers, &mut out);
        divan::black_box(out[4])
    });
}
