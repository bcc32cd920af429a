//! Command-line flags and help text.

use std::path::PathBuf;

use clap::{Parser, Subcommand, ValueEnum};

/// lagrange — analytical mechanics from a short model file: kinematics, the Lagrangian, the
/// equations of motion, and the tools of the symbolic core.
#[derive(Parser, Debug)]
#[command(name = "lagrange", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Solve a model: everything lagrange can derive for it, step by step.
    Solve {
        /// The model file (`.lag`).
        model: PathBuf,
    },
    /// Check a model file and print its summary (degrees of freedom, coordinates, bodies,
    /// forces, constraints), or its errors.
    Check {
        /// The model file (`.lag`).
        model: PathBuf,
    },
    /// Print Lagrange's equations of motion `M(q,t) q̈ = f(q,q̇,t)` of a model.
    Eom {
        /// The model file (`.lag`).
        model: PathBuf,
        /// Output: text for people, or JSON (schema in docs/json.md).
        #[arg(long, value_enum, default_value_t = EomFormat::Text)]
        format: EomFormat,
    },
    /// Print the normal form of an expression (SymPy syntax; rates as `q_d`, `q_dd`).
    Simplify {
        /// The expression, e.g. "sin(a+b) - sin(a)*cos(b)".
        expr: String,
        /// Output dialect.
        #[arg(long, value_enum, default_value_t = Format::Unicode)]
        format: Format,
        /// Names that are functions of time (coordinates), comma-separated; names with a
        /// `_d`/`_dd` suffix are recognised without this.
        #[arg(long, value_delimiter = ',')]
        coords: Vec<String>,
    },
    /// Print the derivative of an expression with respect to a variable; `t` means the total
    /// time derivative (coordinates `q` have rates `q_d`).
    Diff {
        /// The expression.
        expr: String,
        /// The variable: a symbol name, a rate like `theta_d`, or `t`.
        var: String,
        /// Output dialect.
        #[arg(long, value_enum, default_value_t = Format::Unicode)]
        format: Format,
        /// Names that are functions of time (coordinates), comma-separated.
        #[arg(long, value_delimiter = ',')]
        coords: Vec<String>,
    },
}

/// How expressions are printed.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// For terminals: θ̇, ẍ, ℓ, compact form.
    Unicode,
    /// LaTeX in the course's notation.
    Latex,
    /// SymPy syntax, exactly the normal form (reads back with `lagrange simplify`).
    Sympy,
}

/// How `lagrange eom` prints.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum EomFormat {
    /// Unicode equations, the way the course writes them.
    Text,
    /// JSON, `"schema": 1` (docs/json.md).
    Json,
}
