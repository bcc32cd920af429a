//! The `lagrange` binary, run for real: the symbolic-core commands, `check` and `solve` on the
//! seed's examples, and the exit codes and messages of bad input.

use std::path::PathBuf;
use std::process::{Command, Output};

fn lagrange(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lagrange"))
        .args(args)
        .current_dir(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../.."))
        .output()
        .expect("the lagrange binary runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn simplify_prints_the_normal_form_in_each_dialect() {
    let o = lagrange(&["simplify", "sin(a+b) - sin(a)*cos(b)", "--format", "sympy"]);
    assert!(o.status.success());
    assert_eq!(stdout(&o).trim(), "sin(b)*cos(a)");
    let o = lagrange(&["simplify", "(x**2 - y**2)/(x - y)", "--format", "latex"]);
    assert_eq!(stdout(&o).trim(), "x + y");
    let o = lagrange(&["simplify", "sin(theta)**2 + cos(theta)**2"]);
    assert_eq!(stdout(&o).trim(), "1");
}

#[test]
fn diff_takes_partial_and_total_time_derivatives() {
    let o = lagrange(&[
        "diff",
        "l*sin(theta)",
        "t",
        "--coords",
        "theta",
        "--format",
        "sympy",
    ]);
    assert!(o.status.success());
    assert_eq!(stdout(&o).trim(), "l*theta_d*cos(theta)");
    let o = lagrange(&[
        "diff",
        "m*l**2*theta_d**2/2",
        "theta_d",
        "--format",
        "sympy",
    ]);
    assert_eq!(stdout(&o).trim(), "m*theta_d*l**2");
}

#[test]
fn a_malformed_expression_points_at_its_column() {
    let o = lagrange(&["simplify", "sin(x"]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(err.contains("column 4"), "{err}");
    assert!(err.contains("never closed"), "{err}");
    let o = lagrange(&["diff", "x", "2*y"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("not a variable"));
}

#[test]
fn check_summarises_every_seed_exercise() {
    for file in [
        "examples/seed/7.1-cart-pendulum.lag",
        "examples/seed/7.2-rolling-cone.lag",
        "examples/seed/7.3-gears-pendulum.lag",
        "examples/seed/7.4-inverted-pendulum.lag",
    ] {
        let o = lagrange(&["check", file]);
        assert!(o.status.success(), "{file}: {}", stderr(&o));
        assert!(stdout(&o).contains("degrees of freedom"), "{file}");
    }
}

#[test]
fn check_reports_several_errors_with_line_and_column() {
    let dir = std::env::temp_dir().join(format!("lagrange-cli-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("bad.lag");
    std::fs::write(
        &file,
        "coordinates theta\nframe N\npoint P = thta*N.x\nparticle Q mass m\n",
    )
    .unwrap();
    let o = lagrange(&["check", file.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(err.contains("bad.lag:3:11"), "{err}");
    assert!(err.contains("Did you mean `theta`?"), "{err}");
    assert!(err.contains("errors found"), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn solve_gives_the_seed_equations_of_motion_for_7_1() {
    let o = lagrange(&["solve", "examples/seed/7.1-cart-pendulum.lag"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains("(m_A + m_B) ẍ + m_B ℓ θ̈ cos θ − m_B ℓ θ̇² sin θ + k x = F"),
        "{out}"
    );
    assert!(out.contains("= C"), "{out}");
}

#[test]
fn a_missing_model_file_is_an_error_not_a_panic() {
    let o = lagrange(&["solve", "examples/does-not-exist.lag"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("cannot read the model file"));
}
