//! The solution of an exercise the way the course writes it, as a [`Document`]: the system,
//! kinematics, the Lagrangian function, Lagrange's equations of the second kind step by step
//! (`d/dt ∂L/∂q̇`, `∂L/∂q`, `Q_q` for every coordinate, then the pure equations of motion),
//! and the first integrals — with the 1-DOF energy method as a second derivation.
//!
//! Later stages (reactions, equilibria, linearization, simulation) append their own sections
//! to the document this returns.

use cas::Expr;
use mechanics::{angular_velocity, Equations, System};

use crate::document::{Block, Cell, Document, Equation, Math, Notation, Section};

/// Step-by-step derivatives are written out up to this many coordinates; beyond, only the
/// resulting equations (a 10-link pendulum's steps fill pages and say nothing new).
const STEP_BY_STEP_MAX: usize = 6;

/// The sections of the solution that the equations of motion answer.
#[must_use]
pub fn equations_of_motion_sections(
    system: &System,
    equations: &Equations,
    notation: &Notation,
) -> Vec<Section> {
    vec![
        system_section(system, equations, notation),
        kinematics_section(system, notation),
        lagrangian_section(equations, notation),
        lagrange_section(equations, notation),
        first_integrals_section(equations, notation),
    ]
}

/// A new document titled `title` with the equations-of-motion sections, in the system's
/// notation ([`Notation::of`]).
#[must_use]
pub fn solution_document(title: &str, system: &System, equations: &Equations) -> Document {
    solution_document_in(title, system, equations, &Notation::of(system))
}

/// [`solution_document`] in `notation`: the later sections written in the same notation reuse
/// the names it gives to long shared sub-expressions ([`Notation::name_shared`]).
#[must_use]
pub fn solution_document_in(
    title: &str,
    system: &System,
    equations: &Equations,
    notation: &Notation,
) -> Document {
    Document {
        title: title.to_string(),
        sections: equations_of_motion_sections(system, equations, notation),
    }
}

fn coordinate(q: &str) -> Math {
    Math::expr(Expr::coordinate(q))
}

fn rate(q: &str, k: u8) -> Math {
    Math::expr(Expr::rate(q, k))
}

fn system_section(system: &System, equations: &Equations, notation: &Notation) -> Section {
    let mut s = Section::new("The system", 2);
    let names: Vec<String> = system
        .coordinates()
        .iter()
        .map(|q| coordinate(q).unicode)
        .collect();
    let n = equations.coordinates().len();
    let dof = equations.degrees_of_freedom();
    let kept = n - dof;
    let count = if kept == 0 {
        String::new()
    } else {
        format!(
            " ({n} coordinates − {kept} independent constraint{} kept with multipliers)",
            if kept == 1 { "" } else { "s" }
        )
    };
    s.paragraph(format!(
        "Generalized coordinates: {}. Degrees of freedom: {dof}{count}.",
        names.join(", ")
    ));
    for e in equations.eliminated() {
        s.paragraph(format!(
            "The constraint `{}` integrates: {} = {}, so {} is not independent.",
            e.constraint,
            coordinate(&e.coordinate).unicode,
            notation.math(e.value).unicode,
            coordinate(&e.coordinate).unicode
        ));
    }
    for (name, motion) in system.driven() {
        s.paragraph(format!(
            "{} is driven: {} = {}.",
            coordinate(name).unicode,
            coordinate(name).unicode,
            notation.math(*motion).unicode
        ));
    }
    if !equations.constraint_names().is_empty() {
        s.paragraph(format!(
            "Kept with Lagrange multipliers: {}.",
            equations.constraint_names().join(", ")
        ));
    }
    s.blocks.extend(parameter_table(system, notation));
    if !system.constants().is_empty() {
        s.paragraph("Named constants, written by name wherever their value appears below:");
        s.blocks.push(Block::Table {
            header: vec!["constant".into(), "value".into()],
            rows: system
                .constants()
                .iter()
                .map(|(name, value)| {
                    vec![
                        Cell::Math(Math::expr(Expr::symbol(name))),
                        Cell::Math(Math::expr(*value)),
                    ]
                })
                .collect(),
        });
    }
    s
}

