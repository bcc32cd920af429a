//! The working of a reaction, the way a course solution shows it before the result: the
//! released coordinates (or the constraint's multiplier) and the Lagrange equations that give
//! the reaction, with the accelerations still in them. The result that follows in the report
//! is these equations with the accelerations of the pure equations of motion put in.
//!
//! [`Working`] is filled by the library (which derives the released system) and written here
//! by [`working_blocks`]; where the equations would fill pages, one line says so instead.

use cas::Expr;
use mechanics::{Reaction, Vector};

use crate::document::{Equation, Math, Notation, Section};

/// Past this many characters (Unicode, all lines together) the working is not written out:
/// a course solution shows a page of terms to nobody.
pub const WORKING_MAX_CHARS: usize = 900;

/// How a reaction is worked out, for [`working_blocks`].
#[derive(Clone, Debug)]
#[non_exhaustive]
pub enum Working {
    /// A reaction at a point: the bodies released by displacement coordinates `u_i` along
    /// unit directions `d_i`; the Lagrange equation of `u_i` at `u = u̇ = ü = 0` is `R · d_i`.
    Released {
        /// The point released.
        point: String,
        /// Each displacement: its axis label (`x`, `n`), its direction, and its equation's
        /// left side `d/dt ∂ℒ/∂u̇ − ∂ℒ/∂u − Q_u` at `u = 0` (accelerations not eliminated);
        /// those identically zero are left out.
        equations: Vec<(String, Vector, Expr)>,
    },
    /// A constraint kept with its multipliers `λ_k`: each coordinate's Lagrange equation of
    /// the first kind, `d/dt ∂ℒ/∂q̇_j − ∂ℒ/∂q_j − Q_j = −Σ_k a_kj λ_k`.
    Multiplier {
        /// Each coordinate: its name, the left side (accelerations not eliminated) and the
        /// right side `−Σ_k a_kj λ_k` with the multipliers written `λ` (`λ1`, `λ2`, … for
        /// several rows).
        equations: Vec<(String, Expr, Expr)>,
    },
    /// A constraint eliminated by integration (a gear's): the system without it, each
    /// coordinate's equation `d/dt ∂ℒ/∂q̇_j − ∂ℒ/∂q_j − Q_j = Q^R_j`.
    Freed {
        /// Each coordinate: its name and the left side (accelerations not eliminated).
        equations: Vec<(String, Expr)>,
    },
    /// The equations are too long to be of use written out.
    TooLarge {
        /// Their terms, all together.
        terms: usize,
    },
}

/// The multiplier symbol of row `k` of `rows` rows: `λ`, or `λ1`, `λ2`, ….
#[must_use]
pub fn multiplier_symbol(k: usize, rows: usize) -> Expr {
    if rows == 1 {
        Expr::symbol("lambda")
    } else {
        Expr::symbol(&format!("lambda{}", k + 1))
    }
}

/// Appends the working of reaction `r` to the section: a sentence and the equations, or
/// one sentence when they are longer than [`WORKING_MAX_CHARS`]. A coordinate on which the
/// generalized reaction is zero is left out (its equation is its equation of motion).
pub fn working_blocks(s: &mut Section, r: &Reaction, working: &Working, notation: &Notation) {
    let working = &acting(r, working);
    let working = if working_size(working, notation) > WORKING_MAX_CHARS {
        &Working::TooLarge {
            terms: working_terms(working),
        }
    } else {
        working
    };
    match working {
        Working::Released { point, equations } => released(s, &r.name, point, equations, notation),
        Working::Multiplier { equations } => multiplier(s, equations, notation),
        Working::Freed { equations } => freed(s, equations, notation),
        Working::TooLarge { terms } => {
            s.paragraph(format!(
                "Working: the Lagrange equations that give this reaction have {terms} terms \
                 together; written out they would fill pages, so only the result is given."
            ));
        }
    }
}

/// The number of characters the working would take in Unicode: what decides whether it is
/// written out ([`WORKING_MAX_CHARS`]).
#[must_use]
pub fn working_size(working: &Working, notation: &Notation) -> usize {
    let exprs: Vec<Expr> = match working {
        Working::Released { equations, .. } => equations.iter().map(|(_, _, e)| *e).collect(),
        Working::Multiplier { equations } => {
            equations.iter().flat_map(|(_, l, r)| [*l, *r]).collect()
        }
        Working::Freed { equations } => equations.iter().map(|(_, e)| *e).collect(),
        Working::TooLarge { .. } => return 0,
    };
    exprs
        .iter()
        .map(|e| notation.math(*e).unicode.chars().count())
        .sum()
}

/// The terms of the working's expressions, all together.
fn working_terms(working: &Working) -> usize {
    let terms = |e: Expr| match e.normal().node() {
        cas::Node::Add(children) => children.len(),
        _ => 1,
    };
    match working {
        Working::Released { equations, .. } => equations.iter().map(|(_, _, e)| terms(*e)).sum(),
        Working::Multiplier { equations } => equations.iter().map(|(_, l, _)| terms(*l)).sum(),
        Working::Freed { equations } => equations.iter().map(|(_, e)| terms(*e)).sum(),
        Working::TooLarge { terms } => *terms,
    }
}

