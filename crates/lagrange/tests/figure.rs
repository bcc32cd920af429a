//! `Analysis::figure`: the values set on an analysis are the state drawn, and a coordinate a
//! constraint eliminates is drawn where the constraint puts it.

use std::path::Path;

use lagrange::{parse_assignment, Analysis};

fn example(name: &str) -> Analysis {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    Analysis::from_file(&path).expect("a valid example")
}

/// The page position of world point `p` in `figure`, and that of the drawn point `name`.
fn positions(figure: &lagrange::draw::Figure, name: &str, p: [f64; 3]) -> ((f64, f64), (f64, f64)) {
    let expected = figure.view.page(p);
    let marker = format!("id=\"point-{name}\"");
    let at = figure.svg.find(&marker).expect("the point is drawn");
    let tag = &figure.svg[figure.svg[..at].rfind('<').expect("tag")..];
    let tag = &tag[..tag.find('>').expect("closed")];
    let value = |key: &str| -> f64 {
        let from = tag.find(&format!(" {key}=\"")).expect("attribute") + key.len() + 3;
        tag[from..from + tag[from..].find('"').expect("quoted")]
            .parse()
            .expect("a number")
    };
    ((value("cx"), value("cy")), expected)
}

#[test]
fn the_figure_is_drawn_at_the_values_set() {
    let mut pendulum = example("simple-pendulum.lag");
    let drawn = pendulum.figure(0.0).expect("drawn");
    let (at, expected) = positions(&drawn, "P", [0.5f64.sin(), -0.5f64.cos(), 0.0]);
    assert!(
        (at.0 - expected.0).hypot(at.1 - expected.1) <= 1.0,
        "initial θ = 0.5"
    );
    pendulum
        .set(&parse_assignment("theta=2").expect("an assignment"))
        .expect("set");
    let drawn = pendulum.figure(0.0).expect("drawn");
    let (at, expected) = positions(&drawn, "P", [2f64.sin(), -2f64.cos(), 0.0]);
    assert!(
        (at.0 - expected.0).hypot(at.1 - expected.1) <= 1.0,
        "θ = 2 set"
    );
}

#[test]
fn an_eliminated_gear_angle_follows_its_driver() {
    let mut gears = example("seed/7.3-gears-pendulum.lag");
    gears
        .set(&parse_assignment("phi1=0.8").expect("an assignment"))
        .expect("set");
    let figure = gears.figure(0.0).expect("drawn");
    // φ₂ = r φ₁ (r = R1/R2 = 1/2): gear 2's radius line, along G2.x = N rotated −φ₂, is drawn
    // from its centre O2 = (0.3, 0) to O2 + R2 (cos φ₂, −sin φ₂).
    let phi2 = 0.4f64;
    let rim = [0.3 + 0.2 * phi2.cos(), -0.2 * phi2.sin(), 0.0];
    let expected = figure.view.page(rim);
    let found = figure.svg.split("<line ").skip(1).any(|t| {
        let t = &t[..t.find("/>").unwrap_or(t.len())];
        let get = |k: &str| -> Option<f64> {
            let from = t.find(&format!("{k}=\""))? + k.len() + 2;
            t[from..from + t[from..].find('"')?].parse().ok()
        };
        t.contains("class=\"radius\"")
            && matches!((get("x2"), get("y2")), (Some(x), Some(y)) if (x - expected.0).hypot(y - expected.1) <= 1.0)
    });
    assert!(found, "gear 2's radius line ends at {expected:?}");
}

#[test]
fn a_system_built_in_code_has_no_figure() {
    let system = lagrange::mechanics::System::new();
    let e = Analysis::from_system(system).figure(0.0);
    assert!(matches!(e, Err(lagrange::Error::NotAvailable(_))));
}

/// Frame `k` of an animation's page, rebuilt as its script does: the first frame's markup
/// with frame `k`'s numbers put back, or the frame's own markup.
fn frame(html: &str, k: usize) -> String {
    let line = |name: &str| -> serde_json::Value {
        let start = html.find(&format!("\nconst {name}=")).expect("the data") + name.len() + 8;
        let end = start + html[start..].find(";\n").expect("the end of the data");
        serde_json::from_str(&html[start..end]).expect("JSON")
    };
    let (template, frames) = (line("T"), line("F"));
    let f = &frames[k];
    if let Some(s) = f.as_str() {
        return s.to_owned();
    }
    let pieces = template.as_array().expect("pieces");
    let numbers = f.as_array().expect("numbers");
    let mut out = String::new();
    for (i, p) in pieces.iter().enumerate() {
        out.push_str(p.as_str().expect("text"));
        if let Some(x) = numbers.get(i) {
            out.push_str(&x.to_string());
        }
    }
    out
}

fn attribute(markup: &str, marker: &str, key: &str) -> f64 {
    let at = markup.find(marker).expect("the element");
    let tag = &markup[markup[..=at].rfind('<').expect("tag")..];
    let tag = &tag[..tag.find('>').expect("closed")];
    let from = tag.find(&format!(" {key}=\"")).expect("attribute") + key.len() + 3;
    tag[from..from + tag[from..].find('"').expect("quoted")]
        .trim()
        .parse()
        .expect("a number")
}

