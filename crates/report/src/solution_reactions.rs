//! The "Constraint reactions" section of a solution: each reaction the model asks for, by
//! Lagrange's equations of the first kind and by Newton–Euler, whether the two agree, and
//! where a one-sided constraint (a contact, a rope) would be lost.

use cas::Expr;
use mechanics::{Reaction, ReleaseKind, Unilateral};

use crate::document::{Equation, Math, Notation, Section};
use crate::reaction_working::{working_blocks, Working};
use crate::UnilateralReport;

/// The section, from the reactions, their unilateral analyses and their working (same
/// order; a reaction without working, or past the end of `working`, shows only its result).
#[must_use]
pub fn reactions_section(
    reactions: &[Reaction],
    unilateral: &[Option<UnilateralReport>],
    working: &[Option<Working>],
    notation: &Notation,
) -> Section {
    let mut s = Section::new("Constraint reactions", 2);
    s.paragraph(
        "Each constraint is released (a redundant coordinate per constrained direction) and its \
         reaction found twice: as the Lagrange multiplier of the released system (Lagrange I) \
         and from the momentum and angular-momentum equations of the bodies it acts on \
         (Newton–Euler), with the accelerations eliminated by the pure equations of motion. \
         Components are in the inertial frame; the force is the one acting on the bodies named.",
    );
    for (i, r) in reactions.iter().enumerate() {
        let kind = r.kind.map_or("constraint", ReleaseKind::word);
        let title = match &r.point {
            Some((point, _)) => format!(
                "{} — {kind} at {point}, on {}",
                r.name,
                r.members.join(", ")
            ),
            None => format!("{} — {kind}, generalized reaction", r.name),
        };
        s.paragraph(format!("{title}:"));
        if let Some(w) = working.get(i).and_then(Option::as_ref) {
            working_blocks(&mut s, r, w, notation);
        }
        let symbol = match r.kind {
            Some(ReleaseKind::Rope) => "T",
            _ => "N",
        };
        let (r, definitions) = &named(r, notation);
        let mut lines = definitions.clone();
        lines.extend(reaction_lines(r, symbol, notation));
        s.equations(lines);
        if let Some(c) = &r.unbalanced_couple {
            let (c, definitions) = named_vector(c, notation);
            let couple = notation.vector(&c);
            // A long couple goes in a display of its own, not in the sentence.
            let (what, display) = if couple.unicode.chars().count() > 60 || !definitions.is_empty()
            {
                let label = Math::label(
                    format!("M_{}", r.name),
                    format!(r"\vec{{M}}_{{\mathrm{{{}}}}}", latex_name(&r.name)),
                );
                let what = format!("{} below", label.unicode);
                let mut display = definitions;
                display.push(Equation::new(label, couple));
                (what, display)
            } else {
                (couple.unicode, Vec::new())
            };
            s.remark(format!(
                "The motion also needs a couple about this point, {what}, which a {kind} does not \
                 transmit: loads the release cannot attribute to these bodies act on them (other \
                 supports built into the coordinates, whose forces R then includes, or generalized \
                 forces such as the seed's C), or the joint transmits a couple (ask for a clamp).",
            ));
            s.equations(display);
        }
        if r.along.is_some() {
            one_sided(
                &mut s,
                symbol,
                unilateral.get(i).and_then(Option::as_ref),
                notation,
            );
        }
        let methods: Vec<&str> = r.methods.iter().map(|m| m.name()).collect();
        s.paragraph(format!(
            "Methods: {} — {}.",
            methods.join(", "),
            r.agreement.verdict()
        ));
    }
    s
}

/// A reaction's force projected on the axes the model named (`reaction NAME: … in frame R`,
/// `… along n`), for [`projection_blocks`].
#[derive(Clone, Copy, Debug)]
pub struct Projection<'a> {
    /// The reaction's name.
    pub name: &'a str,
    /// What it is projected on: `frame B`, or the direction as written.
    pub onto: &'a str,
    /// Each axis's label (`B.x`, or `along`) and the component.
    pub components: &'a [(String, Expr)],
    /// The components at each equilibrium (`None` where they do not evaluate).
    pub at_equilibria: &'a [Option<Vec<f64>>],
}

/// Appends to the reactions section a projected reaction: the components `R · e` as the
/// change of basis gives them, and their values at the equilibria.
pub fn projection_blocks(s: &mut Section, p: &Projection<'_>, notation: &Notation) {
    let (unit_u, unit_l) = ("ê", r"\hat{e}");
    let sentence = if p.onto.starts_with("frame ") {
        format!(
            "{} in {}: the inertial components above dotted with the frame's unit vectors.",
            p.name, p.onto
        )
    } else {
        format!(
            "{} along {}: the force above dotted with the unit vector {unit_u} along it.",
            p.name, p.onto
        )
    };
    s.paragraph(sentence);
    let r_u = format!("R_{}", p.name);
    let r_l = format!(r"\vec{{R}}_{{\mathrm{{{}}}}}", latex_name(p.name));
    let labels: Vec<Math> = p
        .components
        .iter()
        .map(|(axis, _)| match axis.split_once('.') {
            Some((frame, a)) => Math::label(
                format!("{r_u} · {frame}.{a}"),
                format!(
                    r"{r_l} \cdot \hat{{{a}}}_{{\mathrm{{{}}}}}",
                    latex_name(frame)
                ),
            ),
            None => Math::label(
                format!("{r_u} · {unit_u}"),
                format!(r"{r_l} \cdot {unit_l}"),
            ),
        })
        .collect();
    let exprs: Vec<Expr> = p.components.iter().map(|(_, e)| *e).collect();
    let named = notation.name_shared(&exprs);
    let mut lines = named.definitions;
    for (label, e) in labels.iter().zip(&named.exprs) {
        lines.push(Equation::new(label.clone(), notation.math(*e)));
    }
    s.equations(lines);
    let values: Vec<String> = p
        .at_equilibria
        .iter()
        .enumerate()
        .filter_map(|(k, v)| {
            let v = v.as_ref()?;
            let listed: Vec<String> = labels
                .iter()
                .zip(v)
                .map(|(l, x)| format!("{} = {x:.4}", l.unicode))
                .collect();
            Some(format!("at equilibrium {k}: {}", listed.join(", ")))
        })
        .collect();
    if !values.is_empty() {
        s.paragraph(format!("At rest: {}.", values.join("; ")));
    }
}

