//! Figures checked against the model: a drawn point sits where the model puts it (to within a
//! pixel at the figure's scale), labels never overlap, and every example draws.
//!
//! The SVG is read back as text: the root's `data-scale`, `data-origin`, `data-u`, `data-v`
//! give the projection, `id="point-NAME"` circles the drawn points, `data-box` each label's box.
//! Expected positions are written out by hand from each model's definition.

use std::path::{Path, PathBuf};

use draw::Configuration;

fn examples() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut files = Vec::new();
    let mut stack = vec![root];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir)
            .expect("examples/ is readable")
            .flatten()
        {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "lag") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

fn load(name: &str) -> model::Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    let text = std::fs::read_to_string(&path).expect("the example exists");
    model::load(&text).expect("a valid example")
}

/// The model's initial values, in coordinate order (0 where none is given).
fn initial(model: &model::Model) -> Vec<f64> {
    model
        .coordinates()
        .iter()
        .map(|c| model.initial_value(&c.name.name, false).unwrap_or(0.0))
        .collect()
}

/// The value of attribute `name` in the tag that contains `marker`.
fn attribute(svg: &str, marker: &str, name: &str) -> String {
    let at = svg
        .find(marker)
        .unwrap_or_else(|| panic!("no {marker} in the SVG"));
    let start = svg[..=at].rfind('<').expect("a tag");
    let end = at + svg[at..].find('>').expect("a closed tag");
    let tag = &svg[start..end];
    let key = format!(" {name}=\"");
    let from = tag
        .find(&key)
        .unwrap_or_else(|| panic!("no {name} in {tag}"))
        + key.len();
    tag[from..from + tag[from..].find('"').expect("a quoted value")].to_owned()
}

fn numbers(text: &str) -> Vec<f64> {
    text.split_whitespace()
        .map(|x| x.parse().expect("a number"))
        .collect()
}

/// Where the SVG says the world point `p` is drawn, from its projection attributes.
fn page(svg: &str, p: [f64; 3]) -> (f64, f64) {
    let root = "<svg ";
    let scale: f64 = attribute(svg, root, "data-scale").parse().expect("scale");
    let origin = numbers(&attribute(svg, root, "data-origin"));
    let u = numbers(&attribute(svg, root, "data-u"));
    let v = numbers(&attribute(svg, root, "data-v"));
    let dot = |a: &[f64]| a[0] * p[0] + a[1] * p[1] + a[2] * p[2];
    (origin[0] + scale * dot(&u), origin[1] - scale * dot(&v))
}

/// The centre of the drawn point `name`.
fn drawn(svg: &str, name: &str) -> (f64, f64) {
    let marker = format!("id=\"point-{name}\"");
    (
        attribute(svg, &marker, "cx").parse().expect("cx"),
        attribute(svg, &marker, "cy").parse().expect("cy"),
    )
}

fn assert_within_a_pixel(svg: &str, name: &str, expected: [f64; 3]) {
    let (x, y) = drawn(svg, name);
    let (ex, ey) = page(svg, expected);
    assert!(
        (x - ex).hypot(y - ey) <= 1.0,
        "{name} drawn at ({x}, {y}), the model puts it at ({ex}, {ey})"
    );
}

fn figure(model: &model::Model, coordinates: Vec<f64>) -> draw::Figure {
    draw::figure(
        model,
        Configuration {
            time: 0.0,
            coordinates,
        },
    )
    .expect("drawn")
}

#[test]
fn the_pendulum_bob_is_drawn_where_the_model_puts_it() {
    let model = load("simple-pendulum.lag");
    for theta in [0.5, -1.2, 2.8] {
        let f = figure(&model, vec![theta]);
        // P = l sin θ N.x − l cos θ N.y with l = 1.
        assert_within_a_pixel(&f.svg, "P", [theta.sin(), -theta.cos(), 0.0]);
        // The pivot is drawn at the origin, and the rod is l long on the page.
        assert_within_a_pixel(&f.svg, "O", [0.0; 3]);
        let (p, o) = (drawn(&f.svg, "P"), drawn(&f.svg, "O"));
        let scale: f64 = attribute(&f.svg, "<svg ", "data-scale")
            .parse()
            .expect("scale");
        assert!(((p.0 - o.0).hypot(p.1 - o.1) - scale).abs() <= 1.0);
    }
}

