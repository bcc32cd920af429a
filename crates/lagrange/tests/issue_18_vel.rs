//! Issue 18: a point's velocity could not be named in a constraint, so a no-slip condition
//! had to be expanded by hand (the knife edge's `-sin(theta)*x' + cos(theta)*y' = 0`). Now
//! `vel(P)` is the velocity of a point (the time derivative of its position in the inertial
//! frame), allowed where rates are; the knife edge written with it gives the same equations
//! exactly. `check` also counts a 3-D rolling contact's independent rows (the rank) instead
//! of its statement, as the derivation does.

use std::path::Path;

use lagrange::Analysis;

const KNIFE_EDGE: &str = "coordinates x, y, theta
parameters  m = 1, J = 0.1
inputs      T = 0.1
frame N
frame B = N rotated theta about z
point G = x*N.x + y*N.y
body sled mass m at G frame B inertia J, J, J
couple T*N.z on sled
";

fn knife_edge(constraint: &str) -> Analysis {
    Analysis::from_text(&format!("{KNIFE_EDGE}constraint blade: {constraint}\n"))
        .expect("the knife edge loads")
}

#[test]
fn the_knife_edge_with_vel_gives_the_hand_written_equations_exactly() {
    let by_hand = knife_edge("-sin(theta)*x' + cos(theta)*y' = 0");
    let with_vel = knife_edge("dot(vel(G), B.y) = 0");
    let (a, b) = (
        by_hand.equations().expect("derives"),
        with_vel.equations().expect("derives"),
    );
    assert_eq!(a.coordinates(), b.coordinates());
    assert_eq!(a.degrees_of_freedom(), 2);
    assert_eq!(b.degrees_of_freedom(), 2);
    let same = |x: &lagrange::cas::Expr, y: &lagrange::cas::Expr| (*x - *y).is_zero();
    for (ra, rb) in a.constraint_matrix().iter().zip(b.constraint_matrix()) {
        for (x, y) in ra.iter().zip(rb) {
            assert!(same(x, y), "{x:?} vs {y:?}");
        }
    }
    for (x, y) in a.constraint_rhs().iter().zip(b.constraint_rhs()) {
        assert!(same(x, y));
    }
    for (x, y) in a.forcing().iter().zip(b.forcing()) {
        assert!(same(x, y));
    }
    assert_eq!(a.constraint_matrix().len(), 1);
    assert_eq!(b.constraint_matrix().len(), 1);
}

#[test]
fn vel_is_refused_where_only_positions_may_appear() {
    let text = format!("{KNIFE_EDGE}point Q = G + vel(G)\n");
    let Err(lagrange::Error::Model(e)) = Analysis::from_text(&text) else {
        panic!("a velocity in a point's position was accepted");
    };
    let text = e.render("m.lag", lagrange::model::RenderOptions::default());
    assert!(
        text.contains("E204") && text.contains("`vel(P)` is a velocity"),
        "{text}"
    );
}

#[test]
fn check_counts_a_rolling_contacts_independent_rows() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    for (file, dof) in [("rolling-disk.lag", 3), ("whipple-bicycle.lag", 3)] {
        let a = Analysis::from_file(&root.join(file)).expect("loads");
        let summary = a.source().expect("a file has its source").model.summary();
        assert_eq!(summary.degrees_of_freedom, dof, "{file}");
        assert!(summary
            .to_string()
            .contains("independent constraint rows in all"));
        assert!(!summary.to_string().contains("provisional"));
    }
}