/// The working without the coordinates on which the generalized reaction `r` is zero.
fn acting(r: &Reaction, working: &Working) -> Working {
    let acts = |q: &String| {
        r.generalized
            .iter()
            .find(|(name, _)| name == q)
            .is_none_or(|(_, value)| !value.is_zero())
    };
    match working {
        Working::Multiplier { equations } => Working::Multiplier {
            equations: equations
                .iter()
                .filter(|(q, _, _)| acts(q))
                .cloned()
                .collect(),
        },
        Working::Freed { equations } => Working::Freed {
            equations: equations.iter().filter(|(q, _)| acts(q)).cloned().collect(),
        },
        other => other.clone(),
    }
}

fn released(
    s: &mut Section,
    name: &str,
    point: &str,
    equations: &[(String, Vector, Expr)],
    notation: &Notation,
) {
    let moved: Vec<String> = equations
        .iter()
        .map(|(axis, d, _)| format!("u_{axis} {}", direction(d).0))
        .collect();
    let given = if equations.iter().any(|(_, d, _)| direction(d).0 == "ê") {
        " (ê the unit direction the model gives)"
    } else {
        ""
    };
    let (r_u, r_l) = (
        format!("R_{name}"),
        format!(r"\vec{{R}}_{{\mathrm{{{}}}}}", name.replace('_', r"\_")),
    );
    s.paragraph(format!(
        "Working: released, the point {point} moves with the bodies by {}{given}; u = 0 on \
         the constrained motion. The Lagrange equation of each displacement at u = u̇ = ü = 0 \
         is the reaction's component along it:",
        moved.join(" + "),
    ));
    let mut lines = vec![general(
        "u",
        Math::label(
            format!("{r_u} · ∂{point}/∂u"),
            format!(
                r"{r_l} \cdot \frac{{\partial \vec{{r}}_{{{}}}}}{{\partial u}}",
                point.replace('_', r"\_")
            ),
        ),
        notation,
    )];
    lines.extend(equations.iter().map(|(_, d, e)| {
        let (du, dl) = direction(d);
        Equation::new(
            Math::label(format!("{r_u} · {du}"), format!(r"{r_l} \cdot {dl}")),
            notation.math(*e),
        )
    }));
    s.equations(lines);
    s.paragraph("With the accelerations of the equations of motion put in:");
}

/// The general line of a working, `lhs = d/dt ∂ℒ/∂q̇ − ∂ℒ/∂q − Q_q` for coordinate `q`, in the
/// order of the lines under it (the reaction's component on the left).
fn general(q: &str, lhs: Math, notation: &Notation) -> Equation {
    let (lu, ll) = (&notation.lagrangian().unicode, &notation.lagrangian().latex);
    Equation::new(
        lhs,
        Math::label(
            format!("d/dt ∂{lu}/∂{q}̇ − ∂{lu}/∂{q} − Q_{q}"),
            format!(
                r"\frac{{d}}{{dt}} \frac{{\partial {ll}}}{{\partial \dot{{{q}}}}} - \frac{{\partial {ll}}}{{\partial {q}}} - Q_{{{q}}}"
            ),
        ),
    )
}

fn freed(s: &mut Section, equations: &[(String, Expr)], notation: &Notation) {
    s.paragraph(
        "Working: the constraint is integrable and was used to eliminate a coordinate. Without \
         it every coordinate is free, and each one's Lagrange equation gives the generalized \
         reaction on it, written here on the constrained motion:",
    );
    let mut lines = vec![general("q", Math::label("Q^R_q", "Q^R_{q}"), notation)];
    lines.extend(equations.iter().map(|(q, e)| {
        let q_math = Math::expr(Expr::coordinate(q));
        Equation::new(
            Math::label(
                format!("Q^R_{}", q_math.unicode),
                format!("Q^R_{{{}}}", q_math.latex),
            ),
            notation.math(*e),
        )
    }));
    s.equations(lines);
    s.paragraph("With the accelerations of the equations of motion put in:");
}

fn multiplier(s: &mut Section, equations: &[(String, Expr, Expr)], notation: &Notation) {
    s.paragraph(
        "Working: the constraint is kept with its multiplier λ (Lagrange's equations of the \
         first kind; a_q is the constraint's coefficient of q̇ in its velocity form). Each \
         coordinate's equation gives the reaction's generalized component −a_q λ:",
    );
    let mut lines = vec![general(
        "q",
        Math::label("−a_q λ", r"-a_{q} \lambda"),
        notation,
    )];
    lines.extend(
        equations
            .iter()
            .map(|(_, lhs, rhs)| Equation::new(notation.math(*rhs), notation.math(*lhs))),
    );
    s.equations(lines);
    s.paragraph(
        "Solved for λ together with the constraint's equation, with the accelerations of the \
         equations of motion:",
    );
}

/// The unit vector's name in both notations: `x̂`, `ŷ`, `ẑ` for the inertial axes, `ê` for
/// any other direction.
fn direction(d: &Vector) -> (&'static str, &'static str) {
    let axis = |k: usize| {
        d.iter().enumerate().all(|(i, c)| {
            if i == k {
                c.equals(Expr::one())
            } else {
                c.is_zero()
            }
        })
    };
    if axis(0) {
        ("x̂", r"\hat{x}")
    } else if axis(1) {
        ("ŷ", r"\hat{y}")
    } else if axis(2) {
        ("ẑ", r"\hat{z}")
    } else {
        ("ê", r"\hat{e}")
    }
}
