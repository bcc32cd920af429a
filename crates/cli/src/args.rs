//! Command-line flags and help text.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use lagrange::{Dialect, Method, ReportFormat, ResultFormat};

/// lagrange — analytical mechanics from a short model file: kinematics, the Lagrangian, the
/// equations of motion, and the tools of the symbolic core.
#[derive(Parser, Debug)]
#[command(name = "lagrange", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
    /// Multiply the limits of the symbolic work (terms, degree, total work; docs/cas.md) by
    /// FACTOR: `--work-limit 10` lets a derivation that stopped at a limit go ten times as far.
    #[arg(long, global = true, value_name = "FACTOR")]
    pub work_limit: Option<f64>,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Solve a model: everything lagrange can derive for it, step by step.
    Solve {
        #[command(flatten)]
        input: ModelInput,
        /// Output: the terminal, MyST Markdown, a standalone LaTeX document, or JSON.
        #[arg(long, value_enum, default_value_t = ReportFormat::Text)]
        format: ReportFormat,
        /// Write the report (and its figures) into this directory instead of printing it.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
    /// Check a model file and print its summary (degrees of freedom, coordinates, bodies,
    /// forces, constraints), or its errors.
    Check {
        /// The model file (`.lag`).
        model: PathBuf,
    },
    /// Print the equations of motion of a model: Lagrange's `M(q,t) q̈ = f(q,q̇,t)`, or
    /// Kane's reduced equations in the generalized speeds.
    Eom {
        #[command(flatten)]
        input: ModelInput,
        /// Output: text for people, or JSON (schema in docs/json.md).
        #[arg(long, value_enum, default_value_t = ResultFormat::Text)]
        format: ResultFormat,
        /// How to derive them.
        #[arg(long, value_enum, default_value_t = Method::Lagrange)]
        method: Method,
    },
    /// Print the constraint reactions a model asks for (`reactions …`, `reaction NAME: …`),
    /// by Lagrange's equations of the 1st kind and by Newton–Euler, and whether they agree.
    Reactions {
        #[command(flatten)]
        input: ModelInput,
        /// Output: text for people, or JSON (schema in docs/json.md).
        #[arg(long, value_enum, default_value_t = ResultFormat::Text)]
        format: ResultFormat,
        /// Derive the closed form even where it is large (by default, large reactions are
        /// evaluated numerically at the initial state: docs/reactions.md).
        #[arg(long)]
        symbolic: bool,
    },
    /// Find all equilibria (rest states with inputs held constant), exactly where possible,
    /// and decide their stability.
    Equilibria {
        #[command(flatten)]
        input: ModelInput,
        /// Search and parameter options.
        #[command(flatten)]
        options: EquilibriumOptions,
    },
    /// Linearize about every equilibrium: M0, C0, K0, B0, natural frequencies, modes,
    /// eigenvalues, state-space A, B and controllability.
    Linearize {
        #[command(flatten)]
        input: ModelInput,
        /// Search and parameter options.
        #[command(flatten)]
        options: EquilibriumOptions,
        /// Only this equilibrium (index as listed by `lagrange equilibria`).
        #[arg(long)]
        equilibrium: Option<usize>,
        /// Initial deviation for the free response in closed form: `--initial theta=0.01`,
        /// a rate as `--initial "theta'=0.1"` (repeatable; undamped systems).
        #[arg(long, value_name = "NAME=VALUE")]
        initial: Vec<String>,
        /// Floquet analysis of a time-periodic system (`sin`/`cos` of `ω t` in the equations):
        /// the variational equations over one period T about each equilibrium that holds at
        /// every t (or each periodic orbit, by shooting): monodromy matrix, multipliers,
        /// exponents, verdict. T defaults to the period of the driving; `--periodic 2*pi`
        /// gives it.
        #[arg(long, value_name = "T", num_args = 0..=1, default_missing_value = "")]
        periodic: Option<String>,
    },
    /// Simulate a model: integrate the equations of motion, write the time history as CSV
    /// (`t`, coordinates, rates `q_d`, energy error, constraint drift) and a summary line.
    Simulate(crate::commands::simulate::SimulateArgs),
    /// Draw the system at its initial state (or `--at` another) as an SVG figure: supports,
    /// rods, disks, masses, springs, dampers, forces, gravity, and each coordinate marked.
    Draw(crate::commands::draw::DrawArgs),
    /// Animate the simulated motion as a self-contained HTML page (play/pause, a time slider,
    /// the coordinates' values, traces of chosen points).
    Animate(crate::commands::animate::AnimateArgs),
    /// Print the normal form of an expression (SymPy syntax; rates as `q_d`, `q_dd`).
    Simplify {
        /// The expression, e.g. "sin(a+b) - sin(a)*cos(b)" (a leading minus needs no `--`).
        #[arg(allow_hyphen_values = true)]
        expr: String,
        #[command(flatten)]
        options: ExpressionOptions,
    },
    /// Print the derivative of an expression with respect to a variable; `t` means the total
    /// time derivative (coordinates `q` have rates `q_d`).
    Diff {
        /// The expression (a leading minus needs no `--`).
        #[arg(allow_hyphen_values = true)]
        expr: String,
        /// The variable: a symbol name, a rate like `theta_d`, or `t`.
        var: String,
        #[command(flatten)]
        options: ExpressionOptions,
    },
}

