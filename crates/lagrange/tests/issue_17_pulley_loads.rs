//! Issue 17: a pulley released alone (`reaction axle: hinge origin on pulley`) under a rope
//! built into the coordinates (`y1 = R φ`, `y2 = L − R φ` written into the masses' points) got
//! only its own weight as the axle force, and both methods "agreed exactly": the rope's pull
//! was silently dropped. The release moves only the pulley; the rope's pull reaches it through
//! the coordinate `φ`, which the release does not see. Such a reaction is now refused, naming
//! the coordinate and the bodies whose load would be missing; released together with the
//! masses, the pulley's axle force is the whole load, `M g + T₁ + T₂`.

use lagrange::{cas, model, Analysis, Error, ErrorKind};

const PULLEY: &str = "
coordinates phi
parameters  m1 = 2, m2 = 1, M = 0.5, R = 0.1, I = 0.0025, L = 2, g = 9.81

frame N
frame P = N rotated phi about z
point A = -R*N.x - R*phi*N.y
point B =  R*N.x - (L - R*phi)*N.y

particle A mass m1
particle B mass m2
body pulley mass M at origin frame P inertia I/2, I/2, I
gravity -g*N.y
";

fn with_reaction(statement: &str) -> Analysis {
    Analysis::from_text(&format!("{PULLEY}\n{statement}\n")).expect("the model reads")
}

#[test]
fn a_pulley_released_alone_under_a_rope_in_the_coordinates_is_refused_naming_the_missing_load() {
    let analysis = with_reaction("reaction axle: hinge origin on pulley");
    let source = analysis.source().expect("read from text");
    let refusal = model::reaction_requests(&source.model).expect_err("a partial force is refused");
    let model::LowerError::UnreleasedLoad {
        reaction,
        members,
        coordinate,
        others,
        ..
    } = &refusal
    else {
        panic!("unexpected error: {refusal}");
    };
    assert_eq!(reaction, "axle");
    assert_eq!(members, &["pulley"]);
    assert_eq!(coordinate, "phi");
    assert_eq!(others, &["A", "B"]);
    // The analysis gives the same refusal at the reaction's line, as the user's mistake.
    let error = analysis.reactions().expect_err("refused");
    let Error::Located {
        line,
        kind,
        message,
        ..
    } = &error
    else {
        panic!("unexpected error: {error}");
    };
    assert_eq!((*line, *kind), (15, ErrorKind::Input));
    assert!(
        message.contains("`A` and `B`") && message.contains("missing"),
        "{message}"
    );
}

#[test]
fn released_with_the_masses_the_axle_carries_the_rope_s_pull() {
    let analysis = with_reaction("reaction axle: hinge origin on pulley, A, B");
    let reactions = analysis.reactions().unwrap().expect("one reaction");
    let axle = &reactions.reactions[0];
    let force = axle.force.expect("a hinge's force");
    let (m1, m2, big_m, r, i, g) = (2.0, 1.0, 0.5, 0.1, 0.0025, 9.81);
    let values = |s: cas::Symbol| match s.name() {
        "m1" => Some(m1),
        "m2" => Some(m2),
        "M" => Some(big_m),
        "R" => Some(r),
        "I" => Some(i),
        "L" => Some(2.0),
        "g" => Some(g),
        _ => Some(0.3),
    };
    // The pulley's angular acceleration, and the rope's tensions on each side.
    let alpha = (m1 - m2) * g * r / (i + (m1 + m2) * r * r);
    let (t1, t2) = (m1 * (g - r * alpha), m2 * (g + r * alpha));
    let vertical = force[1].eval(&values).unwrap();
    let expected = big_m * g + t1 + t2;
    assert!(
        (vertical - expected).abs() < 1e-12 * expected,
        "{vertical} against {expected}"
    );
    assert!(force[0].eval(&values).unwrap().abs() < 1e-12);
}
