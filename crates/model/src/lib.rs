//! The lagrange model language: text → checked [`Model`].
//!
//! A model file describes a mechanical system the way a mechanics course does: coordinates,
//! parameters, frames made by rotations, points as vector expressions, particles and rigid
//! bodies, forces, springs, constraints, initial conditions (see `docs/language.md`). This crate
//! lexes ([`lexer`]), parses into an [`ast::Ast`] whose every node has a [`Span`], and checks
//! it into a [`Model`] in which every name is resolved and every expression is typed scalar or
//! vector. Every mistake becomes a [`Diagnostic`] (what, where, how to mend it), rendered with
//! [`render`]; several are reported in one run, and no input makes this crate panic.
//!
//! The pipeline, as `lagrange check` runs it:
//!
#![doc = concat!("```rust\n", include_str!("../tests/readme.rs"), "\n```")]
//!
//! The parts: [`parse`] (text → [`ast::Ast`] and syntax diagnostics), [`check`] (AST →
//! [`Model`] or diagnostics), [`load`] (both), [`Model::require_values`] (what numeric work
//! still needs), [`Model::summary`] (what `lagrange check` prints), [`render`] and
//! [`render_short`] (diagnostics → text), and [`Model::evaluate`] (a plain-`f64` reading of the
//! model's expressions at a state: the reference to check the symbolic lowering against).
#![warn(missing_docs)]

pub mod ast;
mod check;
mod diagnostic;
mod display;
mod evaluate;
pub mod lexer;
mod lower;
mod model;
mod overrides;
mod parser;
mod reactions;
mod render;
mod span;
mod summary;
mod values;

pub use check::check;
pub use diagnostic::{Diagnostic, DiagnosticKind, Diagnostics, Label, NameKind, Severity, Type};
pub use display::DisplayExpr;
pub use evaluate::{Evaluation, EvaluationError, State, Value};
pub use lower::{lower, LowerError};
pub use model::{
    decimal, Axis, Body, BodyId, Connection, Constant, ConstantId, Constraint, ConstraintId,
    ConstraintKind, Coordinate, CoordinateId, Decimal, Declaration, Expr, ExprKind, Frame, FrameId,
    Function, Inertia, InitialValue, Input, InputId, Load, LoadItem, Model, Name, Output,
    Parameter, ParameterId, Particle, Point, PointId, Projection, Prose, Quantity, ReactionTarget,
    Release, ReleaseMember, Rotation, Simulation,
};
pub use overrides::OverrideError;
pub use parser::{parse, MAX_DEPTH};
pub use reactions::{reaction_projections, reaction_requests, ReactionProjection};
pub use render::{render, render_short, RenderOptions};
pub use span::{line_col, LineCol, LineIndex, Span};
pub use summary::Summary;

/// Parse and check `source` in one go. Syntax errors do not stop the checking of the lines
/// that parsed, so all the problems of a file come back together.
///
/// # Errors
/// Every diagnostic, sorted by position, when there is at least one error.
pub fn load(source: &str) -> Result<Model, Diagnostics> {
    let (ast, mut diagnostics) = parse(source);
    let syntax_ok = diagnostics.is_empty();
    match check(&ast) {
        Ok(model) if syntax_ok => Ok(model),
        Ok(_) => Err(Diagnostics(diagnostics)),
        Err(more) => {
            // Names that a broken declaration seems to declare are unknown to the checker; its
            // reports about them would only repeat the syntax error, so they are dropped.
            let skipped = &ast.names_in_broken_declarations;
            diagnostics.extend(more.into_iter().filter(|d| match &d.kind {
                DiagnosticKind::UnknownName { name } | DiagnosticKind::UndefinedPoint { name } => {
                    !skipped.contains(name)
                }
                DiagnosticKind::NoCoordinates => skipped.is_empty(),
                _ => true,
            }));
            diagnostics.sort_by_key(|d| (d.span.start, d.span.end));
            Err(Diagnostics(diagnostics))
        }
    }
}
