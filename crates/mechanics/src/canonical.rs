//! Canonical systems built in code: a simple pendulum, a double pendulum, the cart–pendulum of
//! the seed's exercise 7.1, a disk rolling down a slope and a four-bar linkage.
//!
//! They are the shared fixtures of the tests at every level (this crate's own tests check
//! their equations against the textbook forms, exactly and by numbers) and of the benches.
//! Each is also written as a model file under `examples/canonical/` (same names, same
//! coordinates, same parameters and values), and a test checks that the two give the same
//! equations. Every parameter carries an exact value, so each system can be evaluated and
//! simulated as it is; [`Canonical::initial`] gives a consistent initial state.
//!
//! ```
//! use mechanics::{canonical, derive};
//! let eq = derive(&canonical::pendulum()).unwrap();
//! assert_eq!(eq.coordinates(), ["theta"]);
//! ```

use cas::Expr;

use crate::system::{
    rotation_about, Constraint, ConstraintForm, Load, Particle, RigidBody, Rotation, System, Vector,
};

/// A canonical system with its name and a consistent initial state.
#[derive(Clone, Debug)]
pub struct Canonical {
    /// Its name: the stem of its model file under `examples/canonical/`.
    pub name: &'static str,
    /// The system.
    pub system: System,
    /// Initial values `(coordinate, q, q̇)` for every coordinate of the system, in order;
    /// they satisfy its constraints.
    pub initial: Vec<(String, f64, f64)>,
}

/// All five canonical systems, in the order of this module's functions.
#[must_use]
pub fn all() -> Vec<Canonical> {
    let named = |name, system, initial: &[(&str, f64, f64)]| Canonical {
        name,
        system,
        initial: initial
            .iter()
            .map(|(q, x, v)| ((*q).to_string(), *x, *v))
            .collect(),
    };
    vec![
        named("pendulum", pendulum(), &[("theta", 0.5, 0.0)]),
        named(
            "double-pendulum",
            double_pendulum(),
            &[("theta1", 1.0, 0.0), ("theta2", 0.0, 0.5)],
        ),
        named(
            "cart-pendulum",
            cart_pendulum(),
            &[("x", 0.1, 0.0), ("theta", 0.3, 0.0)],
        ),
        named(
            "rolling-disk",
            rolling_disk(),
            &[("x", 0.0, 0.0), ("phi", 0.0, 0.0)],
        ),
        named("four-bar", four_bar(), &four_bar_initial()),
    ]
}

/// An exact rational `num/den` (`den` non-zero in every call here).
fn ratio(num: i64, den: i64) -> Expr {
    Expr::rational(num, den).unwrap_or_else(Expr::zero)
}

fn parameters(system: &mut System, values: &[(&str, Expr)]) {
    for (name, value) in values {
        system.add_parameter(name, Some(*value));
    }
}

fn s(name: &str) -> Expr {
    Expr::symbol(name)
}

fn z() -> Expr {
    Expr::zero()
}

/// The standard gravity value used by every canonical system, `981/100`.
fn gravity_value() -> Expr {
    ratio(981, 100)
}

/// A simple pendulum: a point mass `m` on a massless rod of length `l` hinged at the origin,
/// `θ` (`theta`) from the downward vertical, gravity `−g ŷ`.
///
/// Position `P = (l sin θ, −l cos θ, 0)`. Parameters `m = 1`, `l = 1`, `g = 981/100`.
/// Equation: `m l² θ̈ = −m g l sin θ`.
#[must_use]
pub fn pendulum() -> System {
    let th = Expr::coordinate("theta");
    let (m, l, g) = (s("m"), s("l"), s("g"));
    let mut system = System::new();
    system.add_coordinate("theta");
    parameters(
        &mut system,
        &[
            ("m", Expr::one()),
            ("l", Expr::one()),
            ("g", gravity_value()),
        ],
    );
    let p = [l * th.sin(), -(l * th.cos()), z()];
    system.add_point("P", p);
    system.add_particle(Particle {
        name: "P".into(),
        mass: m,
        position: p,
    });
    system.add_load(Load::Gravity([z(), -g, z()]));
    system
}

