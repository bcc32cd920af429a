//! Where the time goes when deriving the n-link pendulum: energies, Lagrangian, partial
//! derivatives, time derivatives, coefficient extraction, normalisation, each timed apart.
//! `cargo run --release -p lagrange-cas --example phases -- N REPS`.
#[path = "../tests/common/nlink.rs"]
mod nlink;
use std::time::Instant;
fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let reps: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let (mut te, mut tl, mut td, mut tdt, mut tq, mut taff, mut tnorm) =
        (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for r in 0..reps {
        let s = nlink::NLink::with_prefix(n, &format!("r{r}_"));
        let t = Instant::now();
        let (k, v) = s.energies();
        te += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let l = (k - v).normal();
        tl += t.elapsed().as_secs_f64();
        for i in 0..n {
            let t = Instant::now();
            let p = l.diff(s.rates[i].as_symbol().unwrap());
            td += t.elapsed().as_secs_f64();
            let t = Instant::now();
            let pd = p.dt();
            tdt += t.elapsed().as_secs_f64();
            let t = Instant::now();
            let dq = l.diff(s.angles[i].as_symbol().unwrap());
            tq += t.elapsed().as_secs_f64();
            let t = Instant::now();
            let eq = pd - dq;
            let (_, rest) = eq.affine_coefficients(&s.accelerations).unwrap();
            taff += t.elapsed().as_secs_f64();
            let t = Instant::now();
            let _ = (-rest).normal();
            tnorm += t.elapsed().as_secs_f64();
        }
    }
    let k = 1e3 / reps as f64;
    println!("ms per run: energies {:.2} L {:.2} diff rate {:.2} dt {:.2} diff q {:.2} affine {:.2} neg-normal {:.2}", te*k, tl*k, td*k, tdt*k, tq*k, taff*k, tnorm*k);
}
