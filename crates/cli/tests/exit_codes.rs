//! The exit-code contract of docs/cli.md, for every command: 0 done, 1 the user's mistake,
//! 2 degenerate or unsupported mechanics, 3 a simulation that failed part-way, 5 output that
//! could not be written. (4, lagrange disagreeing with itself, has no input that makes it
//! happen: it is what a bug would give.)

mod common;
use common::{lagrange, root, stderr};

fn temp(name: &str, text: &str) -> String {
    let dir = std::env::temp_dir().join(format!("lagrange-exit-codes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("the file is written");
    path.to_str().expect("a path").to_owned()
}

fn code(args: &[&str]) -> (Option<i32>, String) {
    let o = lagrange(args);
    (o.status.code(), stderr(&o))
}

const GOOD: &str = "examples/seed/7.1-cart-pendulum.lag";

/// Every command that reads a model, with the arguments that make it work on `GOOD`.
fn model_commands() -> Vec<Vec<&'static str>> {
    vec![
        vec!["solve"],
        vec!["check"],
        vec!["eom"],
        vec!["equilibria"],
        vec!["linearize"],
        vec!["simulate", "--t-end", "0.1"],
    ]
}

#[test]
fn success_is_zero_for_every_command() {
    for args in model_commands() {
        let mut all = vec![args[0], GOOD];
        all.extend(&args[1..]);
        let (code, err) = code(&all);
        assert_eq!(code, Some(0), "{all:?}: {err}");
    }
    assert_eq!(
        code(&["reactions", "examples/cartesian-pendulum.lag"]).0,
        Some(0)
    );
    assert_eq!(code(&["simplify", "sin(x)^2 + cos(x)^2"]).0, Some(0));
    assert_eq!(code(&["diff", "x^2", "x"]).0, Some(0));
    assert_eq!(code(&["--help"]).0, Some(0));
}

#[test]
fn a_users_mistake_is_one_for_every_command() {
    let bad = temp("bad.lag", "coordinates x\nframe N\npoint P = y*N.x\n");
    let commands = model_commands();
    for args in commands.iter().chain(&[vec!["reactions"]]) {
        // A model with an error, a missing file, an unknown `--set` name, a bad value.
        for (model, set) in [
            (bad.as_str(), None),
            ("examples/does-not-exist.lag", None),
            (GOOD, Some("nope=1")),
            (GOOD, Some("k=1+")),
        ] {
            let mut all = vec![args[0], model];
            all.extend(&args[1..]);
            if let Some(set) = set {
                if args[0] == "check" {
                    continue;
                }
                all.extend(["--set", set]);
            }
            let (code, err) = code(&all);
            assert_eq!(code, Some(1), "{all:?}: {err}");
            assert!(err.contains("error"), "{all:?}: {err}");
        }
    }
    assert_eq!(code(&["simplify", "sin(x"]).0, Some(1));
    assert_eq!(code(&["diff", "x", "2*y"]).0, Some(1));
    assert_eq!(code(&["eom"]).0, Some(1), "a missing argument");
    assert_eq!(code(&["frobnicate"]).0, Some(1), "an unknown command");
    assert_eq!(code(&["simulate", GOOD, "--rtol", "2"]).0, Some(1));
    assert_eq!(code(&["equilibria", GOOD, "--range", "x=2..1"]).0, Some(1));
    // What describes one run, asked of a sweep: refused before any run, the flags named.
    let sweep = [
        "simulate", GOOD, "--t-end", "0.1", "--sweep", "k=10..20", "--steps", "1",
    ];
    for extra in [
        ["--plot", "run.svg"],
        ["--summary", "s.json"],
        ["--record-when", "x"],
    ] {
        let (code, err) = code(&[&sweep[..], &extra[..]].concat());
        assert_eq!(code, Some(1), "{extra:?}: {err}");
        assert!(
            err.contains(extra[0]) && err.contains("--sweep"),
            "{extra:?}: {err}"
        );
    }
    // A bifurcation diagram to a file type no plot is written as.
    let plot = [
        "--sweep",
        "k=10..20",
        "--steps",
        "1",
        "--plot",
        "diagram.pdf",
    ];
    let (code, err) = code(&[&["equilibria", GOOD][..], &plot[..]].concat());
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains(".svg or .png"), "{err}");
}

#[test]
fn degenerate_mechanics_is_two() {
    // `y` appears nowhere: the mass matrix is singular.
    let singular = temp(
        "singular-mass.lag",
        "coordinates x, y\nparameters m = 1\nframe N\npoint P = x*N.x\nparticle P mass m\nsimulate to 1\n",
    );
    for args in model_commands() {
        if args[0] == "check" {
            continue;
        }
        let mut all = vec![args[0], singular.as_str()];
        all.extend(&args[1..]);
        let (code, err) = code(&all);
        assert_eq!(code, Some(2), "{all:?}: {err}");
        assert!(err.contains("singular"), "{all:?}: {err}");
    }
}

