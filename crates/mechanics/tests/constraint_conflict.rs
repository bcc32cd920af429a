//! Issue 14: redundant or contradictory constraints (`x = 1` and `x = 2`) were not reported —
//! the reactions came out as two zero multipliers. The rank of the constraint rows is checked
//! and the constraints in conflict are named.

use cas::Expr;
use mechanics::{
    canonical, constraint_conflict, derive, reactions, Constraint, ConstraintConflict,
    ConstraintForm, Load, Particle, ReactionError, ReactionRequest, System,
};

/// A particle in a vertical plane with two holonomic constraints `a: fa = 0`, `b: fb = 0`,
/// parameters `p = p_value`, `r = r_value`.
fn particle_with(fa: Expr, fb: Expr, p_value: i64, r_value: i64) -> System {
    let (x, y) = (Expr::coordinate("x"), Expr::coordinate("y"));
    let mut system = System::new();
    system.add_coordinate("x");
    system.add_coordinate("y");
    system.add_parameter("m", Some(Expr::one()));
    system.add_parameter("g", Some(Expr::int(10)));
    system.add_parameter("p", Some(Expr::int(p_value)));
    system.add_parameter("r", Some(Expr::int(r_value)));
    system.add_particle(Particle {
        name: "P".into(),
        mass: Expr::symbol("m"),
        position: [x, y, Expr::zero()],
    });
    system.add_load(Load::Gravity([
        Expr::zero(),
        -Expr::symbol("g"),
        Expr::zero(),
    ]));
    for (name, f) in [("a", fa), ("b", fb)] {
        system.add_constraint(Constraint {
            name: name.into(),
            equations: vec![ConstraintForm::Holonomic(f)],
        });
    }
    system
}

fn requests() -> Vec<ReactionRequest> {
    ["a", "b"]
        .iter()
        .map(|name| ReactionRequest::Constraint {
            name: (*name).to_string(),
            // Not reached: the conflict is found first.
            without: System::new(),
        })
        .collect()
}

fn conflict(system: &System) -> Option<ConstraintConflict> {
    let eq = derive(system).unwrap();
    constraint_conflict(system, &eq)
}

#[test]
fn contradictory_constraints_are_named() {
    let x = Expr::coordinate("x");
    let system = particle_with(x - 1, x - 2, 0, 0);
    let want = ConstraintConflict {
        constraints: vec!["a".into(), "b".into()],
        contradictory: true,
    };
    assert_eq!(conflict(&system), Some(want.clone()));
    let err = reactions(&system, &requests()).unwrap_err();
    assert_eq!(err, ReactionError::Conflict(want));
    assert!(err
        .to_string()
        .contains("contradictory constraints: constraints `a`, `b`"));
}

#[test]
fn redundant_constraints_are_named() {
    let y = Expr::coordinate("y");
    let system = particle_with(y - 1, 2 * y - 2, 0, 0);
    assert_eq!(
        conflict(&system),
        Some(ConstraintConflict {
            constraints: vec!["a".into(), "b".into()],
            contradictory: false,
        })
    );
}

#[test]
fn consistency_is_judged_at_the_parameters_values() {
    let x = Expr::coordinate("x");
    let (p, r) = (Expr::symbol("p"), Expr::symbol("r"));
    let same = particle_with(x - p, x - r, 3, 3);
    assert_eq!(conflict(&same).map(|c| c.contradictory), Some(false));
    let apart = particle_with(x - p, x - r, 3, 4);
    assert_eq!(conflict(&apart).map(|c| c.contradictory), Some(true));
}

#[test]
fn independent_constraints_are_not_in_conflict() {
    let (x, y) = (Expr::coordinate("x"), Expr::coordinate("y"));
    assert_eq!(conflict(&particle_with(x - 1, y - 2, 0, 0)), None);
    // Nonlinear, independent at a generic state: the four-bar's loop, and a rolling disk
    // whose dependent rows all belong to one constraint.
    for c in canonical::all() {
        assert_eq!(conflict(&c.system), None, "{}", c.name);
    }
}
