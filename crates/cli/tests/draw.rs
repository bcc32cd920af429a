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
        "figure.pdf",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains(".svg or .png"), "{}", stderr(&o));
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
fn every_example_has_its_figure_committed_as_draw_makes_it() {
    let mut models = Vec::new();
    for dir in ["examples", "examples/seed", "examples/canonical"] {
        for entry in std::fs::read_dir(root().join(dir))
            .expect("examples/")
            .flatten()
        {
            let name = entry.file_name().to_string_lossy().into_owned();
            if let Some(stem) = name.strip_suffix(".lag") {
                models.push(format!("{dir}/{stem}"));
            }
        }
    }
    assert!(models.len() >= 20, "{models:?}");
    for name in models {
        let o = lagrange(&["draw", &format!("{name}.lag")]);
        assert_eq!(o.status.code(), Some(0), "{name}: {}", stderr(&o));
        let committed = std::fs::read_to_string(root().join(format!("{name}.svg")))
            .unwrap_or_else(|_| panic!("{name}.svg is not committed"));
        assert!(
            stdout(&o) == committed,
            "{name}.svg is stale: run `lagrange draw {name}.lag --out {name}.svg`"
        );
    }
}

#[test]
fn draw_writes_a_png_with_out() {
    let dir = std::env::temp_dir().join(format!("lagrange-draw-png-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let file = dir.join("cart.png");
    let o = lagrange(&[
        "draw",
        "examples/seed/7.1-cart-pendulum.lag",
        "--out",
        &file.to_string_lossy(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let png = std::fs::read(&file).expect("written");
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "a PNG");
    // The header's size is twice the SVG's, rounded up.
    let svg = stdout(&lagrange(&["draw", "examples/seed/7.1-cart-pendulum.lag"]));
    let at = svg.find("viewBox=\"").expect("a viewBox") + 9;
    let view: Vec<f64> = svg[at..at + svg[at..].find('"').expect("quoted")]
        .split(' ')
        .map(|x| x.parse().expect("a number"))
        .collect();
    let width = u32::from_be_bytes(png[16..20].try_into().expect("four bytes"));
    let height = u32::from_be_bytes(png[20..24].try_into().expect("four bytes"));
    assert_eq!(
        (f64::from(width), f64::from(height)),
        ((2.0 * view[2]).ceil(), (2.0 * view[3]).ceil())
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn animate_mode_writes_the_mode_and_refuses_a_missing_one() {
    let o = lagrange(&["animate", "examples/double-pendulum.lag", "--mode", "2"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let page = stdout(&o);
    assert!(page.starts_with("<!DOCTYPE html>") && page.contains("mode 2, ω = "));
    let o = lagrange(&["animate", "examples/double-pendulum.lag", "--mode", "3"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("no mode 3"), "{}", stderr(&o));
    let o = lagrange(&["animate", "examples/double-pendulum.lag", "--mode", "0"]);
    assert_eq!(o.status.code(), Some(1));
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

#[test]
fn solve_puts_the_figure_at_the_top_and_links_the_animation() {
    let dir = std::env::temp_dir().join(format!("lagrange-solve-figure-{}", std::process::id()));
    let model = "examples/simple-pendulum.lag";
    let figure = stdout(&lagrange(&["draw", model]));
    for format in ["md", "tex", "json"] {
        let out = dir.join(format);
        let o = lagrange(&[
            "solve",
            model,
            "--format",
            format,
            "--out",
            &out.to_string_lossy(),
        ]);
        assert_eq!(o.status.code(), Some(0), "{format}: {}", stderr(&o));
        let document = std::fs::read_to_string(out.join(format!("simple-pendulum.{format}")))
            .expect("the document");
        match format {
            "md" => {
                let top = document
                    .find("## The system\n\n")
                    .expect("the first section")
                    + 15;
                assert!(
                    document[top..].starts_with(
                        "```{figure} simple-pendulum.svg\nThe system at its initial state.\n```\n\n\
                         [The motion, animated (opens in a browser)](simple-pendulum.html)\n"
                    ),
                    "{document}"
                );
                let svg = std::fs::read_to_string(out.join("simple-pendulum.svg")).expect("svg");
                assert_eq!(svg, figure);
                let page = std::fs::read_to_string(out.join("simple-pendulum.html")).expect("html");
                assert!(page.starts_with("<!DOCTYPE html>") && page.contains("point-P"));
            }
            "tex" => {
                let at = document.find("\\includegraphics").expect("a figure");
                assert!(document[at..]
                    .starts_with("\\includegraphics[width=0.5\\textwidth]{simple-pendulum.png}"));
                assert!(at < document.find("Generalized coordinates").expect("the text"));
                let png = std::fs::read(out.join("simple-pendulum.png")).expect("png");
                assert!(png.starts_with(b"\x89PNG"));
            }
            _ => {
                let value: serde_json::Value = serde_json::from_str(&document).expect("JSON");
                let blocks = &value["report"]["sections"][0]["blocks"];
                assert_eq!(blocks[0]["kind"], "figure");
                assert_eq!(blocks[0]["path"], "simple-pendulum.svg");
                assert_eq!(blocks[1]["kind"], "link");
                assert_eq!(blocks[1]["path"], "simple-pendulum.html");
                for file in ["simple-pendulum.svg", "simple-pendulum.html"] {
                    assert!(out.join(file).is_file(), "{file} written");
                }
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn animate_mode_at_a_pole_of_the_coordinates_and_without_a_rest() {
    // The spherical pendulum's bottom is a pole of its coordinates (φ moves nothing there):
    // its mode is the swing, and the second is refused with the reason.
    let o = lagrange(&["animate", "examples/spherical-pendulum.lag", "--mode", "1"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stdout(&o).contains("mode 1, ω = 3.1321 rad/s"));
    let o = lagrange(&["animate", "examples/spherical-pendulum.lag", "--mode", "2"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("no mode 2") && stderr(&o).contains("moving phi alone moves nothing"),
        "{}",
        stderr(&o)
    );
    let o = lagrange(&["animate", "examples/heavy-symmetric-top.lag", "--mode", "2"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stdout(&o).contains("mode 2, ω = 11.0736 rad/s"));
    let o = lagrange(&[
        "animate",
        "examples/rolling-disk-incline.lag",
        "--mode",
        "1",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("has no equilibrium"), "{}", stderr(&o));
}
