//! The formats results are written in, and each result rendered in them: the solution as
//! text, MyST Markdown, LaTeX or JSON; equations, reactions, equilibria and linearizations
//! as text or JSON; a lone expression as Unicode, LaTeX or SymPy. The command line and the
//! Python package pick a format and print what comes back; nothing here prints.
//!
//! With the `clap` feature the format enums are `clap::ValueEnum`s, so a command line takes
//! them as flag values (each variant's doc is its help).

use serde_json::Value;

use crate::equilibria::{Deviations, Equilibria, EquilibriumSweep};
use crate::{cas, report, Analysis, Error, Floquet, Reactions, Solution};

/// How a whole solution is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum ReportFormat {
    /// Unicode for the terminal, 80 columns.
    #[default]
    Text,
    /// MyST Markdown (math in `$$…$$`), for a Jupyter Book.
    Md,
    /// A standalone LaTeX document.
    Tex,
    /// Everything as JSON (docs/json.md).
    Json,
}

impl ReportFormat {
    /// The file extension of a report in this format.
    #[must_use]
    pub fn extension(self) -> &'static str {
        match self {
            ReportFormat::Text => "txt",
            ReportFormat::Md => "md",
            ReportFormat::Tex => "tex",
            ReportFormat::Json => "json",
        }
    }
}

/// How a result other than the solution is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum ResultFormat {
    /// Unicode, the way the course writes it.
    #[default]
    Text,
    /// JSON, `"schema": 1` (docs/json.md).
    Json,
}

/// How a lone expression is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Dialect {
    /// For terminals: θ̇, ẍ, ℓ, compact form.
    #[default]
    Unicode,
    /// LaTeX in the course's notation.
    Latex,
    /// SymPy syntax, exactly the normal form (reads back with `lagrange simplify`).
    Sympy,
}

impl Dialect {
    /// `expr` written in this dialect.
    #[must_use]
    pub fn write(self, expr: cas::Expr) -> String {
        match self {
            Dialect::Unicode => cas::print::to_unicode(expr),
            Dialect::Latex => cas::print::to_latex(expr),
            Dialect::Sympy => cas::print::to_sympy(expr),
        }
    }
}

/// Pretty JSON text, ending in a line break.
#[must_use]
pub fn json_text(value: &Value) -> String {
    let text = serde_json::to_string_pretty(value).unwrap_or_else(|e| format!("\"{e}\""));
    text + "\n"
}

/// Kane's equations in `format`, as `lagrange eom --method kane` writes them.
#[must_use]
pub fn kane_written(eom: &crate::KaneEom, format: ResultFormat) -> String {
    match format {
        ResultFormat::Text => crate::kane_text(eom),
        ResultFormat::Json => json_text(&crate::kane_json(eom)),
    }
}

/// A result that is written as text or as JSON.
pub trait Written {
    /// The result as text for people.
    fn text(&self) -> String;
    /// The result as JSON (docs/json.md).
    fn json(&self) -> Value;
    /// The result in `format`, ending in a line break.
    fn written(&self, format: ResultFormat) -> String {
        match format {
            ResultFormat::Text => {
                let text = self.text();
                format!("{}\n", text.trim_end_matches('\n'))
            }
            ResultFormat::Json => json_text(&self.json()),
        }
    }
}

impl Written for Reactions {
    fn text(&self) -> String {
        self.to_text()
    }
    fn json(&self) -> Value {
        self.to_json()
    }
}

impl Written for Equilibria {
    fn text(&self) -> String {
        self.to_text()
    }
    fn json(&self) -> Value {
        self.to_json()
    }
}

impl Written for EquilibriumSweep {
    fn text(&self) -> String {
        self.to_text()
    }
    fn json(&self) -> Value {
        self.to_json()
    }
}

impl Written for Floquet {
    fn text(&self) -> String {
        self.to_text()
    }
    fn json(&self) -> Value {
        self.to_json()
    }
}

/// The linearized dynamics about the equilibria (or only one), with a free response.
pub struct Linearized<'a> {
    /// The equilibria and their linearizations.
    pub equilibria: &'a Equilibria,
    /// Only this equilibrium (by index), or all.
    pub only: Option<usize>,
    /// Deviations from the equilibrium for the free response, when given.
    pub deviations: Deviations<'a>,
}

impl Written for Linearized<'_> {
    fn text(&self) -> String {
        self.equilibria.linearized_text(self.only, self.deviations)
    }
    fn json(&self) -> Value {
        self.equilibria.linearized_json(self.only, self.deviations)
    }
}

impl Analysis {
    /// The equations of motion in `format`, as `lagrange eom` prints them.
    ///
    /// # Errors
    /// As [`Analysis::equations`].
    pub fn equations_written(&self, format: ResultFormat) -> Result<String, Error> {
        let equations = self.equations()?;
        Ok(match format {
            ResultFormat::Text => report::eom_text(self.system(), equations),
            ResultFormat::Json => json_text(&report::eom_json(self.system(), equations)),
        })
    }

    /// The equations of motion by `method` in `format`: Lagrange's as
    /// [`Analysis::equations_written`], Kane's as [`Analysis::kane_equations`] gives them.
    ///
    /// # Errors
    /// As [`Analysis::equations`] or [`Analysis::kane_equations`].
    pub fn equations_written_by(
        &self,
        format: ResultFormat,
        method: crate::Method,
    ) -> Result<String, Error> {
        if method == crate::Method::Lagrange {
            return self.equations_written(format);
        }
        Ok(kane_written(&self.kane_equations()?, format))
    }

    /// `solution` in `format`, as `lagrange solve` writes it.
    ///
    /// # Errors
    /// JSON holds the equations of motion: as [`Analysis::equations`].
    pub fn solution_written(
        &self,
        solution: &Solution,
        format: ReportFormat,
    ) -> Result<String, Error> {
        let document = &solution.document;
        Ok(match format {
            ReportFormat::Text => document.to_text(),
            ReportFormat::Md => document.to_markdown(),
            ReportFormat::Tex => document.to_latex(),
            ReportFormat::Json => json_text(&self.solution_json(solution)?),
        })
    }
}
