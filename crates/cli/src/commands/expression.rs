//! `lagrange simplify` and `lagrange diff`: the symbolic core on the command line.

use cas::{Expr, ParseContext};
use lagrange::cas;

use crate::args::Format;
use crate::exit::{println, Exit, Failure};

fn print(e: Expr, format: Format) -> Result<Exit, Failure> {
    let text = match format {
        Format::Unicode => cas::print::to_unicode(e),
        Format::Latex => cas::print::to_latex(e),
        Format::Sympy => cas::print::to_sympy(e),
    };
    println(&text)?;
    Ok(Exit::Success)
}

/// Parses `text`; the error shows the offending column.
fn parse(text: &str, coords: &[String]) -> Result<Expr, Failure> {
    let ctx = ParseContext::new().with_coordinates(coords.iter().map(String::as_str));
    cas::parse(text, &ctx)
        .map_err(|error| Failure::input(format!("{error}\n{}", error.render(text).trim_end())))
}

/// `lagrange simplify EXPR`.
pub fn simplify(text: &str, format: Format, coords: &[String]) -> Result<Exit, Failure> {
    let normal = parse(text, coords)?
        .try_normal()
        .map_err(|e| Failure::work_limit(&e))?;
    print(normal, format)
}

/// `lagrange diff EXPR VAR`.
pub fn diff(text: &str, var: &str, format: Format, coords: &[String]) -> Result<Exit, Failure> {
    let e = parse(text, coords)?;
    if var == "t" {
        return print(e.dt(), format);
    }
    // The variable is read with the same context so that `theta` means the coordinate when
    // the expression uses it as one.
    let mut names: Vec<String> = coords.to_vec();
    names.extend(ParseContext::for_expr(e).coordinate_names());
    let v = parse(var, &names)?;
    match e.try_diff(v) {
        Ok(d) => print(d, format),
        Err(_) => Err(Failure::input(format!(
            "`{var}` is not a variable; write a symbol name such as `x`, a rate such as `theta_d`, or `t`"
        ))),
    }
}
