//! `lagrange draw`: the figure printed or written, `--at` values, and the exit codes (0 drawn,
//! 1 the input's mistake with its location, 5 the file cannot be written).

mod common;
use common::{lagrange, root, stderr, stdout};

#[test]
fn draw_prints_the_figure_and_writes_it_with_out() {
    let o = lagrange(&["draw", "examples/simple-pendulum.lag"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let printed = stdout(&o);
    assert!(printed.starts_with("<svg ") && printed.trim_end().ends_with("</svg>"));
    let dir = std::env::temp_dir().join(format!("lagrange-draw-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let file = dir.join("pendulum.svg");
    let out = file.to_string_lossy().into_owned();
    let o = lagrange(&["draw", "examples/simple-pendulum.lag", "--out", &out]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&file).expect("written"), printed);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn at_moves_the_state_drawn() {
    let plain = stdout(&lagrange(&["draw", "examples/seed/7.1-cart-pendulum.lag"]));
    let o = lagrange(&[
        "draw",
        "examples/seed/7.1-cart-pendulum.lag",
        "--at",
        "x=0.3,theta=-0.5",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_ne!(stdout(&o), plain);
    // The same state given twice, in two flags, draws the same figure.
    let again = lagrange(&[
        "draw",
        "examples/seed/7.1-cart-pendulum.lag",
        "--at",
        "x=0.3",
        "--at",
        "theta=-0.5",
    ]);
    assert_eq!(stdout(&again), stdout(&o));
}

#[test]
fn input_mistakes_exit_1_and_say_where() {
    let o = lagrange(&["draw", "examples/simple-pendulum.lag", "--at", "nope=1"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("--at nope=1"), "{}", stderr(&o));
    let o = lagrange(&["draw", "examples/simple-pendulum.lag", "--at", "t=soon"]);
    assert_eq!(o.status.code(), Some(1));
    let o = lagrange(&[
        "draw",
        "examples/simple-pendulum.lag",
        "--out",
        "figure.png",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains(".svg"), "{}", stderr(&o));
    let dir = std::env::temp_dir().join(format!("lagrange-draw-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let model = dir.join("broken.lag");
    std::fs::write(&model, "coordinates x\npoint P = y*N.x\n").expect("written");
    let o = lagrange(&["draw", &model.to_string_lossy()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("broken.lag:2:"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_model_file_is_never_overwritten_and_a_bad_output_exits_5() {
    let model = "examples/simple-pendulum.lag";
    let before = std::fs::read(root().join(model)).expect("the example");
    // Named as the model with an .svg extension refused first, so give the model itself a
    // copy whose name ends in .svg.
    let dir = std::env::temp_dir().join(format!("lagrange-draw-self-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let copy = dir.join("model.svg");
    std::fs::write(&copy, &before).expect("written");
    let path = copy.to_string_lossy().into_owned();
    let o = lagrange(&["draw", &path, "--out", &path]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("never writes over its input"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read(&copy).expect("still there"), before);
    let missing = dir.join("no/such/dir/figure.svg");
    let o = lagrange(&["draw", model, "--out", &missing.to_string_lossy()]);
    assert_eq!(o.status.code(), Some(5), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_committed_seed_figures_are_what_draw_makes() {
    for name in [
        "7.1-cart-pendulum",
        "7.2-rolling-cone",
        "7.3-gears-pendulum",
        "7.4-inverted-pendulum",
    ] {
        let o = lagrange(&["draw", &format!("examples/seed/{name}.lag")]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let committed = std::fs::read_to_string(root().join(format!("examples/seed/{name}.svg")))
            .expect("the figure is committed");
        assert!(
            stdout(&o) == committed,
            "examples/seed/{name}.svg is stale: run `lagrange draw examples/seed/{name}.lag --out examples/seed/{name}.svg`"
        );
    }
}

#[test]
fn animate_writes_a_page_and_refuses_bad_input() {
    let dir = std::env::temp_dir().join(format!("lagrange-animate-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let file = dir.join("pendulum.html");
    let out = file.to_string_lossy().into_owned();
    let o = lagrange(&[
        "animate",
        "examples/simple-pendulum.lag",
        "--t-end",
        "2",
        "--trace",
        "P",
        "--out",
        &out,
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let page = std::fs::read_to_string(&file).expect("written");
    assert!(page.starts_with("<!DOCTYPE html>") && page.contains("id=\"trace-P\""));
    let o = lagrange(&["animate", "examples/simple-pendulum.lag", "--out", "a.svg"]);
    assert_eq!(o.status.code(), Some(1));
    let o = lagrange(&["animate", "examples/simple-pendulum.lag", "--fps", "0"]);
    assert_eq!(o.status.code(), Some(1));
    let o = lagrange(&["animate", "examples/four-bar.lag", "--set", "nope=1"]);
    assert_eq!(o.status.code(), Some(1));
    let missing = dir.join("no/such/dir/a.html");
    let o = lagrange(&[
        "animate",
        "examples/simple-pendulum.lag",
        "--t-end",
        "1",
        "--out",
        &missing.to_string_lossy(),
    ]);
    assert_eq!(o.status.code(), Some(5), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&dir);
}
