//! `lagrange simplify` and `lagrange diff`: the symbolic core on the command line.

use lagrange::expression;

use crate::args::ExpressionOptions;
use crate::exit::{println, Exit, Failure};

/// `lagrange simplify EXPR`.
pub fn simplify(text: &str, options: &ExpressionOptions) -> Result<Exit, Failure> {
    let expr = expression::simplify(text, &options.coords).map_err(Failure::plain)?;
    println(&options.format.write(expr))?;
    Ok(Exit::Success)
}

/// `lagrange diff EXPR VAR`.
pub fn diff(text: &str, var: &str, options: &ExpressionOptions) -> Result<Exit, Failure> {
    let expr = expression::diff(text, var, &options.coords).map_err(Failure::plain)?;
    println(&options.format.write(expr))?;
    Ok(Exit::Success)
}
