//! The stability condition in the parameters at each equilibrium known in closed form
//! (`mechanics::stability_condition`), with the parameters whose values are positive taken
//! positive, and how the reports print it: a line beneath each equilibrium of `lagrange
//! equilibria`, an entry per equilibrium in the JSON, and a flag when the values sit on the
//! condition's boundary (the bead on a parabola at `Ω² = 2 a g`, where every `r` rests).

use cas::print::{to_sympy, to_unicode};
use cas::{Expr, Symbol};
use mechanics::equilibria::{EquilibriumSet, RestEquations, Values};
use mechanics::linearize::LinearModel;
use mechanics::stability_condition::{stability_condition, StabilityCondition};
use serde_json::{json, Value};

/// The condition at equilibrium `i` where the model's coordinates fail (a pole), given
/// which parameters are positive.
pub(crate) type AtPole<'a> = dyn Fn(usize, Positive<'_>) -> Option<StabilityCondition> + 'a;

/// Whether a parameter is taken positive.
pub(crate) type Positive<'a> = &'a dyn Fn(Symbol) -> bool;

/// The condition at each equilibrium (`None` where it is not known in closed form or no
/// criterion applies), and whether the values sit on one of its boundaries.
#[derive(Debug, Clone, Default)]
pub struct Conditions {
    /// One per equilibrium, in the order of the set.
    pub at: Vec<Option<StabilityCondition>>,
    /// One per equilibrium: the index of the boundary the values sit on, if any.
    pub on_boundary: Vec<Option<usize>>,
}

impl Conditions {
    /// The conditions at the equilibria of `set` (one symbolic pass for each exact one);
    /// `at_pole` gives the condition where the model's coordinates fail (crate::chart), by
    /// index, with the positivity of the parameters.
    pub(crate) fn of(
        (model, rest, set): (&LinearModel, &RestEquations, &EquilibriumSet),
        values: &Values,
        positive_names: &[String],
        at_pole: &AtPole<'_>,
    ) -> Conditions {
        let positive = |s: Symbol| {
            positive_names.iter().any(|n| n == s.name())
                && values.get(s.name()).is_some_and(|v| *v > 0.0)
        };
        let at: Vec<Option<StabilityCondition>> = set
            .equilibria
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let exact = e.exact.as_deref()?;
                stability_condition(model, rest, exact, &positive).or_else(|| at_pole(i, &positive))
            })
            .collect();
        let on_boundary = at
            .iter()
            .map(|c| c.as_ref().and_then(|c| boundary_at(c, values)))
            .collect();
        Conditions { at, on_boundary }
    }

    /// The lines printed beneath equilibrium `index` (empty without a condition).
    #[must_use]
    pub fn lines(&self, index: usize) -> Vec<String> {
        let Some(Some(c)) = self.at.get(index) else {
            return Vec::new();
        };
        let mut lines = vec![format!(
            "in the parameters: {} ({})",
            c.sentence(to_unicode),
            c.criterion.sentence()
        )];
        lines.extend(c.boundary_sentences(to_unicode));
        if let Some(Some(k)) = self.on_boundary.get(index) {
            if let Some(b) = c.boundary_sentences(to_unicode).get(*k) {
                lines.push(format!("these values sit on that boundary: {b}"));
            }
        }
        lines
    }

    /// The conditions as JSON (docs/json.md): one entry per equilibrium, `null` where none.
    #[must_use]
    pub fn json(&self) -> Value {
        self.at
            .iter()
            .zip(&self.on_boundary)
            .map(|(c, on)| c.as_ref().map_or(Value::Null, |c| condition_json(c, *on)))
            .collect()
    }
}

/// `text` (as `lagrange equilibria` prints it) with each equilibrium's condition beneath its
/// stability line.
pub(crate) fn with_condition_lines(text: &str, conditions: &Conditions) -> String {
    let mut out = String::with_capacity(text.len());
    let mut current: Option<usize> = None;
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix('#') {
            current = rest.split(':').next().and_then(|k| k.parse().ok());
        }
        out.push_str(line);
        out.push('\n');
        let body = line.trim_start();
        let indent = &line[..line.len() - body.len()];
        let stability_line = !indent.is_empty()
            && ["stable", "unstable", "undecided", "stability not decided"]
                .iter()
                .any(|w| body.starts_with(w));
        if let (Some(k), true) = (current, stability_line) {
            for extra in conditions.lines(k) {
                out.push_str(indent);
                out.push_str(&extra);
                out.push('\n');
            }
        }
    }
    out
}

fn condition_json(c: &StabilityCondition, on_boundary: Option<usize>) -> Value {
    let matrix = |m: &[Vec<Expr>]| -> Value {
        m.iter()
            .map(|row| row.iter().map(|e| to_sympy(*e)).collect::<Vec<_>>())
            .collect()
    };
    let inequalities: Vec<String> = match &c.verdict {
        mechanics::stability_condition::Verdict::When(all) => {
            all.iter().map(|i| i.text(to_sympy)).collect()
        }
        _ => Vec::new(),
    };
    let verdict = match &c.verdict {
        mechanics::stability_condition::Verdict::Always => "always",
        mechanics::stability_condition::Verdict::Never => "never",
        _ => "when",
    };
    json!({
        "coordinates": c.coordinates,
        "criterion": c.criterion.sentence(),
        "M0": matrix(&c.mass),
        "G": matrix(&c.gyroscopic),
        "K": matrix(&c.stiffness),
        "tests": c.tests.iter().map(|e| to_sympy(*e)).collect::<Vec<_>>(),
        "verdict": verdict,
        "inequalities": inequalities,
        "sentence": c.sentence(to_unicode),
        "boundaries": c.boundaries.iter().map(|b| json!({
            "relation": b.relation.text(to_sympy).replacen(['<', '>'], "==", 1),
            "family": b.family,
        })).collect::<Vec<_>>(),
        "on_boundary": on_boundary,
    })
}

/// The boundary the values sit on (its two sides equal to rounding), if any.
fn boundary_at(c: &StabilityCondition, values: &Values) -> Option<usize> {
    let env = |s: Symbol| values.get(s.name()).copied();
    c.boundaries.iter().position(|b| {
        let (Ok(greater), Ok(less)) = (b.relation.greater.eval(&env), b.relation.less.eval(&env))
        else {
            return false;
        };
        (greater - less).abs() <= 1e-9 * greater.abs().max(less.abs()).max(f64::MIN_POSITIVE)
    })
}

impl crate::Analysis {
    /// Adds the stability conditions in the parameters to the solution's section on the
    /// equilibria (its last paragraphs), when there are any.
    pub(crate) fn condition_paragraphs(
        &self,
        sections: &mut [report::document::Section],
        equilibria: &crate::Equilibria,
    ) {
        let conditions = &equilibria.conditions;
        let paragraphs = report::solution_equilibria::stability_condition_paragraphs(
            &conditions.at,
            &conditions.on_boundary,
        );
        let title = "Equilibria and their stability";
        if let Some(section) = sections.iter_mut().find(|s| s.title == title) {
            for p in paragraphs {
                section.paragraph(p);
            }
        }
    }
}
