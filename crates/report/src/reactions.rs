//! The JSON rendering of constraint reactions, [`reactions_json`] (schema in `docs/json.md`,
//! section "reactions").

use cas::print::to_sympy;
use cas::print::to_unicode;
use mechanics::{Reaction, Unilateral, Vector};
use serde_json::{json, Value};

fn vector(v: &Vector) -> Value {
    v.iter().map(|e| Value::String(to_sympy(*e))).collect()
}

/// What is known of a unilateral reaction along the motion (see `mechanics::scan_unilateral`).
#[derive(Clone, Debug, Default)]
pub struct UnilateralReport {
    /// The reaction along the motion, with `h_0` the value of the energy integral.
    pub along_motion: Option<cas::Expr>,
    /// Where it changes sign from the model's initial state.
    pub scan: Option<Unilateral>,
}

fn unilateral_json(u: &UnilateralReport) -> Value {
    let scan = match &u.scan {
        Some(Unilateral::Lost {
            coordinate,
            value,
            rate,
        }) => json!({ "lost": true, "coordinate": coordinate, "value": value, "rate": rate }),
        Some(Unilateral::LostAtStart) => json!({ "lost": true, "at_start": true }),
        Some(Unilateral::Kept {
            coordinate,
            turning_point,
        }) => json!({ "lost": false, "coordinate": coordinate, "turning_point": turning_point }),
        _ => Value::Null,
    };
    json!({
        "along_motion": u.along_motion.map(to_sympy),
        "from_initial_state": scan,
    })
}

/// Reactions as JSON: each with its `name`, `kind`, `point`, the `bodies` it acts on, its
/// `components` in the inertial frame (SymPy syntax, functions of `q`, `q_d`, `t`), and the
/// `methods` that agree. `unilateral[i]` belongs to `reactions[i]` (missing entries: none).
#[must_use]
pub fn reactions_json(
    coordinates: &[String],
    reactions: &[Reaction],
    unilateral: &[Option<UnilateralReport>],
) -> Value {
    let list: Vec<Value> = reactions
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let unilateral = unilateral.get(i).and_then(Option::as_ref).map(unilateral_json);
            json!({
                "name": r.name,
                "kind": r.kind.map_or(if r.driving { "driving" } else { "generalized" }, |k| k.word()),
                "point": r.point.as_ref().map(|(name, at)| json!({ "name": name, "position": vector(at) })),
                "bodies": r.members,
                "components": r.force.as_ref().map(vector),
                "couple": r.couple.as_ref().map(vector),
                "friction": r.friction.as_ref().map(vector),
                "unbalanced_couple": r.unbalanced_couple.as_ref().map(vector),
                "along": r.along.as_ref().map(|(value, direction)| json!({
                    "value": to_sympy(*value),
                    "direction": vector(direction),
                    "unilateral": unilateral,
                })),
                "generalized": r.generalized.iter().map(|(q, e)| json!({ "coordinate": q, "value": to_sympy(*e) })).collect::<Vec<_>>(),
                "multipliers": r.multipliers.iter().map(|e| to_sympy(*e)).collect::<Vec<_>>(),
                "methods": r.methods.iter().map(|m| m.name()).collect::<Vec<_>>(),
                "agreement": r.agreement.name(),
            })
        })
        .collect();
    json!({
        "schema": crate::SCHEMA,
        "coordinates": coordinates,
        "reactions": list,
    })
}

