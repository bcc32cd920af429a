//! Issue 14: the work limits of the symbolic core on the command line. Past a limit a command
//! exits 2 with the model line being derived and how to go on (`--work-limit`), quickly; two
//! `gravity` statements no longer make the reactions disagree (exit 4).

mod common;
use common::{lagrange, stderr, stdout};

const MODEL: &str = "examples/double-pendulum.lag";

#[test]
fn a_derivation_past_the_work_limit_exits_2_at_its_line_and_the_flag_raises_it() {
    let tight = lagrange(&["--work-limit", "0.0001", "eom", MODEL]);
    assert_eq!(tight.status.code(), Some(2), "{}", stderr(&tight));
    let err = stderr(&tight);
    let located = regex_free_location(&err, "double-pendulum.lag:");
    assert!(located, "no line:column in {err}");
    assert!(
        err.contains("work limit") && err.contains("--work-limit 10"),
        "{err}"
    );
    // The flag goes after the command too (it is global), and the default limits suffice.
    let normal = lagrange(&["eom", MODEL, "--work-limit", "1"]);
    assert_eq!(normal.status.code(), Some(0), "{}", stderr(&normal));
    let bad = lagrange(&["--work-limit", "-3", "eom", MODEL]);
    assert_eq!(bad.status.code(), Some(1), "{}", stderr(&bad));
}

/// Whether `text` has `prefix` followed by `LINE:COLUMN:`.
fn regex_free_location(text: &str, prefix: &str) -> bool {
    text.split(prefix).skip(1).any(|rest| {
        let mut parts = rest.splitn(3, ':');
        let (line, column) = (parts.next(), parts.next());
        [line, column]
            .iter()
            .all(|p| p.is_some_and(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit())))
    })
}

#[test]
fn simplify_of_a_sine_of_21_terms_is_refused_by_the_limit() {
    let angle: Vec<String> = (0..21).map(|i| format!("a{i}")).collect();
    let expr = format!("sin({})", angle.join("+"));
    let o = lagrange(&["simplify", &expr]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("max_terms"), "{}", stderr(&o));
    assert!(stdout(&o).is_empty());
    // A smaller one is expanded as before.
    let o = lagrange(&["simplify", "--format", "sympy", "sin(a+b) - sin(a)*cos(b)"]);
    assert_eq!(stdout(&o).trim(), "sin(b)*cos(a)");
}

#[test]
fn two_gravity_statements_do_not_make_the_reactions_disagree() {
    let text = std::fs::read_to_string(common::root().join("examples/simple-pendulum.lag"))
        .expect("the example")
        .replace("gravity -g*N.y", "gravity -g*N.y\ngravity -g*N.y");
    let dir = std::env::temp_dir().join(format!("lagrange-gravity-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a directory");
    let path = dir.join("two-gravities.lag");
    std::fs::write(&path, text).expect("written");
    let o = lagrange(&["reactions", path.to_str().expect("a path")]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains("2 g cos θ") && out.contains("agree exactly"),
        "{out}"
    );
}
