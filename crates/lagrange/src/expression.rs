//! One expression on its own, as `lagrange simplify` and `lagrange diff` take it: read with
//! the names that are coordinates (functions of time, rates `q_d`), put in normal form, or
//! differentiated by a variable or by time.

use cas::{Expr, ParseContext};

use crate::Error;

/// Reads `text`; the names in `coordinates`, and those with a `_d`/`_dd` suffix, are
/// coordinates.
///
/// # Errors
/// [`Error::Expression`], with the column.
pub fn parse(text: &str, coordinates: &[String]) -> Result<Expr, Error> {
    let context = ParseContext::new().with_coordinates(coordinates.iter().map(String::as_str));
    cas::parse(text, &context).map_err(|error| Error::Expression {
        text: text.to_owned(),
        error,
    })
}

/// The normal form of `text` (docs/cas.md).
///
/// # Errors
/// As [`parse`], or [`Error::WorkLimit`] past a work limit of the symbolic core.
pub fn simplify(text: &str, coordinates: &[String]) -> Result<Expr, Error> {
    parse(text, coordinates)?
        .try_normal()
        .map_err(|error| Error::WorkLimit {
            message: error.to_string(),
            error,
            at: None,
        })
}

/// The derivative of `text` by `variable`: a symbol, a rate (`theta_d`), or `t` for the
/// total time derivative. The variable is read with the expression's coordinates, so that
/// `theta` is the coordinate when the expression uses it as one.
///
/// # Errors
/// As [`parse`], or [`Error::NotAVariable`].
pub fn diff(text: &str, variable: &str, coordinates: &[String]) -> Result<Expr, Error> {
    let e = parse(text, coordinates)?;
    if variable == "t" {
        return Ok(e.dt());
    }
    let mut names: Vec<String> = coordinates.to_vec();
    names.extend(ParseContext::for_expr(e).coordinate_names());
    let v = parse(variable, &names)?;
    e.try_diff(v).map_err(|_| Error::NotAVariable {
        name: variable.to_owned(),
    })
}