/// `r` with the long sums its components share named ([`Notation::name_shared`]), and the
/// definitions of the names it introduces.
fn named(r: &Reaction, notation: &Notation) -> (Reaction, Vec<Equation>) {
    let vectors = [&r.force, &r.couple];
    let mut exprs: Vec<Expr> = vectors
        .iter()
        .filter_map(|v| v.as_ref())
        .flat_map(|v| v.iter().copied())
        .collect();
    exprs.extend(r.along.iter().map(|(value, _)| *value));
    exprs.extend(r.generalized.iter().map(|(_, e)| *e));
    let named = notation.name_shared(&exprs);
    let mut out = r.clone();
    let mut next = named.exprs.into_iter();
    for v in [&mut out.force, &mut out.couple].into_iter().flatten() {
        for c in v.iter_mut() {
            *c = next.next().unwrap_or(*c);
        }
    }
    if let Some((value, _)) = &mut out.along {
        *value = next.next().unwrap_or(*value);
    }
    for (_, e) in &mut out.generalized {
        *e = next.next().unwrap_or(*e);
    }
    (out, named.definitions)
}

/// A vector with the long sums its components share named, and the new definitions.
fn named_vector(v: &[Expr; 3], notation: &Notation) -> ([Expr; 3], Vec<Equation>) {
    let named = notation.name_shared(v);
    let mut out = *v;
    for (c, n) in out.iter_mut().zip(named.exprs) {
        *c = n;
    }
    (out, named.definitions)
}

/// The force, couple, normal force or tension, and generalized reactions of `r`.
fn reaction_lines(r: &Reaction, symbol: &str, notation: &Notation) -> Vec<Equation> {
    let mut lines = Vec::new();
    if let Some(force) = &r.force {
        lines.push(Equation::new(
            Math::label(
                format!("R_{}", r.name),
                format!(r"\vec{{R}}_{{\mathrm{{{}}}}}", latex_name(&r.name)),
            ),
            notation.vector(force),
        ));
    }
    if let Some(couple) = &r.couple {
        lines.push(Equation::new(
            Math::label(
                format!("C_{}", r.name),
                format!(r"\vec{{C}}_{{\mathrm{{{}}}}}", latex_name(&r.name)),
            ),
            notation.vector(couple),
        ));
    }
    if let Some((value, _)) = &r.along {
        lines.push(Equation::new(
            Math::label(symbol, symbol),
            notation.math(*value),
        ));
    }
    for (q, e) in &r.generalized {
        let q_math = Math::expr(cas::Expr::coordinate(q));
        lines.push(Equation::new(
            Math::label(
                format!("Q^R_{}", q_math.unicode),
                format!("Q^R_{{{}}}", q_math.latex),
            ),
            notation.math(*e),
        ));
    }
    lines
}

/// What a one-sided constraint's sign says: the value along the motion and where, from the
/// initial state, the constraint is lost or kept.
fn one_sided(
    s: &mut Section,
    symbol: &str,
    unilateral: Option<&UnilateralReport>,
    notation: &Notation,
) {
    let sense = if symbol == "T" {
        "a rope pulls only: it goes slack where T < 0"
    } else {
        "a contact pushes only: it is lost where N < 0"
    };
    s.paragraph(format!("One-sided: {sense}."));
    if let Some(u) = unilateral {
        if let Some(along) = u.along_motion {
            s.equations(vec![Equation::new(
                Math::label(
                    format!("{symbol} (along the motion, h = h₀)"),
                    format!(r"{symbol}\big|_{{h = h_0}}"),
                ),
                notation.math(along),
            )]);
        }
        match &u.scan {
            Some(Unilateral::Lost {
                coordinate,
                value,
                rate,
            }) => {
                s.remark(format!(
                    "From the initial state, {symbol} changes sign at {coordinate} = {value:.4} \
                     (rate {rate:.4}): the constraint is lost there, and the model no longer \
                     describes the motion beyond that point."
                ));
            }
            Some(Unilateral::LostAtStart) => {
                s.remark(format!(
                    "{symbol} < 0 at the initial state: the constraint does not hold."
                ));
            }
            Some(Unilateral::Kept {
                coordinate,
                turning_point: Some(q),
            }) => {
                s.remark(format!(
                    "From the initial state, {symbol} keeps its sign up to the turning point \
                     {coordinate} = {q:.4}: the constraint holds for the whole motion."
                ));
            }
            _ => {}
        }
    }
}

fn latex_name(name: &str) -> String {
    name.replace('_', r"\_")
}