fn kinematics_section(system: &System, notation: &Notation) -> Section {
    let mut s = Section::new("Kinematics", 2);
    s.paragraph(
        "Positions and velocities in the inertial frame (unit vectors x̂, ŷ, ẑ); velocities are \
         the time derivatives of the positions as the model defines them (for a point that \
         does not move with a body, like a contact point, that is the geometric point's \
         velocity, not the velocity of the body's material point there); angular velocities \
         come from ω× = Ṙ Rᵀ.",
    );
    let mut lines = Vec::new();
    let velocity = |r: &[Expr; 3]| -> [Expr; 3] { r.map(|x| x.dt().normal()) };
    let mut point = |name: &str, position: &[Expr; 3]| {
        let (unicode, latex) = point_label(name);
        lines.push(Equation::new(
            Math::label(format!("r_{unicode}"), format!(r"\vec{{r}}_{{{latex}}}")),
            notation.vector(position),
        ));
        lines.push(Equation::new(
            Math::label(format!("v_{unicode}"), format!(r"\vec{{v}}_{{{latex}}}")),
            notation.vector(&velocity(position)),
        ));
    };
    if system.points().is_empty() {
        // A system built by hand names no points: its particles and centres of mass.
        for p in system.particles() {
            point(&p.name, &p.position);
        }
        for b in system.bodies() {
            point(&format!("G_{}", b.name), &b.centre);
        }
    } else {
        for (name, position) in system.points() {
            point(name, position);
        }
    }
    for b in system.bodies() {
        lines.push(Equation::new(
            Math::label(
                format!("ω_{}", b.name),
                format!(
                    r"\vec{{\omega}}_{{\mathrm{{{}}}}}",
                    b.name.replace('_', r"\_")
                ),
            ),
            notation.vector(&angular_velocity(&b.rotation)),
        ));
    }
    s.equations(lines);
    s
}

/// A point's name as a subscript: `P1` → `P1`; `G_cone` → `G_{cone}` in LaTeX.
fn point_label(name: &str) -> (String, String) {
    let latex = match name.split_once('_') {
        Some((head, tail)) => format!(r"{head}_{{\mathrm{{{}}}}}", tail.replace('_', r"\_")),
        None => name.to_string(),
    };
    (name.to_string(), latex)
}

fn lagrangian_section(equations: &Equations, notation: &Notation) -> Section {
    let mut s = Section::new("Lagrangian function", 2);
    let k = equations.kinetic_energy();
    let v = equations.potential_energy();
    s.equations(vec![
        Equation::new(Math::label("K", "K"), notation.math(k)),
        Equation::new(Math::label("U", "U"), notation.sum(-v)),
        Equation::new(
            Math::label(
                format!("{} = K + U", notation.lagrangian().unicode),
                format!("{} = K + U", notation.lagrangian().latex),
            ),
            notation.math(equations.lagrangian()),
        ),
    ]);
    s.paragraph("U is the force function (U = −V, V the potential energy).");
    s
}

fn lagrange_section(equations: &Equations, notation: &Notation) -> Section {
    let mut s = Section::new("Lagrange equations (II type)", 2);
    let coordinates = equations.coordinates();
    let n = coordinates.len();
    if n <= STEP_BY_STEP_MAX {
        let l = &notation.lagrangian().unicode;
        s.paragraph(format!(
            "For every coordinate q: d/dt(∂{l}/∂q̇) − ∂{l}/∂q = Q_q, with Q_q the generalized \
             force of the loads not in U, by virtual work."
        ));
        derivative_steps(&mut s, equations, notation);
    } else {
        s.paragraph(format!(
            "With {n} coordinates the intermediate derivatives are not written out; the \
             equations follow."
        ));
    }

    let pure = pure_equations(equations, notation);
    s.paragraph(format!(
        "Pure equations of motion ({n} equation{} in M(q, t) q̈ = f(q, q̇, t) form):",
        if n == 1 { "" } else { "s" }
    ));
    s.blocks.extend(pure.blocks);
    s
}

/// For every coordinate: `∂L/∂q̇`, its time derivative, `∂L/∂q` and the generalized force.
fn derivative_steps(s: &mut Section, equations: &Equations, notation: &Notation) {
    let lagrangian = equations.lagrangian();
    let coordinates = equations.coordinates();
    let (lu, ll) = (&notation.lagrangian().unicode, &notation.lagrangian().latex);
    for (j, q) in coordinates.iter().enumerate() {
        let (qs, qd) = (coordinate(q), rate(q, 1));
        let Some(qd_symbol) = Expr::rate(q, 1).as_symbol() else {
            continue;
        };
        let Some(q_symbol) = Expr::coordinate(q).as_symbol() else {
            continue;
        };
        let momentum = lagrangian.diff(qd_symbol).normal();
        let d_momentum = momentum.dt().normal();
        let dl_dq = lagrangian.diff(q_symbol).normal();
        let dl_dqd_label = Math::label(
            format!("∂{lu}/∂{}", qd.unicode),
            format!(r"\frac{{\partial {ll}}}{{\partial {}}}", qd.latex),
        );
        s.blocks
            .push(Block::Paragraph(format!("Coordinate {}:", qs.unicode)));
        s.equations(vec![
            Equation::new(dl_dqd_label.clone(), notation.math(momentum)),
            Equation::new(
                Math::label(
                    format!("d/dt(∂{lu}/∂{})", qd.unicode),
                    format!(
                        r"\frac{{d}}{{dt}} \frac{{\partial {ll}}}{{\partial {}}}",
                        qd.latex
                    ),
                ),
                notation.math(d_momentum),
            ),
            Equation::new(
                Math::label(
                    format!("∂{lu}/∂{}", qs.unicode),
                    format!(r"\frac{{\partial {ll}}}{{\partial {}}}", qs.latex),
                ),
                notation.math(dl_dq),
            ),
            Equation::new(
                Math::label(format!("Q_{}", qs.unicode), format!("Q_{{{}}}", qs.latex)),
                notation.math(equations.generalized_forces()[j]),
            ),
        ]);
    }
}