#[test]
fn the_cart_and_its_bob_are_drawn_where_the_model_puts_them() {
    let model = load("seed/7.1-cart-pendulum.lag");
    let (x, theta, l) = (0.25, -0.7, 0.5);
    let f = figure(&model, vec![x, theta]);
    // A = x N.x, B = A + l sin θ N.x + l cos θ N.y; gravity is +y, so the page's up is −y.
    assert_within_a_pixel(&f.svg, "A", [x, 0.0, 0.0]);
    assert_within_a_pixel(&f.svg, "B", [x + l * theta.sin(), l * theta.cos(), 0.0]);
    let (a, b) = (drawn(&f.svg, "A"), drawn(&f.svg, "B"));
    assert!(b.1 > a.1, "the bob hangs below the cart on the page");
    assert!(f.svg.contains("id=\"block-A\""), "the cart is a block");
}

#[test]
fn a_gear_rim_point_turns_with_its_gear() {
    let model = load("seed/7.3-gears-pendulum.lag");
    let (phi1, r1) = (0.7, 0.1);
    let f = figure(&model, vec![phi1, 0.0, 0.2]);
    // P = O1 + R1 G1.x with G1 = N rotated φ₁ about z.
    assert_within_a_pixel(&f.svg, "P", [r1 * phi1.cos(), r1 * phi1.sin(), 0.0]);
    // The gears mesh: radii R1 = 0.1 and R2 = 0.2 from the gear ratio and the axles' distance.
    let scale: f64 = attribute(&f.svg, "<svg ", "data-scale")
        .parse()
        .expect("scale");
    for (body, radius) in [("gear1", 0.1), ("gear2", 0.2)] {
        let r: f64 = attribute(&f.svg, &format!("id=\"body-{body}\""), "r")
            .parse()
            .expect("r");
        assert!((r - radius * scale).abs() <= 0.5, "{body}: r = {r}");
    }
}

#[test]
fn a_spatial_system_is_drawn_in_oblique_projection_with_its_axes() {
    let model = load("spherical-pendulum.lag");
    let (phi, theta) = (0.4, 0.8);
    let f = figure(&model, vec![phi, theta]);
    assert!(!f.view.planar);
    for axis in ["N.x", "N.y", "N.z"] {
        assert!(f.svg.contains(&format!(">{axis}</text>")), "axis {axis}");
    }
    // P = −l B.z, B = N rotated φ about z then θ about x: B.z = (sin φ sin θ, −cos φ sin θ, cos θ).
    let p = [
        -(phi.sin() * theta.sin()),
        phi.cos() * theta.sin(),
        -theta.cos(),
    ];
    assert_within_a_pixel(&f.svg, "P", p);
}

#[test]
fn each_coordinate_is_marked_with_its_symbol() {
    for (name, symbols) in [
        ("seed/7.1-cart-pendulum.lag", &["x", "θ"][..]),
        ("double-pendulum.lag", &["θ₁", "θ₂"][..]),
        ("four-bar.lag", &["θ₁", "θ₂", "θ₃"][..]),
        ("heavy-symmetric-top.lag", &["ψ", "θ", "φ"][..]),
        ("rolling-disk-incline.lag", &["x", "φ"][..]),
    ] {
        let model = load(name);
        let f = figure(&model, initial(&model));
        assert!(
            f.scene.unmarked.is_empty(),
            "{name}: {:?}",
            f.scene.unmarked
        );
        for s in symbols {
            let marked =
                f.svg.split("<text ").skip(1).any(|t| {
                    t.contains("class=\"coordinate\"") && t.contains(&format!(">{s}</text>"))
                });
            assert!(marked, "{name}: no mark for {s}");
        }
    }
}

fn boxes(svg: &str) -> Vec<[f64; 4]> {
    svg.match_indices("data-box=\"")
        .map(|(at, key)| {
            let from = at + key.len();
            let text = &svg[from..from + svg[from..].find('"').expect("quoted")];
            let n = numbers(text);
            [n[0], n[1], n[2], n[3]]
        })
        .collect()
}

