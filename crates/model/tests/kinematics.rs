//! The kinematics of the example models, checked numerically with [`Model::evaluate`]: the
//! reconstructions of the seed exercises satisfy the relations the seed states (the rolling
//! cone's contact point is on the plane and at rest under the seed's rolling relation; the
//! gears' contact speeds match), and the classic systems keep their rod lengths.

use std::path::Path;

use model::{Axis, Declaration, Expr, ExprKind, Model, State, Type};

fn load(file: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(file);
    let source = std::fs::read_to_string(&path).expect("example");
    model::load(&source).unwrap_or_else(|e| panic!("{}", model::render_short(&e.0, file, &source)))
}

fn synthetic(kind: ExprKind, ty: Type) -> Expr {
    Expr {
        kind,
        span: model::Span::default(),
        ty,
    }
}

fn point(model: &Model, name: &str) -> Expr {
    let id = match model.find(name) {
        Some(Declaration::Point(id)) => id,
        _ if name == "origin" => model::PointId::ORIGIN,
        _ => panic!("no point {name}"),
    };
    synthetic(ExprKind::Point(id), Type::Vector)
}

fn unit(model: &Model, frame: &str, axis: Axis) -> Expr {
    let Some(Declaration::Frame(id)) = model.find(frame) else {
        panic!("no frame {frame}")
    };
    synthetic(ExprKind::UnitVector { frame: id, axis }, Type::Vector)
}

fn parameter(model: &Model, name: &str) -> f64 {
    let Some(Declaration::Parameter(id)) = model.find(name) else {
        panic!("no parameter {name}")
    };
    model
        .evaluate_constant(model.parameter(id).value.as_ref().expect("a value"))
        .expect("a number")
}

fn coordinate(model: &Model, name: &str) -> usize {
    let Some(Declaration::Coordinate(id)) = model.find(name) else {
        panic!("no coordinate {name}")
    };
    id.index()
}

fn vector(model: &Model, expr: &Expr, state: &State<'_>) -> [f64; 3] {
    model
        .evaluate(expr, state)
        .expect("evaluates")
        .vector()
        .expect("a vector")
}

/// Position and velocity (by central difference along q(t) = q + q' (t − t0)) of `expr`.
fn motion(model: &Model, expr: &Expr, q: &[f64], rates: &[f64]) -> ([f64; 3], [f64; 3]) {
    let h = 1e-6;
    let shifted = |dt: f64| -> Vec<f64> { q.iter().zip(rates).map(|(q, r)| q + r * dt).collect() };
    let at = |dt: f64| {
        let coordinates = shifted(dt);
        vector(
            model,
            expr,
            &State {
                time: dt,
                coordinates: &coordinates,
                rates,
            },
        )
    };
    let (before, after) = (at(-h), at(h));
    let velocity = [0, 1, 2].map(|i| (after[i] - before[i]) / (2.0 * h));
    (at(0.0), velocity)
}

/// Angular velocity of a frame: ω = ½ Σᵢ eᵢ × ėᵢ.
fn angular_velocity(model: &Model, frame: &str, q: &[f64], rates: &[f64]) -> [f64; 3] {
    let mut omega = [0.0; 3];
    for axis in [Axis::X, Axis::Y, Axis::Z] {
        let (e, de) = motion(model, &unit(model, frame, axis), q, rates);
        let c = cross(e, de);
        for i in 0..3 {
            omega[i] += 0.5 * c[i];
        }
    }
    omega
}