/// The pure equations of motion, the constraints kept with multipliers, and the explicit
/// accelerations when they fit.
fn pure_equations(equations: &Equations, notation: &Notation) -> Section {
    let coordinates = equations.coordinates();
    let mut pure = Section::new("Pure equations of motion", 3);
    let multipliers: Vec<Expr> = (1..=equations.constraint_names().len())
        .map(|i| Expr::symbol(&format!("lambda{i}")))
        .collect();
    let lines: Vec<Equation> = equations
        .lagrange_lhs()
        .iter()
        .zip(equations.generalized_forces())
        .enumerate()
        .map(|(j, (lhs, q))| {
            let reactions = equations
                .constraint_matrix()
                .iter()
                .zip(&multipliers)
                .filter_map(|(row, lambda)| row.get(j).map(|a| *lambda * *a))
                .sum::<Expr>();
            Equation::new(notation.math(*lhs), notation.math(*q - reactions))
        })
        .collect();
    pure.equations(lines);
    let constraint_lines: Vec<Equation> = equations
        .constraint_matrix()
        .iter()
        .zip(equations.constraint_rhs())
        .map(|(row, b)| {
            let lhs = row
                .iter()
                .zip(coordinates)
                .map(|(a, q)| *a * Expr::rate(q, 2))
                .sum::<Expr>();
            Equation::new(notation.math(lhs), notation.math(*b))
        })
        .collect();
    if !constraint_lines.is_empty() {
        pure.paragraph(format!(
            "with the constraints kept ({}), differentiated to the accelerations:",
            equations.constraint_names().join(", ")
        ));
        pure.equations(constraint_lines);
    }
    // Beyond the size budget the explicit accelerations would swamp the page (and say no
    // more than M q̈ = f); the factored form adj(M) f/Δ is shown when it fits.
    if let Some(accelerations) = crate::accelerations::for_report(equations) {
        pure.paragraph("Solved for the accelerations:");
        let named = notation.name_shared(&accelerations);
        let mut lines = named.definitions;
        lines.extend(
            coordinates
                .iter()
                .zip(&named.exprs)
                .enumerate()
                .map(|(j, (q, a))| {
                    Equation::new(rate(q, 2), acceleration(equations, notation, j, *a))
                }),
        );
        pure.equations(lines);
    }
    pure
}

/// An explicit acceleration as people write it. Where the equation of `q_j` involves no other
/// acceleration (one coordinate, or a diagonal row of `M`), that is `f_j/M_jj`, each shaped on
/// its own (`θ̈ = −m g b sin θ/Ĩ` keeps the inertia `Ĩ` whole), when that prints shorter than
/// the single fraction of the normal form.
#[must_use]
pub fn acceleration(equations: &Equations, notation: &Notation, j: usize, a: Expr) -> Math {
    let single = notation.math(a);
    let (Some(row), Some(f)) = (equations.mass_matrix().get(j), equations.forcing().get(j)) else {
        return single;
    };
    let diagonal = row
        .iter()
        .enumerate()
        .all(|(k, m)| k == j || m.is_literal_zero());
    if !diagonal || !equations.constraint_names().is_empty() {
        return single;
    }
    let Some(m) = row.get(j) else {
        return single;
    };
    let quotient = Math::expr(Expr::mul_all([
        notation.shape(*f),
        notation.shape(*m).powi(-1),
    ]));
    if quotient.unicode.chars().count() < single.unicode.chars().count() {
        quotient
    } else {
        single
    }
}

/// The conditions under which a first integral holds, `C = 0 and F = 0`; `None` when it
/// holds outright.
#[must_use]
pub fn conditions_text(f: &mechanics::FirstIntegral) -> Option<String> {
    if f.conditions.is_empty() {
        return None;
    }
    let zeros: Vec<String> = f
        .conditions
        .iter()
        .map(|c| format!("{} = 0", Math::expr(*c).unicode))
        .collect();
    Some(zeros.join(" and "))
}

