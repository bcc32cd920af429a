//! The one grammar of values given from outside the model — `NAME=VALUE` (a parameter, an
//! input, an initial value `q`, a rate `q_d` or `q'`), `NAME=A..B` (a range or a sweep) —
//! shared by every command and by programs. A value is a number or a constant expression
//! (`pi/2`, `2*g` with the model's values); an input's value may be a function of time
//! (`tau=2*sin(3*t)`).

use cas::{Expr, ParseContext};

/// Why a `NAME=VALUE` or `NAME=A..B` is refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum AssignmentError {
    /// Not of the form `NAME=VALUE` / `NAME=A..B`.
    #[error("`{text}` should look like {form}")]
    Form {
        /// As given.
        text: String,
        /// The expected form.
        form: &'static str,
    },
    /// The value does not parse.
    #[error("`{text}`: {reason}")]
    Syntax {
        /// As given.
        text: String,
        /// What is wrong, with the column in the value.
        reason: String,
    },
    /// No parameter, input or coordinate has this name.
    #[error("`{name}` is not a parameter, an input or a coordinate of the model{}", listing(.known))]
    UnknownName {
        /// The name given.
        name: String,
        /// The names that can be set.
        known: Vec<String>,
    },
    /// The value names something that has no numeric value.
    #[error("`{text}`: the value must be a number: {reason}")]
    NotANumber {
        /// As given.
        text: String,
        /// Why it has no number.
        reason: String,
    },
    /// The value is infinite or not a number.
    #[error("`{text}`: the value is not a finite number")]
    NotFinite {
        /// As given.
        text: String,
    },
    /// A function of time given for something that is not an input.
    #[error("`{name}` is not an input: only inputs may be functions of time")]
    TimeDependent {
        /// The name.
        name: String,
    },
    /// A range whose lower end is above its upper end.
    #[error("`{text}`: the lower end is above the upper end")]
    Reversed {
        /// As given.
        text: String,
    },
    /// The name exists but cannot take a value.
    #[error("`{name}` is a {what}: only parameters, inputs and initial values of coordinates can be set")]
    NotSettable {
        /// The name.
        name: String,
        /// What it is.
        what: &'static str,
    },
}

fn listing(known: &[String]) -> String {
    if known.is_empty() {
        String::new()
    } else {
        format!(" (it has: {})", known.join(", "))
    }
}

/// `NAME=VALUE`, the value still an expression (numbers, `pi`, the model's names, `t`).
#[derive(Debug, Clone, PartialEq)]
pub struct Assignment {
    /// The name as given (`theta`, `theta_d`, `theta'`, `k`).
    pub name: String,
    /// The value.
    pub value: Expr,
    /// The text as given, for messages.
    pub text: String,
}

impl Assignment {
    /// An assignment of a number.
    #[must_use]
    pub fn number(name: &str, value: f64) -> Assignment {
        Assignment {
            name: name.to_owned(),
            value: Expr::float(value),
            text: format!("{name}={value}"),
        }
    }
}

/// `NAME=A..B`, both ends numbers or constant expressions.
#[derive(Debug, Clone, PartialEq)]
pub struct Range {
    /// The name.
    pub name: String,
    /// The lower end.
    pub low: f64,
    /// The upper end.
    pub high: f64,
}

/// Reads `NAME=VALUE`.
///
/// # Errors
/// [`AssignmentError::Form`] or [`AssignmentError::Syntax`] with the column.
pub fn parse_assignment(text: &str) -> Result<Assignment, AssignmentError> {
    let (name, value) = split_name(text, "NAME=VALUE")?;
    Ok(Assignment {
        name: name.to_owned(),
        value: parse_value(text, value)?,
        text: text.to_owned(),
    })
}

/// Reads `NAME=A..B`; the ends may use `pi` and the names `values` knows.
///
/// # Errors
/// An [`AssignmentError`] saying what is wrong.
pub fn parse_range(
    text: &str,
    values: &dyn Fn(cas::Symbol) -> Option<f64>,
) -> Result<Range, AssignmentError> {
    let form = "NAME=A..B";
    let (name, range) = split_name(text, form)?;
    let (a, b) = range.split_once("..").ok_or(AssignmentError::Form {
        text: text.to_owned(),
        form,
    })?;
    let low = number(text, parse_value(text, a)?, values)?;
    let high = number(text, parse_value(text, b)?, values)?;
    if low > high {
        return Err(AssignmentError::Reversed {
            text: text.to_owned(),
        });
    }
    Ok(Range {
        name: name.to_owned(),
        low,
        high,
    })
}

/// The number an expression stands for, with `values` for the names in it.
///
/// # Errors
/// [`AssignmentError::NotANumber`] or [`AssignmentError::NotFinite`].
pub fn number(
    text: &str,
    value: Expr,
    values: &dyn Fn(cas::Symbol) -> Option<f64>,
) -> Result<f64, AssignmentError> {
    let x = value
        .eval(values)
        .map_err(|e| AssignmentError::NotANumber {
            text: text.to_owned(),
            reason: e.to_string(),
        })?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(AssignmentError::NotFinite {
            text: text.to_owned(),
        })
    }
}

