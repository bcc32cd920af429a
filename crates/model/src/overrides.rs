//! Values set for one run from the command line (`lagrange simulate --set k=40 --set
//! theta=0.3 --set theta_d=1`): [`Model::with_overrides`] returns a copy of the model in which
//! each named parameter or input has the given value, or each named coordinate (or its rate,
//! written `q_d` or `q'`) the given initial value. Parameters defined from the overridden one
//! (`I = m*l^2/3`) follow, since values are read from the model's expressions afterwards.

use crate::diagnostic::{DiagnosticKind, Type};
use crate::model::{Declaration, Expr, ExprKind, InitialValue, Model};

/// Why a `NAME=VALUE` override was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum OverrideError {
    /// No parameter, input or coordinate has this name.
    #[error("`{name}` is not a parameter, an input or a coordinate of the model{}", hint(.known))]
    UnknownName {
        /// The name given.
        name: String,
        /// The names that can be set.
        known: Vec<String>,
    },
    /// The name exists but cannot take a value (a frame, a point, a named constant…).
    #[error("`{name}` is a {kind}: only parameters, inputs and initial values of coordinates can be set")]
    NotSettable {
        /// The name given.
        name: String,
        /// What it is.
        kind: &'static str,
    },
    /// A driven coordinate's motion is prescribed, so it takes no initial value.
    #[error("`{name}` is driven (its motion is prescribed): it takes no initial value")]
    Driven {
        /// The coordinate.
        name: String,
    },
    /// The value is not a finite number.
    #[error("the value of `{name}` is not a finite number")]
    NotFinite {
        /// The name given.
        name: String,
    },
    /// The value is non-zero but below the smallest normal double (2.2e-308).
    #[error("the value of `{name}` is too small for numeric work (non-zero values must be at least 2.2e-308 in size)")]
    TooSmall {
        /// The name given.
        name: String,
    },
    /// With the new values, a value of the model (a parameter defined from the one set, a
    /// mass…) is one numeric work cannot use.
    #[error("with these values, a value of the model {reason}")]
    UnusableValue {
        /// What is wrong with it.
        reason: &'static str,
        /// Where the expression is in the model's source (for a caller that has the source
        /// to show it with its line and column).
        span: crate::span::Span,
    },
}

fn hint(known: &[String]) -> String {
    if known.is_empty() {
        String::new()
    } else {
        format!(" (it has: {})", known.join(", "))
    }
}

impl Model {
    /// A copy of the model with `overrides` applied in order (a later one wins).
    ///
    /// # Errors
    /// An [`OverrideError`] for the first name that cannot be set.
    pub fn with_overrides(&self, overrides: &[(String, f64)]) -> Result<Model, OverrideError> {
        let mut model = self.clone();
        for (name, value) in overrides {
            model.set_value(name, *value)?;
        }
        if let Some(problem) = model.value_diagnostics().into_iter().next() {
            let reason = match problem.kind {
                DiagnosticKind::UnusableValue { reason } => reason,
                _ => "makes a mass zero, negative or too small to compute with",
            };
            return Err(OverrideError::UnusableValue {
                reason,
                span: problem.span,
            });
        }
        Ok(model)
    }

    fn set_value(&mut self, name: &str, value: f64) -> Result<(), OverrideError> {
        if !value.is_finite() {
            return Err(OverrideError::NotFinite {
                name: name.to_owned(),
            });
        }
        if value != 0.0 && !value.is_normal() {
            return Err(OverrideError::TooSmall {
                name: name.to_owned(),
            });
        }
        let (base, rate) = if let Some(base) = name.strip_suffix("_d") {
            (base, true)
        } else if let Some(base) = name.strip_suffix('\'') {
            (base, true)
        } else {
            (name, false)
        };
        // A name ending in `_d` may itself be declared (a parameter `k_d`): that wins.
        let found = match self.find(name) {
            Some(d) => Some((d, false)),
            None if rate => self.find(base).map(|d| (d, true)),
            None => None,
        };
        let number = |span| Expr {
            kind: ExprKind::Number {
                text: format!("{value:?}"),
                value,
            },
            span,
            ty: Type::Scalar,
        };
        match found {
            Some((Declaration::Parameter(id), false)) => {
                let p = &mut self.parameters[id.index()];
                p.value = Some(number(p.name.span));
            }
            Some((Declaration::Input(id), false)) => {
                let input = &mut self.inputs[id.index()];
                input.value = Some(number(input.name.span));
            }
            Some((Declaration::Coordinate(id), is_rate)) => {
                let coordinate = &self.coordinates[id.index()];
                if coordinate.driven.is_some() {
                    return Err(OverrideError::Driven {
                        name: coordinate.name.name.clone(),
                    });
                }
                let span = coordinate.name.span;
                let initial = InitialValue {
                    coordinate: id,
                    rate: is_rate,
                    value: number(span),
                };
                match self
                    .initial
                    .iter_mut()
                    .find(|i| i.coordinate == id && i.rate == is_rate)
                {
                    Some(existing) => *existing = initial,
                    None => self.initial.push(initial),
                }
            }
            Some((declaration, _)) => {
                let kind = match declaration {
                    Declaration::Constant(_) => "named constant",
                    Declaration::Frame(_) => "frame",
                    Declaration::Point(_) => "point",
                    Declaration::Body(_) => "body",
                    Declaration::Constraint(_) => "constraint",
                    _ => "parameter or input (write its rate as a coordinate's)",
                };
                return Err(OverrideError::NotSettable {
                    name: name.to_owned(),
                    kind,
                });
            }
            None => {
                let known = self
                    .parameters
                    .iter()
                    .map(|p| p.name.name.clone())
                    .chain(self.inputs.iter().map(|i| i.name.name.clone()))
                    .chain(
                        self.free_coordinates()
                            .flat_map(|(_, c)| [c.name.name.clone(), format!("{}_d", c.name.name)]),
                    )
                    .collect();
                return Err(OverrideError::UnknownName {
                    name: name.to_owned(),
                    known,
                });
            }
        }
        Ok(())
    }