/// A double pendulum: point masses `m1`, `m2` on massless rods `l1`, `l2`, both angles
/// `θ1`, `θ2` (`theta1`, `theta2`) from the downward vertical, gravity `−g ŷ`.
///
/// `P1 = l1 (sin θ1, −cos θ1)`, `P2 = P1 + l2 (sin θ2, −cos θ2)`. Parameters `m1 = m2 = 1`,
/// `l1 = l2 = 1`, `g = 981/100`. Equations, with `δ = θ1 − θ2`:
/// `(m1 + m2) l1² θ̈1 + m2 l1 l2 cos δ θ̈2 = −m2 l1 l2 sin δ θ̇2² − (m1 + m2) g l1 sin θ1`,
/// `m2 l1 l2 cos δ θ̈1 + m2 l2² θ̈2 = m2 l1 l2 sin δ θ̇1² − m2 g l2 sin θ2`.
#[must_use]
pub fn double_pendulum() -> System {
    let (t1, t2) = (Expr::coordinate("theta1"), Expr::coordinate("theta2"));
    let (m1, m2, l1, l2, g) = (s("m1"), s("m2"), s("l1"), s("l2"), s("g"));
    let mut system = System::new();
    system.add_coordinate("theta1");
    system.add_coordinate("theta2");
    let one = Expr::one();
    parameters(
        &mut system,
        &[
            ("m1", one),
            ("m2", one),
            ("l1", one),
            ("l2", one),
            ("g", gravity_value()),
        ],
    );
    let p1 = [l1 * t1.sin(), -(l1 * t1.cos()), z()];
    let p2 = [p1[0] + l2 * t2.sin(), p1[1] - l2 * t2.cos(), z()];
    for (name, mass, position) in [("P1", m1, p1), ("P2", m2, p2)] {
        system.add_point(name, position);
        system.add_particle(Particle {
            name: name.into(),
            mass,
            position,
        });
    }
    system.add_load(Load::Gravity([z(), -g, z()]));
    system
}

/// The cart–pendulum of the seed's exercise 7.1: a cart `A` of mass `m_A` slides along `x`
/// on a spring of stiffness `k` (rest length zero, anchored at the origin) and carries a
/// point mass `B` (`m_B`) on a massless rod of length `l`, `θ` (`theta`) from the vertical.
/// `ŷ` points down: gravity is `+g ŷ`. Inputs: a force `F x̂` on the cart and a couple `C`
/// entering as the generalized force `Q_θ = C` (both 0 unless set).
///
/// `A = (x, 0)`, `B = (x + l sin θ, l cos θ)`. Parameters `m_A = 2`, `m_B = 1`, `l = 1/2`,
/// `k = 30`, `g = 981/100`. Equations:
/// `(m_A + m_B) ẍ + m_B l cos θ θ̈ = m_B l sin θ θ̇² − k x + F`,
/// `m_B l cos θ ẍ + m_B l² θ̈ = −m_B g l sin θ + C`.
#[must_use]
pub fn cart_pendulum() -> System {
    let (x, th) = (Expr::coordinate("x"), Expr::coordinate("theta"));
    let (ma, mb, l, k, g) = (s("m_A"), s("m_B"), s("l"), s("k"), s("g"));
    let mut system = System::new();
    system.add_coordinate("x");
    system.add_coordinate("theta");
    parameters(
        &mut system,
        &[
            ("m_A", Expr::int(2)),
            ("m_B", Expr::one()),
            ("l", ratio(1, 2)),
            ("k", Expr::int(30)),
            ("g", gravity_value()),
        ],
    );
    system.add_input("F", Some(z()));
    system.add_input("C", Some(z()));
    let a = [x, z(), z()];
    let b = [x + l * th.sin(), l * th.cos(), z()];
    for (name, mass, position) in [("A", ma, a), ("B", mb, b)] {
        system.add_point(name, position);
        system.add_particle(Particle {
            name: name.into(),
            mass,
            position,
        });
    }
    system.add_load(Load::Gravity([z(), g, z()]));
    system.add_load(Load::Potential(k * x.powi(2) / 2));
    system.add_load(Load::Force {
        force: [s("F"), z(), z()],
        point: a,
    });
    system.add_load(Load::GeneralizedForce {
        force: s("C"),
        coordinate: 1,
    });
    system
}