/// Initial deviations `NAME=VALUE` (a rate as `NAME'` or `NAME_d`) → `(δq₀, δq̇₀)` in the
/// order of `coordinates`, the others 0.
///
/// # Errors
/// A malformed item, a value that is not a number, or a name that is not a coordinate.
pub fn deviations(
    items: &[String],
    coordinates: &[String],
    values: &dyn Fn(cas::Symbol) -> Option<f64>,
) -> Result<(Vec<f64>, Vec<f64>), AssignmentError> {
    let n = coordinates.len();
    let (mut dq, mut dv) = (vec![0.0; n], vec![0.0; n]);
    for item in items {
        let a = parse_assignment(item)?;
        let value = number(item, a.value, values)?;
        let (base, rate) = match a.name.strip_suffix('\'').or(a.name.strip_suffix("_d")) {
            Some(base) => (base, true),
            None => (a.name.as_str(), false),
        };
        let i = coordinates.iter().position(|q| q == base).ok_or_else(|| {
            AssignmentError::UnknownName {
                name: base.to_owned(),
                known: coordinates.to_vec(),
            }
        })?;
        if rate {
            dv[i] = value;
        } else {
            dq[i] = value;
        }
    }
    Ok((dq, dv))
}

impl crate::Analysis {
    /// Reads `NAME=A..B` (a search range, a sweep), the ends with the model's values.
    ///
    /// # Errors
    /// As [`parse_range`].
    pub fn read_range(&self, text: &str) -> Result<Range, AssignmentError> {
        parse_range(text, &self.lookup())
    }

    /// Reads `NAME=VALUE` as a number (a steady motion's rate), with the model's values.
    ///
    /// # Errors
    /// As [`parse_assignment`] and [`number`].
    pub fn read_number(&self, text: &str) -> Result<(String, f64), AssignmentError> {
        let assignment = parse_assignment(text)?;
        let value = number(text, assignment.value, &self.lookup())?;
        Ok((assignment.name, value))
    }

    /// Reads initial deviations about an equilibrium ([`deviations`]) with the model's values.
    ///
    /// # Errors
    /// As [`deviations`].
    pub fn read_deviations(
        &self,
        items: &[String],
        coordinates: &[String],
    ) -> Result<(Vec<f64>, Vec<f64>), AssignmentError> {
        deviations(items, coordinates, &self.lookup())
    }
}

/// Whether a value is a function of time.
#[must_use]
pub fn depends_on_time(value: Expr) -> bool {
    Expr::time()
        .as_symbol()
        .is_some_and(|t| cas::solve::depends_on(value, t))
}

fn split_name<'a>(
    text: &'a str,
    form: &'static str,
) -> Result<(&'a str, &'a str), AssignmentError> {
    let bad = || AssignmentError::Form {
        text: text.to_owned(),
        form,
    };
    let (name, value) = text.split_once('=').ok_or_else(bad)?;
    let name = name.trim();
    let plain = name
        .trim_end_matches('\'')
        .chars()
        .all(|c| c.is_alphanumeric() || c == '_');
    if name.is_empty() || !plain || value.trim().is_empty() {
        return Err(bad());
    }
    Ok((name, value.trim()))
}

fn parse_value(text: &str, value: &str) -> Result<Expr, AssignmentError> {
    cas::parse(value, &ParseContext::new()).map_err(|e| AssignmentError::Syntax {
        text: text.to_owned(),
        reason: e.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn none(_: cas::Symbol) -> Option<f64> {
        None
    }

    #[test]
    fn numbers_constant_expressions_and_functions_of_time() {
        let a = parse_assignment("g=pi").unwrap();
        assert_eq!(a.name, "g");
        assert_eq!(
            number("g=pi", a.value, &none).unwrap(),
            std::f64::consts::PI
        );
        let a = parse_assignment(" theta' = pi/2 ").unwrap();
        assert_eq!(a.name, "theta'");
        assert!((number("", a.value, &none).unwrap() - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let a = parse_assignment("tau=2*sin(3*t)").unwrap();
        assert!(depends_on_time(a.value));
        let g = |s: cas::Symbol| (s.name() == "g").then_some(9.81);
        let a = parse_assignment("k=2*g").unwrap();
        assert!(!depends_on_time(a.value));
        assert_eq!(number("k=2*g", a.value, &g).unwrap(), 2.0 * 9.81);
    }

    #[test]
    fn malformed_assignments_say_what_is_wrong() {
        assert!(matches!(
            parse_assignment("g"),
            Err(AssignmentError::Form { .. })
        ));
        assert!(matches!(
            parse_assignment("=3"),
            Err(AssignmentError::Form { .. })
        ));
        assert!(matches!(
            parse_assignment("g="),
            Err(AssignmentError::Form { .. })
        ));
        let e = parse_assignment("g=3+*2").unwrap_err();
        assert!(matches!(e, AssignmentError::Syntax { .. }), "{e}");
        assert!(e.to_string().contains("column"), "{e}");
        let a = parse_assignment("g=h").unwrap();
        assert!(matches!(
            number("g=h", a.value, &none),
            Err(AssignmentError::NotANumber { .. })
        ));
    }

    #[test]
    fn ranges_take_expressions_and_refuse_reversed_ends() {
        let r = parse_range("theta=-pi/2..pi/2", &none).unwrap();
        assert_eq!(r.name, "theta");
        assert!((r.low + std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!((r.high - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let r = parse_range("k=0.5..1.5", &none).unwrap();
        assert_eq!((r.low, r.high), (0.5, 1.5));
        assert!(matches!(
            parse_range("k=2..1", &none),
            Err(AssignmentError::Reversed { .. })
        ));
        assert!(matches!(
            parse_range("k=2", &none),
            Err(AssignmentError::Form { .. })
        ));
    }
}
