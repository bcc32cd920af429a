//! The `lagrange` binary, run for real: the symbolic-core commands, `check` and `solve` on the
//! seed's examples, and the exit codes and messages of bad input.

use std::process::Command;

mod common;
use common::{lagrange, stderr, stdout};

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
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(err.contains("column 4"), "{err}");
    assert!(err.contains("never closed"), "{err}");
    let o = lagrange(&["diff", "x", "2*y"]);
    assert_eq!(o.status.code(), Some(1));
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

#[test]
fn a_reader_that_stops_early_does_not_make_it_panic() {
    use std::io::Read;
    use std::process::Stdio;
    // A 12-link pendulum: its equations are larger than a pipe's buffer (64 KiB), so the
    // writer is still writing when the reader goes away.
    let n = 12;
    let mut model = String::from("coordinates ");
    model += &(1..=n)
        .map(|i| format!("th{i}"))
        .collect::<Vec<_>>()
        .join(", ");
    model += "\nparameters g = 9.81";
    for i in 1..=n {
        model += &format!(", m{i} = 1, l{i} = 1");
    }
    model += "\nframe N\n";
    for i in 1..=n {
        let prev = if i > 1 {
            format!("P{} + ", i - 1)
        } else {
            String::new()
        };
        model += &format!("point P{i} = {prev}l{i}*sin(th{i})*N.x - l{i}*cos(th{i})*N.y\n");
        model += &format!("particle P{i} mass m{i}\n");
    }
    model += "gravity -g*N.y\n";
    let path = std::env::temp_dir().join(format!("lagrange-pipe-{}.lag", std::process::id()));
    std::fs::write(&path, model).expect("temporary model written");
    let mut child = Command::new(env!("CARGO_BIN_EXE_lagrange"))
        .args([
            "eom".as_ref(),
            path.as_os_str(),
            "--format".as_ref(),
            "json".as_ref(),
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the lagrange binary runs");
    // Read one byte, then close the pipe as `head -c 1` would.
    let mut first = [0u8; 1];
    child
        .stdout
        .take()
        .expect("piped stdout")
        .read_exact(&mut first)
        .expect("some output");
    let mut err = String::new();
    child
        .stderr
        .take()
        .expect("piped stderr")
        .read_to_string(&mut err)
        .expect("stderr reads");
    child.wait().expect("the process ends");
    let _ = std::fs::remove_file(&path);
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn an_expression_may_start_with_a_minus() {
    let o = lagrange(&["simplify", "-x^2", "--format", "sympy"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stdout(&o).trim(), "-x**2");
    let o = lagrange(&["diff", "-x^2", "x", "--format", "sympy"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stdout(&o).trim(), "-2*x");
}
