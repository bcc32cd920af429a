//! Benchmark of the symbolic core on the planar n-link pendulum: build K and V, form all of
//! Lagrange's equations, extract the mass matrix and the forcing in normal form.
//!
//! Run with `cargo bench -p lagrange-cas --bench nlink`. Targets (issue 2): n = 10 under
//! 10 ms, n = 40 under 1 s. `derive_nlink` goes through `Expr` operations only (a tree after
//! every step); `derive_nlink_working_forms` keeps the intermediate results as
//! `cas::NormalForm`, as the mechanics crate does. Each iteration uses fresh symbol names, so that no memoised
//! normal form from an earlier iteration is reused.

#[path = "../tests/common/nlink.rs"]
mod nlink;

use std::sync::atomic::{AtomicUsize, Ordering};

use nlink::NLink;

fn main() {
    divan::main();
}

static RUN: AtomicUsize = AtomicUsize::new(0);

#[divan::bench(args = [5, 10, 20, 40], sample_count = 3, sample_size = 1)]
fn derive_nlink(bencher: divan::Bencher, n: usize) {
    bencher
        .with_inputs(|| {
            // Fresh names per run: the arena and the memo tables would otherwise hand back
            // the previous run's results.
            let run = RUN.fetch_add(1, Ordering::Relaxed);
            NLink::with_prefix(n, &format!("r{run}_"))
        })
        .bench_values(|system| divan::black_box(system.equations()));
}

#[divan::bench(args = [5, 10, 20, 40], sample_count = 3, sample_size = 1)]
fn derive_nlink_working_forms(bencher: divan::Bencher, n: usize) {
    bencher
        .with_inputs(|| {
            let run = RUN.fetch_add(1, Ordering::Relaxed);
            NLink::with_prefix(n, &format!("w{run}_"))
        })
        .bench_values(|system| divan::black_box(system.equations_on_working_forms()));
}