fn matmul(a: &Rotation, b: &Rotation) -> Rotation {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// Components of `v` along the axes of the frame `r` (columns: its unit vectors).
fn in_frame(r: &Rotation, v: &Vector) -> Vector {
    std::array::from_fn(|i| (0..3).map(|k| r[k][i] * v[k]).sum::<Expr>().normal())
}

/// A uniform disk of mass `m` and radius `R` rolling without slipping down a slope inclined
/// at the fixed angle `α` (`alpha`). The slope's frame `S` is `N` turned by `−α` about `z`
/// (`S.x` downhill, `S.y` normal to the slope); `x` is the distance travelled along `S.x`,
/// `φ` (`phi`) the disk's rotation, clockwise (the disk's frame is `S` turned by `−φ`).
/// Gravity `−g ŷ`.
///
/// Centre `C = x S.x + R S.y`, contact point `A = x S.x`; inertia `diag(m R²/4, m R²/4,
/// m R²/2)` about `C`. The rolling constraint `roll` (velocity of the material point at `A`
/// zero, in the disk's axes) integrates to `φ = x/R`, which eliminates `φ`. Parameters `m = 1`,
/// `R = 1/5`, `alpha = 3/10`, `g = 981/100`. Equation: `(3/2) m ẍ = m g sin α`.
#[must_use]
pub fn rolling_disk() -> System {
    let (x, phi) = (Expr::coordinate("x"), Expr::coordinate("phi"));
    let (m, r, alpha, g) = (s("m"), s("R"), s("alpha"), s("g"));
    let mut system = System::new();
    system.add_coordinate("x");
    system.add_coordinate("phi");
    parameters(
        &mut system,
        &[
            ("m", Expr::one()),
            ("R", ratio(1, 5)),
            ("alpha", ratio(3, 10)),
            ("g", gravity_value()),
        ],
    );
    let slope = rotation_about(2, -alpha);
    let disk = matmul(&slope, &rotation_about(2, -phi));
    let along = |a: Expr, b: Expr| -> Vector {
        std::array::from_fn(|i| (a * slope[i][0] + b * slope[i][1]).normal())
    };
    let centre = along(x, r);
    let contact = along(x, z());
    system.add_point("C", centre);
    system.add_point("A", contact);
    let quarter = m * r.powi(2) / 4;
    system.add_body(RigidBody {
        name: "disk".into(),
        mass: m,
        centre,
        rotation: disk,
        inertia: [
            [quarter, z(), z()],
            [z(), quarter, z()],
            [z(), z(), m * r.powi(2) / 2],
        ],
    });
    system.add_load(Load::Gravity([z(), -g, z()]));
    // The material point at A: v_C + ω × (A − C), in the disk's axes (where the
    // coefficients of the rates are constant, so the constraint integrates).
    let w = crate::equations::angular_velocity(&disk);
    let d: Vector = std::array::from_fn(|i| contact[i] - centre[i]);
    let v: Vector = centre.map(Expr::dt);
    let vp: Vector = [
        v[0] + w[1] * d[2] - w[2] * d[1],
        v[1] + w[2] * d[0] - w[0] * d[2],
        v[2] + w[0] * d[1] - w[1] * d[0],
    ];
    system.add_constraint(Constraint {
        name: "roll".into(),
        equations: in_frame(&disk, &vp)
            .into_iter()
            .map(ConstraintForm::Velocity)
            .collect(),
    });
    system
}

/// The loop-closure functions of the four-bar: the coupler's far end reached through the
/// crank and the coupler equals it reached through the rocker.
#[must_use]
pub fn four_bar_loop() -> [Expr; 2] {
    let [t1, t2, t3] = ["theta1", "theta2", "theta3"].map(Expr::coordinate);
    let (l1, l2, l3, d) = (s("l1"), s("l2"), s("l3"), s("d"));
    [
        l1 * t1.cos() + l2 * t2.cos() - l3 * t3.cos() - d,
        l1 * t1.sin() + l2 * t2.sin() - l3 * t3.sin(),
    ]
}

/// A four-bar linkage in a vertical plane: three uniform rods, a crank `O A` (length `l1`,
/// mass `m1`) hinged at the origin `O`, a coupler `A B` (`l2`, `m2`) and a rocker `D B`
/// (`l3`, `m3`) hinged at `D = (d, 0)`; gravity `−g ŷ`. The three angles `θ1`, `θ2`, `θ3`
/// (`theta1`…) are measured from `x̂`, each rod's frame `B_i` is `N` turned by `θ_i`, and
/// the rods are kept together by the holonomic loop-closure constraints
/// `loop_x: l1 cos θ1 + l2 cos θ2 − l3 cos θ3 − d = 0`,
/// `loop_y: l1 sin θ1 + l2 sin θ2 − l3 sin θ3 = 0`, with multipliers (one degree of freedom).
///
/// Rod `i` has its centre at its middle and inertia `diag(0, m_i l_i²/12, m_i l_i²/12)` in
/// its axes. Parameters `m1 = 1`, `m2 = 3`, `m3 = 2`, `l1 = 1`, `l2 = 5`, `l3 = 4`, `d = 4`,
/// `g = 981/100`: a Grashof crank–rocker (`l1 + l2 < l3 + d`), never at a singular position.
/// Equations `M q̈ + Aᵀλ = f`, `A q̈ = b` with `M` = `[[m1 l1²/3 + m2 l1², m2 l1 l2 cos(θ1 −
/// θ2)/2, 0], [·, m2 l2²/3, 0], [0, 0, m3 l3²/3]]`, `A` the Jacobian of the loop functions
/// ([`four_bar_loop`]) and `b = −Ȧ q̇`.
#[must_use]
pub fn four_bar() -> System {
    let names = ["theta1", "theta2", "theta3"];
    let [t1, t2, t3] = names.map(Expr::coordinate);
    let (m1, m2, m3) = (s("m1"), s("m2"), s("m3"));
    let (l1, l2, l3, d, g) = (s("l1"), s("l2"), s("l3"), s("d"), s("g"));
    let mut system = System::new();
    for name in names {
        system.add_coordinate(name);
    }
    parameters(
        &mut system,
        &[
            ("m1", Expr::one()),
            ("m2", Expr::int(3)),
            ("m3", Expr::int(2)),
            ("l1", Expr::one()),
            ("l2", Expr::int(5)),
            ("l3", Expr::int(4)),
            ("d", Expr::int(4)),
            ("g", gravity_value()),
        ],
    );
    let unit = |th: Expr| [th.cos(), th.sin(), z()];
    let (e1, e2, e3) = (unit(t1), unit(t2), unit(t3));
    let a: Vector = e1.map(|c| l1 * c);
    let dee: Vector = [d, z(), z()];
    let b: Vector = std::array::from_fn(|i| a[i] + l2 * e2[i]);
    let rods = [
        ("crank", m1, l1, t1, e1.map(|c| l1 * c / 2)),
        (
            "coupler",
            m2,
            l2,
            t2,
            std::array::from_fn(|i| a[i] + l2 * e2[i] / 2),
        ),
        (
            "rocker",
            m3,
            l3,
            t3,
            std::array::from_fn(|i| dee[i] + l3 * e3[i] / 2),
        ),
    ];
    system.add_point("A", a);
    system.add_point("B", b);
    system.add_point("D", dee);
    for (name, mass, length, angle, centre) in rods {
        let j = mass * length.powi(2) / 12;
        system.add_body(RigidBody {
            name: name.into(),
            mass,
            centre,
            rotation: rotation_about(2, angle),
            inertia: [[z(), z(), z()], [z(), j, z()], [z(), z(), j]],
        });
    }
    system.add_load(Load::Gravity([z(), -g, z()]));
    let [fx, fy] = four_bar_loop();
    for (name, f) in [("loop_x", fx), ("loop_y", fy)] {
        system.add_constraint(Constraint {
            name: name.into(),
            equations: vec![ConstraintForm::Holonomic(f)],
        });
    }
    system
}

/// A consistent initial state of [`four_bar`] at its parameter values: the crank along `x̂`
/// (`A = (1, 0)`), the coupler at `atan2(4, 3)` (`B = (4, 4)`), the rocker upright; the crank
/// turning at 3 rad/s, the coupler and rocker at −1 rad/s (the rates the loop allows).
fn four_bar_initial() -> [(&'static str, f64, f64); 3] {
    [
        ("theta1", 0.0, 3.0),
        ("theta2", 4f64.atan2(3.0), -1.0),
        ("theta3", std::f64::consts::FRAC_PI_2, -1.0),
    ]
}
