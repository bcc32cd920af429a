//! Running the real `lagrange` binary from the integration tests, from the repository root
//! (where `examples/` is).

// Each test file is its own crate and uses only some of these.
#![allow(dead_code)]

use std::path::PathBuf;
use std::process::{Command, Output};

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Runs `lagrange ARGS` in the repository root.
pub fn lagrange(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lagrange"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("the lagrange binary runs")
}

/// Its standard output.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Its standard error.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `lagrange simulate` of the particle leaving a sphere, tight tolerances, 5 s: the start of
/// the contact-loss tests' command lines.
#[allow(dead_code)]
pub const SPHERE_RUN: [&str; 8] = [
    "simulate",
    "examples/particle-on-sphere.lag",
    "--t-end",
    "5",
    "--rtol",
    "1e-10",
    "--atol",
    "1e-12",
];

/// [`lagrange`] with `first` and then `rest` as arguments.
#[allow(dead_code)]
pub fn lagrange_with(first: &[&str], rest: &[&str]) -> Output {
    lagrange(&[first, rest].concat())
}

/// Runs `lagrange ARGS`: its exit code, standard output and standard error.
pub fn run_code(args: &[&str]) -> (Option<i32>, String, String) {
    let out = lagrange(args);
    (out.status.code(), stdout(&out), stderr(&out))
}

/// Runs `lagrange ARGS`: whether it succeeded, its standard output and standard error.
pub fn run(args: &[&str]) -> (bool, String, String) {
    let out = lagrange(args);
    (out.status.success(), stdout(&out), stderr(&out))
}
