//! `lagrange simplify` and `lagrange diff`: the symbolic core on the command line.

use lagrange::{cas, expression};

use crate::args::{ExpressionOptions, Format};
use crate::exit::{println, Exit, Failure};

/// `lagrange simplify EXPR`.
pub fn simplify(text: &str, options: &ExpressionOptions) -> Result<Exit, Failure> {
    print(expression::simplify(text, &options.coords), options.format)
}

/// `lagrange diff EXPR VAR`.
pub fn diff(text: &str, var: &str, options: &ExpressionOptions) -> Result<Exit, Failure> {
    print(expression::diff(text, var, &options.coords), options.format)
}

fn print(e: Result<cas::Expr, lagrange::Error>, format: Format) -> Result<Exit, Failure> {
    let e = e.map_err(Failure::plain)?;
    println(&match format {
        Format::Unicode => cas::print::to_unicode(e),
        Format::Latex => cas::print::to_latex(e),
        Format::Sympy => cas::print::to_sympy(e),
    })?;
    Ok(Exit::Success)
}
