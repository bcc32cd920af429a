//! The JSON rendering of constraint reactions, [`reactions_json`] (schema in `docs/json.md`,
//! section "reactions").

use cas::print::to_sympy;
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
