//! Issue 14: two particles at one point made the reaction of a hinge holding one of them
//! "DISAGREE: this is a bug" — Lagrange I (whose value is right) counts both, since the
//! release moves both, while Newton–Euler balances the momentum of the named one only. Where
//! the release moves bodies it does not name, that is said plainly: `Agreement::Unattributed`.

use cas::Expr;
use mechanics::{
    reactions, Agreement, Load, Method, Particle, ReactionRequest, Release, ReleaseKind, System,
};

fn pendulum_with_two_bobs(displaced: bool) -> System {
    let th = Expr::coordinate("theta");
    let (l, g) = (Expr::symbol("l"), Expr::symbol("g"));
    let (ux, uy) = if displaced {
        (Expr::coordinate("u_x"), Expr::coordinate("u_y"))
    } else {
        (Expr::zero(), Expr::zero())
    };
    let mut system = System::new();
    system.add_coordinate("theta");
    if displaced {
        system.add_coordinate("u_x");
        system.add_coordinate("u_y");
    }
    let at = [l * th.sin() + ux, -(l * th.cos()) + uy, Expr::zero()];
    for (name, mass) in [("P", "m1"), ("P", "m2")] {
        system.add_particle(Particle {
            name: name.into(),
            mass: Expr::symbol(mass),
            position: at,
        });
    }
    system.add_load(Load::Gravity([Expr::zero(), -g, Expr::zero()]));
    system
}

#[test]
fn a_hinge_on_one_of_two_particles_at_a_point_is_lagrange_one_alone() {
    let release = Release {
        name: "pivot".into(),
        kind: ReleaseKind::Hinge,
        point: ("origin".into(), [Expr::zero(), Expr::zero(), Expr::zero()]),
        members: vec!["P".into()],
        system: pendulum_with_two_bobs(true),
        displacements: vec![
            ("u_x".into(), [Expr::one(), Expr::zero(), Expr::zero()]),
            ("u_y".into(), [Expr::zero(), Expr::one(), Expr::zero()]),
        ],
        rotations: Vec::new(),
        normal: None,
        particles: vec![0],
        bodies: Vec::new(),
    };
    let original = pendulum_with_two_bobs(false);
    let [r] = &reactions(&original, &[ReactionRequest::Release(release)]).unwrap()[..] else {
        panic!("one reaction");
    };
    assert_eq!(r.agreement, Agreement::Unattributed);
    assert_eq!(r.methods, [Method::LagrangeI]);
    // The rod pulls both bobs: R = (m1 + m2) (l θ̇² + g cos θ) along −r̂.
    let th = Expr::coordinate("theta");
    let thd = Expr::rate("theta", 1);
    let [m1, m2, l, g] = ["m1", "m2", "l", "g"].map(Expr::symbol);
    let pull = (m1 + m2) * (l * thd.powi(2) + g * th.cos());
    let force = r.force.expect("a force");
    assert!(force[0].equals(-(pull * th.sin())), "{}", force[0]);
    assert!(force[1].equals(pull * th.cos()), "{}", force[1]);
    assert!(!r.agreement.verdict().contains("bug"));
}