    /// The initial value of a coordinate (`rate = false`) or of its rate, from the `initial`
    /// statement (after overrides); zero when not given, `None` when given but not a number.
    #[must_use]
    pub fn initial_value(&self, coordinate: &str, rate: bool) -> Option<f64> {
        let Some(Declaration::Coordinate(id)) = self.find(coordinate) else {
            return Some(0.0);
        };
        match self
            .initial
            .iter()
            .find(|i| i.coordinate == id && i.rate == rate)
        {
            Some(initial) => self.evaluate_constant(&initial.value),
            None => Some(0.0),
        }
    }

    /// The numeric values of every parameter and every input whose value is a constant, by
    /// name (after overrides); names without a numeric value are left out.
    #[must_use]
    pub fn numeric_values(&self) -> Vec<(String, f64)> {
        let parameters = self.parameters.iter().filter_map(|p| {
            let value = self.evaluate_constant(p.value.as_ref()?)?;
            Some((p.name.name.clone(), value))
        });
        let inputs = self.inputs.iter().filter_map(|i| {
            let value = self.evaluate_constant(i.value.as_ref()?)?;
            Some((i.name.name.clone(), value))
        });
        parameters.chain(inputs).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SOURCE: &str = "coordinates x, theta
parameters m = 2, l = 0.5, I = m*l^2/3
inputs F = 0
frame N
point P = x*N.x + l*sin(theta)*N.y
particle P mass m
initial x = 0.1
";

    fn value(model: &Model, name: &str) -> Option<f64> {
        model
            .numeric_values()
            .into_iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v)
    }

    #[test]
    fn parameters_inputs_and_initial_values_can_be_set() {
        let model = crate::load(SOURCE).unwrap();
        let set = |name: &str, v: f64| (name.to_owned(), v);
        let changed = model
            .with_overrides(&[
                set("m", 3.0),
                set("F", 1.5),
                set("theta", 0.3),
                set("x_d", -1.0),
            ])
            .unwrap();
        assert_eq!(value(&changed, "m"), Some(3.0));
        assert_eq!(value(&changed, "F"), Some(1.5));
        // I = m l²/3 follows m.
        assert!((value(&changed, "I").unwrap() - 0.25).abs() < 1e-15);
        assert_eq!(changed.initial_value("theta", false), Some(0.3));
        assert_eq!(changed.initial_value("x", true), Some(-1.0));
        assert_eq!(changed.initial_value("x", false), Some(0.1));
        assert_eq!(model.initial_value("theta", false), Some(0.0));
    }

    #[test]
    fn unknown_and_unsettable_names_are_errors() {
        let model = crate::load(SOURCE).unwrap();
        let err = model.with_overrides(&[("k".into(), 1.0)]).unwrap_err();
        assert!(matches!(err, OverrideError::UnknownName { ref name, .. } if name == "k"));
        assert!(err.to_string().contains("theta_d"), "{err}");
        let err = model.with_overrides(&[("N".into(), 1.0)]).unwrap_err();
        assert!(matches!(
            err,
            OverrideError::NotSettable { kind: "frame", .. }
        ));
        let err = model.with_overrides(&[("m".into(), f64::NAN)]).unwrap_err();
        assert!(matches!(err, OverrideError::NotFinite { .. }));
    }
}