#[test]
fn contradictory_constraints_are_two_and_named() {
    let model = temp(
        "contradictory.lag",
        "coordinates x, y\nparameters m = 1\nframe N\npoint P = x*N.x + y*N.y\nparticle P mass m\n\
         constraint a: x = 1\nconstraint b: x = 2\nreactions a, b\nsimulate to 1\n",
    );
    for command in ["eom", "reactions", "solve", "simulate"] {
        let (code, err) = code(&[command, &model]);
        assert_eq!(code, Some(2), "{command}: {err}");
        assert!(err.contains("`a`, `b` cannot all hold"), "{command}: {err}");
    }
}

#[test]
fn a_run_that_fails_part_way_is_three() {
    // The mass matrix 4 m x² vanishes at x = 0, which the motion reaches at t = 1/2.
    let model = temp(
        "blow-up.lag",
        "coordinates x\nparameters m = 1\nframe N\npoint P = x^2*N.x\nparticle P mass m\n\
         initial x = 1, x' = -1\nsimulate to 2\n",
    );
    assert_eq!(code(&["simulate", &model]).0, Some(3));
}

#[cfg(target_os = "linux")]
#[test]
fn output_that_cannot_be_written_is_five_not_a_panic() {
    use std::process::{Command, Stdio};
    for args in [
        vec!["solve", GOOD],
        vec!["check", GOOD],
        vec!["eom", GOOD],
        vec!["equilibria", GOOD],
        vec!["simplify", "x"],
        vec!["draw", GOOD],
        vec!["animate", GOOD, "--t-end", "0.1"],
        vec!["simulate", GOOD, "--t-end", "0.1"],
        vec![
            "simulate", GOOD, "--t-end", "0.1", "--sweep", "k=10..20", "--steps", "1",
        ],
    ] {
        let full = std::fs::File::create("/dev/full").expect("/dev/full");
        let o = Command::new(env!("CARGO_BIN_EXE_lagrange"))
            .args(&args)
            .current_dir(root())
            .stdout(Stdio::from(full))
            .output()
            .expect("runs");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(5), "{args:?}: {err}");
        assert!(err.contains("cannot write"), "{args:?}: {err}");
    }
}

#[test]
fn the_model_file_is_never_an_output() {
    let model = temp(
        "keep-me.lag",
        &std::fs::read_to_string(root().join(GOOD)).expect("reads"),
    );
    let before = std::fs::read_to_string(&model).expect("reads");
    for flag in ["--out", "--summary", "--events"] {
        let (code, err) = code(&["simulate", &model, "--t-end", "0.1", flag, &model]);
        assert_eq!(code, Some(1), "{flag}: {err}");
        assert!(err.contains("never writes over its input"), "{err}");
    }
    // `solve --out DIR` into the model's own directory, the report named like the model.
    let dir = std::path::Path::new(&model).parent().expect("a directory");
    let tex = dir.join("keep-me.tex");
    std::fs::write(&tex, "old").expect("written");
    let o = lagrange(&[
        "solve",
        &model,
        "--format",
        "tex",
        "--out",
        dir.to_str().expect("dir"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("replacing"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&model).expect("reads"), before);
    // A model named like the report it would write.
    let named = temp("report.md", &before);
    let (code, err) = code(&[
        "solve",
        &named,
        "--format",
        "md",
        "--out",
        dir.to_str().expect("dir"),
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert_eq!(std::fs::read_to_string(&named).expect("reads"), before);
}

/// `draw` and `animate` (issue 16, after the contract was written) keep it too.
#[test]
fn drawing_and_animating_keep_the_contract() {
    assert_eq!(code(&["draw", GOOD]).0, Some(0));
    assert_eq!(code(&["animate", GOOD, "--t-end", "0.1"]).0, Some(0));
    let bad = temp("bad-draw.lag", "coordinates x\nframe N\npoint P = y*N.x\n");
    for args in [
        vec!["draw", bad.as_str()],
        vec!["draw", "examples/does-not-exist.lag"],
        vec!["draw", GOOD, "--at", "nope=1"],
        vec!["draw", GOOD, "--at", "t=soon"],
        vec!["draw", GOOD, "--out", "figure.pdf"],
        vec!["animate", bad.as_str()],
        vec!["animate", GOOD, "--set", "nope=1"],
        vec!["animate", GOOD, "--fps", "0"],
        vec!["animate", GOOD, "--out", "movie.svg"],
    ] {
        let (code, err) = code(&args);
        assert_eq!(code, Some(1), "{args:?}: {err}");
        assert!(err.contains("error"), "{args:?}: {err}");
    }
    // `y` appears nowhere: the mass matrix is singular, so there is no motion to animate.
    let singular = temp(
        "singular-animate.lag",
        "coordinates x, y\nparameters m = 1\nframe N\npoint P = x*N.x\nparticle P mass m\nsimulate to 1\n",
    );
    let (code, err) = code(&["animate", &singular]);
    assert_eq!(code, Some(2), "{err}");
}
