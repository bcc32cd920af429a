//! The symbolic core of lagrange: exact, fast algebra for the expressions mechanics produces.
//!
//! * [`Expr`] — a 4-byte handle to a hash-consed expression node: equal sub-expressions are
//!   stored once, and `a == b` is a pointer comparison.
//! * [`Expr::normal`] — the canonical normal form: a fraction of expanded polynomials in
//!   *atoms* (symbols, `sin`/`cos` of single angles, roots, other functions) with exact rational
//!   coefficients, trigonometry of sums and multiples expanded, `sin² = 1 − cos²` applied and
//!   fractions in lowest terms. For the class of expressions Lagrangian mechanics produces,
//!   equal expressions have identical normal forms, so [`Expr::is_zero`] is exact.
//! * [`NormalForm`] — a normal form kept as a polynomial fraction, for chains of operations
//!   whose intermediate trees nobody reads (building a large tree is most of an operation's
//!   cost); [`NormalForm::to_expr`] gives the same tree as [`Expr::normal`].
//! * Calculus: [`Expr::diff`] (partial derivative), [`Expr::dt`] (total time derivative with
//!   `q → q̇ → q̈`), [`Expr::taylor`] (series to any order at a point).
//! * [`Expr::subs`], [`Expr::eval`], [`Expr::coeff`], [`Expr::collect`],
//!   [`Expr::common_factor`], [`Expr::expand`]; small exact linear solves with [`Matrix`].
//! * Printing in three dialects ([`print`](mod@print)) and a parser that reads the text syntax back
//!   ([`parse`](mod@parse)).
//!
//! ```
//! use cas::Expr;
//! let th = Expr::coordinate("theta");
//! let l = Expr::symbol("l");
//! // d/dt (l sin θ) = l θ̇ cos θ
//! let v = (l * th.sin()).dt();
//! assert!(v.equals(l * Expr::rate("theta", 1) * th.cos()));
//! // sin²θ + cos²θ − 1 is exactly zero.
//! assert!((th.sin().powi(2) + th.cos().powi(2) - 1).is_zero());
//! ```
#![warn(missing_docs)]

mod calculus;
mod eval;
mod expr;
mod form;
mod limits;
mod matrix;
mod normal;
mod number;
mod ops;
pub mod parse;
mod poly;
pub mod print;
pub mod solve;
mod term_order;

pub use calculus::NotASymbol;
pub use eval::EvalError;
pub use expr::{arena_len, Constant, Expr, Func, Name, Node, Symbol, SymbolKind};
pub use form::NormalForm;
pub use limits::{
    limit_hit, limited, run_limited, set_work_limits, with_work_limits, work_limits,
    WorkLimitError, WorkLimits,
};
pub use matrix::{Matrix, SolveError};
pub use number::{LiteralError, Number, MAX_LITERAL_EXPONENT};
pub use parse::{parse, ParseContext, ParseError};
pub use solve::{solve_for, Condition, Solution, Solved};