fn first_integrals_section(equations: &Equations, notation: &Notation) -> Section {
    let mut s = Section::new("First integrals", 2);
    if equations.first_integrals().is_empty() {
        s.paragraph(
            "None found: the energy is not conserved (forces that depend on the state or on \
             time, moving constraints) and no coordinate is cyclic.",
        );
        return s;
    }
    for f in equations.first_integrals() {
        let condition = conditions_text(f)
            .map(|c| format!(", while {c}"))
            .unwrap_or_default();
        let (what, label) = match &f.coordinate {
            Some(q) => (
                format!(
                    "the momentum conjugate to the cyclic coordinate {}",
                    coordinate(q).unicode
                ),
                Math::label(
                    format!("p_{}", coordinate(q).unicode),
                    format!("p_{{{}}}", coordinate(q).latex),
                ),
            ),
            None if f.kind == "energy" => {
                ("the energy h = K + V".to_string(), Math::label("h", "h"))
            }
            None => (
                "the Jacobi integral h = Σ q̇ ∂ℒ/∂q̇ − ℒ (not K + V: the constraints move)"
                    .to_string(),
                Math::label("h", "h"),
            ),
        };
        s.paragraph(format!("Conserved{condition}: {what}."));
        s.equations(vec![Equation::new(label, notation.math(f.value))]);
    }
    // The seed's second method for one degree of freedom: dh/dt = q̇ · (equation of motion).
    let coordinates = equations.coordinates();
    if let ([q], Some(energy)) = (
        coordinates,
        equations
            .first_integrals()
            .iter()
            .find(|f| f.coordinate.is_none() && f.conditions.is_empty()),
    ) {
        let qd = Expr::rate(q, 1);
        let dh = energy.value.dt().normal();
        let per_rate = (dh / qd).normal();
        let lhs = equations.lagrange_lhs()[0];
        if per_rate.equals(lhs) {
            s.remark(format!(
                "Energy method (one degree of freedom): dh/dt = {} · ({}) = 0; for motions with \
                 {} ≠ 0 this is the equation of motion again.",
                rate(q, 1).unicode,
                notation.math(lhs).unicode,
                rate(q, 1).unicode
            ));
        }
    }
    s
}

/// The parameters and their values (`symbolic` where the model gives none), as a table;
/// none without parameters.
pub(crate) fn parameter_table(system: &System, notation: &Notation) -> Option<Block> {
    let rows: Vec<Vec<Cell>> = (system.parameters().iter())
        .map(|(name, value)| {
            vec![
                Cell::Math(Math::expr(Expr::symbol(name))),
                match value {
                    Some(v) => Cell::Math(notation.math(*v)),
                    None => Cell::Text("symbolic".into()),
                },
            ]
        })
        .collect();
    (!rows.is_empty()).then(|| Block::Table {
        header: vec!["parameter".into(), "value".into()],
        rows,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use mechanics::{derive, Load, Particle};

    fn pendulum() -> (System, Equations) {
        let th = Expr::coordinate("theta");
        let (m, l, g) = (Expr::symbol("m"), Expr::symbol("l"), Expr::symbol("g"));
        let mut system = System::new();
        system.add_coordinate("theta");
        system.add_parameter("m", Some(Expr::int(1)));
        system.add_particle(Particle {
            name: "P".into(),
            mass: m,
            position: [l * th.sin(), -(l * th.cos()), Expr::zero()],
        });
        system.add_load(Load::Gravity([Expr::zero(), -g, Expr::zero()]));
        let eq = derive(&system).expect("derives");
        (system, eq)
    }

    #[test]
    fn the_pendulum_is_solved_step_by_step() {
        let (system, eq) = pendulum();
        let doc = solution_document("Simple pendulum", &system, &eq);
        let titles: Vec<&str> = doc.sections.iter().map(|s| s.title.as_str()).collect();
        assert_eq!(
            titles,
            [
                "The system",
                "Kinematics",
                "Lagrangian function",
                "Lagrange equations (II type)",
                "First integrals"
            ]
        );
        let text = doc.to_text();
        assert!(text.contains("  r_P = ℓ sin θ x̂ − ℓ cos θ ŷ"), "{text}");
        assert!(text.contains("  v_P = ℓ θ̇ cos θ x̂ + ℓ θ̇ sin θ ŷ"), "{text}");
        assert!(text.contains("  ∂ℒ/∂θ̇ = m ℓ² θ̇"), "{text}");
        assert!(text.contains("  d/dt(∂ℒ/∂θ̇) = m ℓ² θ̈"), "{text}");
        assert!(text.contains("  ∂ℒ/∂θ = −m g ℓ sin θ"), "{text}");
        assert!(text.contains("  Q_θ = 0"), "{text}");
        assert!(text.contains("  θ̈ = −g sin θ/ℓ"), "{text}");
        assert!(text.contains("Energy method"), "{text}");
        let md = doc.to_markdown();
        assert!(
            md.contains(r"\frac{\partial \mathcal{L}}{\partial \dot{\theta}} &= "),
            "{md}"
        );
    }
}
