//! The stability condition of a steady motion in the parameters (`mechanics::kane`'s steady
//! condition): the motion of the model's `initial` statement given exactly (its expressions,
//! `x' = v`, rather than their values), the parameters with positive values taken positive,
//! and how `linearize` and `solve` print it (as `lagrange equilibria` prints the holonomic
//! conditions).

use cas::print::{to_sympy, to_unicode};
use cas::{Expr, Symbol};
use mechanics::kane::{ExactSteadyMotion, SteadyLinearization, SteadySpectrum};
use mechanics::stability_condition::{StabilityCondition, Verdict};
use serde_json::{json, Value};

use crate::{Analysis, Error};

impl Analysis {
    /// The stability condition of the steady motion in the parameters, `None` where the
    /// symbolic route does not apply or passes its limits (the Whipple bicycle: the numeric
    /// results stand alone there).
    ///
    /// # Errors
    /// As [`Analysis::kane_system`].
    pub fn steady_condition(
        &self,
        lin: &SteadyLinearization,
        spectrum: &SteadySpectrum,
    ) -> Result<Option<StabilityCondition>, Error> {
        let (system, values) = self.kane_system()?;
        let motion = self.exact_steady_motion(lin);
        let positive_names = self.positive_parameters();
        let positive = |s: Symbol| positive_names.iter().any(|n| n == s.name());
        // Past the size or work limits there is no condition to state; the numeric verdict
        // is the answer then.
        Ok(system
            .steady_condition(&motion, &values, (lin, spectrum), &positive)
            .ok()
            .flatten())
    }

    /// The steady motion with the `initial` statement's expressions where they give the
    /// values (and no value was set over them), exact numbers of the linearization's
    /// configuration otherwise.
    fn exact_steady_motion(&self, lin: &SteadyLinearization) -> ExactSteadyMotion {
        let coordinates = self.system().coordinates().to_vec();
        let mut motion = ExactSteadyMotion {
            configuration: lin
                .configuration
                .iter()
                .map(|x| mechanics::kane::exact_value(*x))
                .collect(),
            rates: vec![None; coordinates.len()],
        };
        let given = self.given_rates();
        for (j, q) in coordinates.iter().enumerate() {
            if let Some(e) = self.initial_expression(q, false) {
                motion.configuration[j] = e;
            }
            if given.contains(q) {
                motion.rates[j] = self.initial_expression(q, true).or_else(|| {
                    let value = self.initial_value(q, true).ok()?;
                    Some(mechanics::kane::exact_value(value))
                });
            }
        }
        motion
    }

    /// The `initial` statement's expression for `q` (or its rate) when its value is the one
    /// in force (not replaced by a value set).
    fn initial_expression(&self, q: &str, rate: bool) -> Option<Expr> {
        let source = self.source()?;
        let model = &source.model;
        let initial = model
            .initial()
            .iter()
            .find(|i| i.rate == rate && model.coordinate(i.coordinate).name.name == q)?;
        let text = model.display(&initial.value).to_string();
        let expr = crate::expression::parse(&text, self.system().coordinates()).ok()?;
        let values = self.values().ok()?;
        let env = |s: Symbol| values.iter().find(|(n, _)| n == s.name()).map(|(_, v)| *v);
        let value = expr.eval(&env).ok()?;
        let in_force = self.initial_value(q, rate).ok()?;
        ((value - in_force).abs() <= 1e-12 * value.abs().max(1.0)).then_some(expr)
    }

    /// The solution's section on the steady motion of the `initial` statement: the verdict
    /// relative to the family of steady motions, why, the eigenvalues, and the condition in
    /// the parameters where there is one.
    pub(crate) fn steady_section(&self) -> report::document::Section {
        let mut section = report::document::Section::new("Steady motion and its stability", 2);
        let lin = match self.steady_linearization() {
            Ok(lin) => lin,
            Err(why) => {
                section.paragraph(format!("Not analysed: {why}."));
                return section;
            }
        };
        let spectrum = match lin.spectrum() {
            Ok(s) => s,
            Err(why) => {
                section.paragraph(format!("Not analysed: {why}."));
                return section;
            }
        };
        let eigenvalues: Vec<String> = spectrum
            .eigenvalues
            .iter()
            .map(|(re, im)| crate::steady_print::complex_text(*re, *im, 6))
            .collect();
        section.paragraph(format!(
            "Linearized about the steady motion of the initial values by Kane's method (states {}): \
             eigenvalues {}. Verdict: {}; {}.",
            lin.states.join(", "),
            eigenvalues.join(", "),
            spectrum.verdict.words(),
            crate::steady_print::verdict_reason(&spectrum)
        ));
        if let Ok(Some(c)) = self.steady_condition(&lin, &spectrum) {
            section.paragraph(format!("{}.", condition_lines(&c).join("; ")));
        }
        section
    }
}

/// The lines `linearize` prints for the condition.
#[must_use]
pub fn condition_lines(c: &StabilityCondition) -> Vec<String> {
    let mut lines = vec![format!(
        "in the parameters: {} ({})",
        c.sentence(to_unicode),
        c.criterion.sentence()
    )];
    if !c.characteristic.is_empty() {
        lines.push(format!(
            "characteristic polynomial (the family's zero roots divided out): {}",
            to_unicode(polynomial(&c.characteristic))
        ));
    }
    lines.extend(c.boundary_sentences(to_unicode));
    lines
}

/// The condition as JSON (docs/json.md, "Steady motions").
#[must_use]
pub fn condition_json(c: &StabilityCondition) -> Value {
    let (verdict, inequalities) = match &c.verdict {
        Verdict::Always => ("always", Vec::new()),
        Verdict::Never => ("never", Vec::new()),
        Verdict::When(all) => ("when", all.iter().map(|i| i.text(to_sympy)).collect()),
        _ => ("unknown", Vec::new()),
    };
    json!({
        "coordinates": c.coordinates,
        "criterion": c.criterion.sentence(),
        "characteristic": to_sympy(polynomial(&c.characteristic)),
        "tests": c.tests.iter().map(|e| to_sympy(*e)).collect::<Vec<_>>(),
        "verdict": verdict,
        "inequalities": inequalities,
        "sentence": c.sentence(to_unicode),
    })
}

/// `c₀ + c₁ λ + …` as one expression.
fn polynomial(c: &[Expr]) -> Expr {
    // A symbol none of the coefficients holds (a parameter may be called `lambda`).
    let mut names: Vec<String> = Vec::new();
    let mut stack: Vec<Expr> = c.to_vec();
    while let Some(e) = stack.pop() {
        if let cas::Node::Symbol(s) = e.node() {
            names.push(s.name().to_owned());
        }
        stack.extend_from_slice(e.children());
    }
    let lambda = mechanics::kane::fresh_lambda(&names);
    Expr::add_all(c.iter().enumerate().map(|(k, ck)| {
        let power = i64::try_from(k).unwrap_or(i64::MAX);
        *ck * lambda.powi(power)
    }))
    .normal()
}