#[test]
fn every_example_draws_with_labels_apart_and_inside_the_picture() {
    let files = examples();
    assert!(files.len() >= 20, "examples found: {}", files.len());
    for path in files {
        let text = std::fs::read_to_string(&path).expect("readable");
        let model = model::load(&text).expect("a valid example");
        let f = figure(&model, initial(&model));
        let svg = &f.svg;
        let name = path.display();
        assert!(
            svg.starts_with("<svg ") && svg.ends_with("</svg>\n"),
            "{name}"
        );
        assert!(
            !svg.contains("NaN") && !svg.contains("inf"),
            "{name}: a number is not finite"
        );
        assert_eq!(
            svg,
            &figure(&model, initial(&model)).svg,
            "{name}: not deterministic"
        );
        let view = numbers(&attribute(svg, "<svg ", "viewBox"));
        let labels = boxes(svg);
        assert_eq!(labels.len(), f.labels.len(), "{name}");
        assert!(
            f.touching.is_empty(),
            "{name}: labels on the drawing: {:?}",
            f.touching
        );
        for (i, a) in labels.iter().enumerate() {
            assert!(
                a[0] >= view[0]
                    && a[1] >= view[1]
                    && a[0] + a[2] <= view[0] + view[2]
                    && a[1] + a[3] <= view[1] + view[3],
                "{name}: label {i} outside the picture"
            );
            for b in &labels[i + 1..] {
                let apart = a[0] + a[2] <= b[0]
                    || b[0] + b[2] <= a[0]
                    || a[1] + a[3] <= b[1]
                    || b[1] + b[3] <= a[1];
                assert!(apart, "{name}: labels {a:?} and {b:?} overlap");
            }
        }
    }
}

#[test]
fn a_wrong_configuration_is_refused() {
    let model = load("simple-pendulum.lag");
    let e = draw::figure(
        &model,
        Configuration {
            time: 0.0,
            coordinates: vec![0.1, 0.2],
        },
    );
    assert!(matches!(
        e,
        Err(draw::DrawError::State {
            given: 2,
            needed: 1
        })
    ));
    let e = draw::figure(
        &model,
        Configuration {
            time: 0.0,
            coordinates: vec![f64::NAN],
        },
    );
    assert!(e.is_err());
}

#[test]
fn the_png_is_the_svg_painted() {
    let model = load("simple-pendulum.lag");
    let f = figure(&model, vec![0.5]);
    let scale = 2.0;
    let image = tiny_skia::Pixmap::decode_png(&f.png(scale).expect("painted")).expect("a PNG");
    let view = numbers(&attribute(&f.svg, "<svg ", "viewBox"));
    assert_eq!(
        (image.width(), image.height()),
        (
            (view[2] * scale).ceil() as u32,
            (view[3] * scale).ceil() as u32
        )
    );
    // The pixel of an image point (x, y) in SVG pixels.
    let pixel = |x: f64, y: f64| {
        let (i, j) = (
            ((x - view[0]) * scale) as u32,
            ((y - view[1]) * scale) as u32,
        );
        let p = image.pixel(i, j).expect("inside the image");
        [p.red(), p.green(), p.blue()]
    };
    let ink = |c: [u8; 3]| c.iter().all(|v| *v < 100);
    let (bx, by) = drawn(&f.svg, "P");
    assert!(
        ink(pixel(bx, by)),
        "the bob is painted: {:?}",
        pixel(bx, by)
    );
    // The rod is painted halfway between the pivot and the bob.
    let (ox, oy) = drawn(&f.svg, "O");
    let middle = pixel(0.5 * (bx + ox), 0.5 * (by + oy));
    assert!(ink(middle), "the rod is painted: {middle:?}");
    assert_eq!(
        pixel(view[0] + 1.0, view[1] + 1.0),
        [255, 255, 255],
        "white paper"
    );
    // Every label is painted inside its box: some pixel there is not white.
    for b in boxes(&f.svg) {
        let painted = (0..b[2] as usize).any(|dx| {
            (0..b[3] as usize).any(|dy| pixel(b[0] + dx as f64, b[1] + dy as f64) != [255; 3])
        });
        assert!(painted, "the label in {b:?} is painted");
    }
    assert!(matches!(f.png(1e6), Err(draw::RasterError::Size { .. })));
}