fn cross(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

fn sub(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    [u[0] - v[0], u[1] - v[1], u[2] - v[2]]
}

fn add(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    [u[0] + v[0], u[1] + v[1], u[2] + v[2]]
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Velocity of the material point of a body (frame `frame`, centre `centre`) at `at`.
fn material_velocity(
    model: &Model,
    frame: &str,
    centre: &str,
    at: &str,
    q: &[f64],
    rates: &[f64],
) -> [f64; 3] {
    let (c, vc) = motion(model, &point(model, centre), q, rates);
    let (a, _) = motion(model, &point(model, at), q, rates);
    add(
        vc,
        cross(angular_velocity(model, frame, q, rates), sub(a, c)),
    )
}

/// A few fixed, irregular sample values.
const SAMPLES: [f64; 5] = [0.3, -1.2, 2.5, 0.05, -2.9];

#[test]
fn rolling_cone_contact_point_is_on_the_plane_and_rolls_as_the_seed_says() {
    let model = load("seed/7.2-rolling-cone.lag");
    let (d, alpha) = (parameter(&model, "d"), parameter(&model, "alpha"));
    let (r, b) = (d * alpha.sin(), d * alpha.cos().powi(2));
    let (theta, phi) = (coordinate(&model, "theta"), coordinate(&model, "phi"));
    for (i, &angle) in SAMPLES.iter().enumerate() {
        let mut q = [0.0; 2];
        q[theta] = angle;
        q[phi] = SAMPLES[(i + 2) % 5];
        let theta_rate = SAMPLES[(i + 1) % 5];
        // The seed's rolling relation: R φ' = (R sin α + b) θ'.
        let mut rates = [0.0; 2];
        rates[theta] = theta_rate;
        rates[phi] = (r * alpha.sin() + b) / r * theta_rate;
        let (a, _) = motion(&model, &point(&model, "A"), &q, &rates);
        assert!(a[2].abs() < 1e-12, "A is on the plane z = 0: {a:?}");
        assert!(
            (norm(a) - d).abs() < 1e-12,
            "A is on the rim, at distance d from the apex"
        );
        let v = material_velocity(&model, "B", "C", "A", &q, &rates);
        assert!(norm(v) < 1e-7, "the contact point is at rest: {v:?}");
        // And with any other spin rate it slides.
        rates[phi] += 0.5;
        assert!(norm(material_velocity(&model, "B", "C", "A", &q, &rates)) > 1e-3);
    }
}

#[test]
fn gears_contact_speeds_match_with_the_seed_ratio() {
    let model = load("seed/7.3-gears-pendulum.lag");
    let (r1, r2) = (parameter(&model, "R1"), parameter(&model, "R2"));
    let (phi1, phi2) = (coordinate(&model, "phi1"), coordinate(&model, "phi2"));
    for &rate in &SAMPLES {
        let mut q = [0.0; 3];
        q[phi1] = 0.7 * rate;
        q[phi2] = -0.4 * rate;
        let mut rates = [0.0; 3];
        rates[phi1] = rate;
        rates[phi2] = r1 / r2 * rate;
        // The pitch point, where the teeth meet, is R1 along N.x from O1.
        let contact = [r1, 0.0, 0.0];
        let on_gear = |frame: &str, centre: &str| {
            let (c, _) = motion(&model, &point(&model, centre), &q, &rates);
            cross(angular_velocity(&model, frame, &q, &rates), sub(contact, c))
        };
        let (v1, v2) = (on_gear("G1", "O1"), on_gear("G2", "O2"));
        assert!(norm(sub(v1, v2)) < 1e-7, "{v1:?} vs {v2:?}");
    }
}

#[test]
fn rolling_disk_contact_is_at_rest_when_x_rate_is_r_phi_rate() {
    let model = load("rolling-disk-incline.lag");
    let r = parameter(&model, "R");
    let (x, phi) = (coordinate(&model, "x"), coordinate(&model, "phi"));
    for &rate in &SAMPLES {
        let mut q = [0.0; 2];
        q[x] = rate;
        q[phi] = 2.0 * rate;
        let mut rates = [0.0; 2];
        rates[phi] = rate;
        rates[x] = r * rate;
        let v = material_velocity(&model, "D", "C", "A", &q, &rates);
        assert!(norm(v) < 1e-7, "{v:?}");
    }
}

#[test]
fn rods_keep_their_lengths() {
    let cases: [(&str, &str, &str, &str); 4] = [
        ("double-pendulum.lag", "P1", "P2", "l2"),
        ("spherical-pendulum.lag", "origin", "P", "l"),
        ("heavy-symmetric-top.lag", "origin", "G", "l"),
        ("seed/7.4-inverted-pendulum.lag", "A", "G", "L"),
    ];
    for (file, from, to, length) in cases {
        let model = load(file);
        let expected = if length == "L" {
            parameter(&model, "L") / 2.0
        } else {
            parameter(&model, length)
        };
        let n = model.coordinates().len();
        for &value in &SAMPLES {
            let q: Vec<f64> = (0..n).map(|i| value * (i as f64 + 1.0)).collect();
            let rates = vec![0.0; n];
            let state = State {
                time: 0.0,
                coordinates: &q,
                rates: &rates,
            };
            let rod = sub(
                vector(&model, &point(&model, to), &state),
                vector(&model, &point(&model, from), &state),
            );
            assert!(
                (norm(rod) - expected).abs() < 1e-12,
                "{file}: |{to} − {from}| = {}",
                norm(rod)
            );
        }
    }
}

#[test]
fn driven_coordinates_have_their_prescribed_rate() {
    let model = load("driven-pivot-pendulum.lag");
    let (a, omega) = (parameter(&model, "a"), parameter(&model, "omega"));
    let Some(Declaration::Coordinate(id)) = model.find("s") else {
        panic!()
    };
    let rate = synthetic(ExprKind::Rate(id), Type::Scalar);
    for &time in &SAMPLES {
        let q = [0.0; 2];
        let state = State {
            time,
            coordinates: &q,
            rates: &q,
        };
        let value = model
            .evaluate(&rate, &state)
            .expect("evaluates")
            .scalar()
            .expect("scalar");
        let exact = -a * omega * (omega * time).sin();
        assert!(
            (value - exact).abs() < 1e-6 * (1.0 + exact.abs()),
            "s' = {value}, expected {exact}"
        );
    }
}

#[test]
fn missing_values_and_short_states_are_errors() {
    let model =
        model::load("coordinates x\nparameters k\nframe N\npoint P = k*x*N.x\nparticle P mass 1\n")
            .expect("valid");
    let position = point(&model, "P");
    let err = model
        .evaluate(
            &position,
            &State {
                time: 0.0,
                coordinates: &[1.0],
                rates: &[0.0],
            },
        )
        .unwrap_err();
    assert_eq!(err.to_string(), "`k` has no value");
    let err = model
        .evaluate(
            &position,
            &State {
                time: 0.0,
                coordinates: &[],
                rates: &[],
            },
        )
        .unwrap_err();
    assert!(matches!(
        err,
        model::EvaluationError::StateTooShort {
            given: 0,
            needed: 1
        }
    ));
}