#[test]
fn the_animation_moves_the_bob_as_the_simulation_does_and_stays_small() {
    let cart = example("seed/7.1-cart-pendulum.lag");
    let html = cart
        .animation(Some(10.0), 30.0, &["B".to_owned()])
        .expect("animated");
    assert!(
        html.len() < 2_000_000,
        "{} bytes for 10 s at 30 fps",
        html.len()
    );
    assert!(
        html.contains("<script>") && !html.contains("src="),
        "self-contained"
    );
    assert!(html.contains("id=\"trace-B\""));
    let options = lagrange::SimulationOptions {
        t_end: Some(10.0),
        output_step: Some(1.0 / 30.0),
        ..lagrange::SimulationOptions::default()
    };
    let run = cart.simulate(&options).expect("simulated");
    assert_eq!(run.rows.len(), 301);
    let root = &html[html.find("<svg ").expect("the picture")..];
    let scale = attribute(root, "<svg ", "data-scale");
    let origin: Vec<f64> = {
        let at = root.find("data-origin=\"").expect("origin") + 13;
        root[at..at + root[at..].find('"').expect("quoted")]
            .split(' ')
            .map(|x| x.parse().expect("number"))
            .collect()
    };
    let mut seen = Vec::new();
    for k in [0, 40, 150, 300] {
        let markup = frame(&html, k);
        let (x, theta) = (run.rows[k][1], run.rows[k][2]);
        // B = (x + l sin θ, l cos θ) with l = 0.5; the page's up is −y (gravity is +y).
        let (bx, by) = (x + 0.5 * theta.sin(), 0.5 * theta.cos());
        let expected = (origin[0] + scale * bx, origin[1] + scale * by);
        let drawn = (
            attribute(&markup, "id=\"point-B\"", "cx"),
            attribute(&markup, "id=\"point-B\"", "cy"),
        );
        assert!(
            (drawn.0 - expected.0).hypot(drawn.1 - expected.1) <= 1.0,
            "frame {k}: B at {drawn:?}, the simulation puts it at {expected:?}"
        );
        seen.push(drawn);
    }
    assert!(seen.windows(2).all(|w| w[0] != w[1]), "the frames differ");
}

/// The values rows of an animation's page: the time, then each coordinate.
fn values(html: &str) -> Vec<Vec<f64>> {
    let start = html.find("\nconst Q=").expect("the values") + 9;
    let end = start + html[start..].find(";\n").expect("the end of the values");
    serde_json::from_str(&html[start..end]).expect("JSON")
}

#[test]
fn a_mode_animation_follows_the_mode_shape_at_its_frequency() {
    let double = example("double-pendulum.lag");
    let equilibria = double.equilibria().expect("equilibria");
    let (rest, linear) = equilibria
        .set
        .equilibria
        .iter()
        .zip(&equilibria.linearized)
        .find_map(|(e, l)| match l {
            Ok(l) if l.stable == Some(true) => Some((e.values.clone(), l)),
            _ => None,
        })
        .expect("the hanging equilibrium is stable");
    assert_eq!(equilibria.rest.coordinates, ["theta1", "theta2"]);
    for k in [1, 2] {
        let omega = linear.omega_squared.as_ref().expect("ω²")[k - 1].sqrt();
        let shape = &linear.modes[k - 1];
        let html = double
            .mode_animation(k, None, 30.0, &["P2".to_owned()])
            .expect("animated");
        // Three periods at 30 frames per second.
        let rows = values(&html);
        assert!(
            (rows.len() as f64 - 3.0 * std::f64::consts::TAU / omega * 30.0).abs() <= 2.0,
            "mode {k}: {} frames",
            rows.len()
        );
        let first = &rows[0];
        let amplitude = (first[1] - rest[0]) / shape[0];
        assert!(amplitude.abs() > 0.01, "a visible amplitude: {amplitude}");
        for i in [0, 7, 20, 33] {
            let row = &rows[i];
            let c = (omega * row[0]).cos();
            for j in 0..2 {
                let expected = rest[j] + amplitude * shape[j] * c;
                assert!(
                    (row[j + 1] - expected).abs() < 2e-4,
                    "mode {k}, frame {i}, coordinate {j}: {} against {expected}",
                    row[j + 1]
                );
            }
        }
        // The bob is drawn where the frame's coordinates put it (l1 = l2 = 1, y up).
        let root = &html[html.find("<svg ").expect("the picture")..];
        let scale = attribute(root, "<svg ", "data-scale");
        let at = root.find("data-origin=\"").expect("origin") + 13;
        let origin: Vec<f64> = root[at..at + root[at..].find('"').expect("quoted")]
            .split(' ')
            .map(|x| x.parse().expect("number"))
            .collect();
        let row = &rows[20];
        let (t1, t2) = (row[1], row[2]);
        let bob = (t1.sin() + t2.sin(), -t1.cos() - t2.cos());
        let expected = (origin[0] + scale * bob.0, origin[1] - scale * bob.1);
        let markup = frame(&html, 20);
        let drawn = (
            attribute(&markup, "id=\"point-P2\"", "cx"),
            attribute(&markup, "id=\"point-P2\"", "cy"),
        );
        assert!(
            (drawn.0 - expected.0).hypot(drawn.1 - expected.1) <= 1.0,
            "mode {k}: P2 drawn at {drawn:?}, the model puts it at {expected:?}"
        );
    }
    let none = double.mode_animation(3, None, 30.0, &[]);
    assert!(
        matches!(&none, Err(lagrange::Error::NotAvailable(m)) if m.contains("no mode 3")),
        "{none:?}"
    );
}

#[test]
fn without_a_stable_equilibrium_there_is_no_mode() {
    // A particle pushed away from the origin in proportion to its distance: one
    // equilibrium, unstable.
    let text = "coordinates x\nparameters m = 1, k = 2\nframe N\npoint P = x*N.x\n\
                particle P mass m\nforce k*x*N.x at P\ninitial x = 0.1\n";
    let unstable = Analysis::from_text(text).expect("a valid model");
    let e = unstable.mode_animation(1, None, 30.0, &[]);
    assert!(
        matches!(&e, Err(lagrange::Error::NotAvailable(m)) if m.contains("no stable equilibrium")),
        "{e:?}"
    );
}
