//! `lagrange simplify` and `lagrange diff`: the symbolic core on the command line.

use std::process::ExitCode;

use cas::{Expr, ParseContext};

use crate::args::Format;

fn print(e: Expr, format: Format) {
    let text = match format {
        Format::Unicode => cas::print::to_unicode(e),
        Format::Latex => cas::print::to_latex(e),
        Format::Sympy => cas::print::to_sympy(e),
    };
    println!("{text}");
}

/// Parses `text`, or prints the error under the offending column and returns `None`.
fn parse_or_report(text: &str, coords: &[String]) -> Option<Expr> {
    let ctx = ParseContext::new().with_coordinates(coords.iter().map(String::as_str));
    match cas::parse(text, &ctx) {
        Ok(e) => Some(e),
        Err(error) => {
            eprintln!("error: {error}");
            eprintln!("{}", error.render(text));
            None
        }
    }
}

/// `lagrange simplify EXPR`.
pub fn simplify(text: &str, format: Format, coords: &[String]) -> anyhow::Result<ExitCode> {
    let Some(e) = parse_or_report(text, coords) else {
        return Ok(ExitCode::from(2));
    };
    print(e.normal(), format);
    Ok(ExitCode::SUCCESS)
}

/// `lagrange diff EXPR VAR`.
pub fn diff(text: &str, var: &str, format: Format, coords: &[String]) -> anyhow::Result<ExitCode> {
    let Some(e) = parse_or_report(text, coords) else {
        return Ok(ExitCode::from(2));
    };
    if var == "t" {
        print(e.dt(), format);
        return Ok(ExitCode::SUCCESS);
    }
    // The variable is read with the same context so that `theta` means the coordinate when
    // the expression uses it as one.
    let mut names: Vec<String> = coords.to_vec();
    names.extend(ParseContext::for_expr(e).coordinate_names());
    let Some(v) = parse_or_report(var, &names) else {
        return Ok(ExitCode::from(2));
    };
    match e.try_diff(v) {
        Ok(d) => {
            print(d, format);
            Ok(ExitCode::SUCCESS)
        }
        Err(_) => {
            eprintln!("error: `{var}` is not a variable; write a symbol name such as `x`, a rate such as `theta_d`, or `t`");
            Ok(ExitCode::from(2))
        }
    }
}