/// The options of `lagrange simplify` and `lagrange diff`.
#[derive(Args, Debug, Clone)]
pub struct ExpressionOptions {
    /// Output dialect.
    #[arg(long, value_enum, default_value_t = Dialect::Unicode)]
    pub format: Dialect,
    /// Names that are functions of time (coordinates), comma-separated; names with a
    /// `_d`/`_dd` suffix are recognised without this.
    #[arg(long, value_delimiter = ',')]
    pub coords: Vec<String>,
}

/// A model file and values for this run: what every command that reads a model takes.
#[derive(Args, Debug, Clone)]
pub struct ModelInput {
    /// The model file (`.lag`).
    pub model: PathBuf,
    /// Override a parameter, an input or an initial value for this run: `k=40`, `theta=0.3`,
    /// `theta_d=-1`; a number or a constant expression (`pi/4`, `2*g`), for an input a
    /// function of `t` (docs/cli.md). Repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
}

/// Options shared by `lagrange equilibria` and `lagrange linearize`.
#[derive(Args, Debug, Clone)]
pub struct EquilibriumOptions {
    /// Output: text for people, or JSON (schema in docs/json.md).
    #[arg(long, value_enum, default_value_t = ResultFormat::Text)]
    pub format: ResultFormat,
    /// The search range of a non-angle coordinate, e.g. `--range x=-2..2` (default −10..10;
    /// angles always span one turn).
    #[arg(long = "range", value_name = "NAME=A..B")]
    pub range: Vec<String>,
    /// Steady motion: a cyclic coordinate turning at a constant rate, e.g. `--steady phi=2`
    /// (repeatable); the relative equilibria of the other coordinates are found, and their
    /// stability by Routh's reduced potential. The rate is then the parameter `phi_d` (for
    /// `--sweep phi_d=1..5`).
    #[arg(long = "steady", value_name = "NAME=RATE")]
    pub steady: Vec<String>,
    /// Sweep a parameter: `--sweep Omega=0..10` prints equilibria and stability at each step.
    /// With `linearize --periodic`, one or two (repeat the flag) for the stability chart on
    /// their grid, printed as CSV.
    #[arg(long, value_name = "NAME=A..B")]
    pub sweep: Vec<String>,
    /// Number of steps of a sweep.
    #[arg(long, default_value_t = 20)]
    pub steps: usize,
    /// With `--sweep`: draw the bifurcation diagram (equilibria against the parameter,
    /// stable filled, unstable open) to this `.svg` or `.png` file; with `linearize
    /// --periodic`, the stability chart (the stable region of the motion `--equilibrium`,
    /// default the first).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<std::path::PathBuf>,
}
