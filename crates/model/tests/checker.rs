//! What the checker builds from valid models: constraint classification, driven coordinates,
//! vector constants, inertia about a point, outputs, and constant evaluation.

use model::{ConstraintKind, Declaration, ExprKind, Model, Quantity, ReactionTarget, Type};

const PRELUDE: &str = "coordinates x, y, theta\nparameters m = 2, l = 0.5, r = 3\nframe N\n";

fn load(body: &str) -> Model {
    let source = format!("{PRELUDE}{body}");
    match model::load(&source) {
        Ok(model) => model,
        Err(errors) => panic!("{}", model::render_short(&errors.0, "test.lag", &source)),
    }
}

fn error_codes(body: &str) -> Vec<&'static str> {
    match model::load(&format!("{PRELUDE}{body}")) {
        Ok(_) => Vec::new(),
        Err(errors) => errors.0.iter().map(|d| d.kind.code()).collect(),
    }
}

#[test]
fn constraints_are_classified_by_their_rates() {
    let model = load(
        "point P = x*N.x + y*N.y + theta*N.z\nparticle P mass m\n\
         constraint a: x^2 + y^2 = l^2\nconstraint b: x' + r*theta' = 0\n",
    );
    let kinds: Vec<&ConstraintKind> = model.constraints().iter().map(|c| &c.kind).collect();
    assert!(matches!(kinds[0], ConstraintKind::Holonomic { .. }));
    assert!(matches!(kinds[1], ConstraintKind::Velocity { .. }));
    assert!(model.constraints()[0].is_holonomic());
    assert!(!model.constraints()[1].is_holonomic());
    // Three coordinates, less one holonomic and one velocity constraint (as `solve` counts).
    assert_eq!(model.summary().degrees_of_freedom, 1);
}

#[test]
fn gears_integrate_only_with_a_constant_ratio() {
    let model = load(
        "point P = x*N.x + y*N.y + theta*N.z\nparticle P mass m\n\
         constraint g1: gear x to y ratio r\nconstraint g2: gear x to theta ratio 1 + x^2\n",
    );
    assert!(model.constraints()[0].is_holonomic());
    assert!(!model.constraints()[1].is_holonomic());
}

#[test]
fn driven_coordinates_are_functions_of_time() {
    let model = load(
        "inputs w = 2\ndriven psi = w*t\nframe H = N rotated psi about z\n\
         point P = x*H.x + y*N.y + theta*N.z\nparticle P mass m\nreactions psi\noutput psi'\n",
    );
    let psi = model
        .coordinates()
        .iter()
        .find(|c| c.name.name == "psi")
        .expect("psi");
    assert!(psi.driven.is_some());
    assert_eq!(model.free_coordinates().count(), 3);
    assert!(matches!(model.reactions(), [ReactionTarget::Driven(_)]));
    // A driven coordinate has no initial condition, and is not a constant.
    assert_eq!(error_codes("driven s = t\ninitial s = 1\n"), ["E303"]);
    assert_eq!(error_codes("driven s = t\nconstants c = s\n"), ["E205"]);
    // Driven motions depend on time only.
    assert_eq!(error_codes("driven s = x*t\n"), ["E205"]);
}

#[test]
fn levels_follow_frames_and_points() {
    // A fixed-angle frame is constant, so gravity may use it; a rotating one is not.
    let model = load("frame S = N rotated r about z\ngravity -9.81*S.y\npoint P = x*N.x + y*N.y + theta*N.z\nparticle P mass m\n");
    assert_eq!(model.frames().len(), 2);
    assert_eq!(
        error_codes("frame B = N rotated theta about z\ngravity -9.81*B.y\n"),
        ["E205"]
    );
    // Inputs may appear in positions (a prescribed motion), not in masses.
    assert_eq!(
        error_codes("inputs u = t\npoint P = u*N.x\nparticle P mass u\n"),
        ["E205"]
    );
}

#[test]
fn constants_carry_their_type() {
    let model =
        load("constants e = N.x + N.y, k = 2*m\npoint P = (x + y + theta)*e\nparticle P mass k\n");
    let types: Vec<Type> = model.constants().iter().map(|c| c.value.ty).collect();
    assert_eq!(types, [Type::Vector, Type::Scalar]);
    assert_eq!(
        error_codes("constants e = N.x\npoint P = x*N.x\nparticle P mass e\n"),
        ["E201"]
    );
}

#[test]
fn inertia_about_a_point_and_full_tensors() {
    let model = load(
        "frame B = N rotated theta about z\npoint G = x*N.x + y*N.y + l*B.x\npoint O = x*N.x + y*N.y\n\
         body rod mass m at G frame B inertia xx = 0, yy = m*l^2/3, zz = m*l^2/3, xy = 0 about O\n",
    );
    let body = &model.bodies()[0];
    assert_eq!(model.point(body.inertia.about).name.name, "O");
    assert!(!body.inertia.principal);
    assert!(body.inertia.components[3].is_some() && body.inertia.components[4].is_none());
}

#[test]
fn outputs_and_lookups() {
    let model = load(
        "point P = x*N.x + y*N.y + theta*N.z\nparticle P mass m\nconstraint c: x = y\n\
         output P, c, kinetic_energy, w = x' + 1\n",
    );
    let quantities: Vec<&Quantity> = model.outputs().iter().map(|o| &o.quantity).collect();
    assert!(matches!(quantities[0], Quantity::Expr(e) if e.ty == Type::Vector));
    assert!(matches!(
        quantities[1],
        Quantity::Reaction(ReactionTarget::Constraint(_))
    ));
    assert!(matches!(quantities[2], Quantity::KineticEnergy));
    assert!(matches!(model.find("l"), Some(Declaration::Parameter(_))));
    assert!(matches!(model.find("c"), Some(Declaration::Constraint(_))));
    assert_eq!(model.find("origin"), None);
}

#[test]
fn constant_evaluation() {
    let model = load(
        "parameters a = 2*l + sqrt(4), b = atan2(1, 1)*4/pi\nconstants c = a^2 - b\n\
         point P = c*(x + y + theta)*N.x\nparticle P mass a\n",
    );
    let value = |name: &str| match model.find(name) {
        Some(Declaration::Parameter(id)) => model
            .parameter(id)
            .value
            .as_ref()
            .and_then(|v| model.evaluate_constant(v)),
        Some(Declaration::Constant(id)) => model.evaluate_constant(&model.constant(id).value),
        _ => None,
    };
    assert_eq!(value("a"), Some(3.0));
    assert!((value("b").unwrap_or(0.0) - 1.0).abs() < 1e-15);
    assert!((value("c").unwrap_or(0.0) - 8.0).abs() < 1e-12);
    // A number literal keeps its text for exact conversion.
    let Some(Declaration::Parameter(l)) = model.find("l") else {
        panic!()
    };
    let Some(ExprKind::Number { text, .. }) = model.parameter(l).value.as_ref().map(|v| &v.kind)
    else {
        panic!()
    };
    assert_eq!(
        model::decimal(text),
        Some(model::Decimal {
            mantissa: 5,
            exponent: -1
        })
    );
}