/// One reaction for the terminal: its force, couple, friction, the one-sided analysis, the
/// generalized reaction and multipliers, and whether the methods agree.
#[must_use]
pub fn reaction_text(r: &Reaction, unilateral: Option<&UnilateralReport>) -> String {
    let kind = r.kind.map_or("constraint", |k| k.word());
    let mut lines = vec![match &r.point {
        Some((point, _)) => format!(
            "{} — {kind} at {point}, on {}:",
            r.name,
            r.members.join(", ")
        ),
        None if r.driving => format!(
            "{} — driven coordinate, the generalized force that drives it:",
            r.name
        ),
        None => format!("{} — {kind}, generalized reaction:", r.name),
    }];
    if let Some(f) = &r.force {
        lines.extend(components("R", f, true));
    }
    if let Some(c) = &r.couple {
        lines.extend(components("C", c, true));
    }
    if let Some(c) = &r.unbalanced_couple {
        let parts: Vec<String> = components("C", c, false)
            .iter()
            .map(|l| l.trim().to_owned())
            .collect();
        lines.push(format!(
            "  note: the motion also needs a couple about this point ({}), which a {kind} does not transmit: loads the release cannot attribute to these bodies act on them (other supports built into the coordinates, whose forces R then includes, or generalized forces), or the joint transmits a couple (ask for a clamp)",
            parts.join(", ")
        ));
    }
    if let Some(f) = &r.friction {
        lines.extend(components("friction F", f, false));
    }
    if let Some((value, _)) = &r.along {
        lines.extend(one_sided(r, *value, unilateral));
    }
    let label = if r.driving { "Q_drive" } else { "Q^R" };
    lines.extend(
        r.generalized
            .iter()
            .map(|(q, e)| format!("  {label}_{q} = {}", to_unicode(*e))),
    );
    lines.extend(
        r.multipliers
            .iter()
            .enumerate()
            .map(|(k, l)| format!("  λ{} = {}", k + 1, to_unicode(*l))),
    );
    let methods: Vec<&str> = r.methods.iter().map(|m| m.name()).collect();
    lines.push(format!(
        "  methods: {} — {}",
        methods.join(", "),
        r.agreement.verdict()
    ));
    lines.join("\n") + "\n"
}

/// `  {name}_x = …` for each non-zero component; `  {name} = 0` when all vanish and
/// `zero_line`.
fn components(name: &str, v: &Vector, zero_line: bool) -> Vec<String> {
    let mut lines: Vec<String> = ["x", "y", "z"]
        .iter()
        .zip(v)
        .filter(|(_, x)| !x.is_zero())
        .map(|(axis, x)| format!("  {name}_{axis} = {}", to_unicode(*x)))
        .collect();
    if lines.is_empty() && zero_line {
        lines.push(format!("  {name} = 0"));
    }
    lines
}

/// A contact's normal force or a rope's tension: its sign rule, its value along the motion,
/// and where it changes sign from the initial state.
fn one_sided(r: &Reaction, value: cas::Expr, unilateral: Option<&UnilateralReport>) -> Vec<String> {
    let (symbol, sign) = match r.kind {
        Some(mechanics::ReleaseKind::Rope) => ("T", "pull only: the rope goes slack where T < 0"),
        _ => ("N", "push only: contact is lost where N < 0"),
    };
    let mut lines = vec![format!("  {symbol} = {}   ({sign})", to_unicode(value))];
    let Some(u) = unilateral else {
        return lines;
    };
    if let Some(along) = u.along_motion {
        lines.push(format!(
            "  along the motion (energy integral h = h₀): {symbol} = {}",
            to_unicode(along)
        ));
    }
    match &u.scan {
        Some(Unilateral::Lost {
            coordinate,
            value,
            rate,
        }) => lines.push(format!(
            "  from the initial state, {symbol} changes sign at {coordinate} = {value:.6} (cos = {:.6}, rate {rate:.6}): the constraint is lost there",
            value.cos()
        )),
        Some(Unilateral::LostAtStart) => lines.push(format!(
            "  {symbol} < 0 at the initial state: the constraint does not hold"
        )),
        Some(Unilateral::Kept {
            coordinate,
            turning_point: Some(q),
        }) => lines.push(format!(
            "  from the initial state, {symbol} keeps its sign up to the turning point {coordinate} = {q:.6}"
        )),
        _ => {}
    }
    lines
}
