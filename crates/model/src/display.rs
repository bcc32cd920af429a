//! Printing resolved expressions back in the language's syntax, with declared names: for
//! summaries and messages. [`Model::display`] gives a value that implements `Display`.

use std::fmt;

use crate::ast::BinaryOp;
use crate::model::{Expr, ExprKind, Model};

/// An expression of a model, ready to print; made by [`Model::display`].
#[derive(Clone, Copy, Debug)]
pub struct DisplayExpr<'a> {
    model: &'a Model,
    expr: &'a Expr,
}

impl Model {
    /// Print `expr` (an expression of this model) in the model language.
    #[must_use]
    pub fn display<'a>(&'a self, expr: &'a Expr) -> DisplayExpr<'a> {
        DisplayExpr { model: self, expr }
    }
}

fn precedence(expr: &Expr) -> u8 {
    match &expr.kind {
        ExprKind::Binary {
            op: BinaryOp::Add | BinaryOp::Sub,
            ..
        } => 1,
        ExprKind::Binary {
            op: BinaryOp::Mul | BinaryOp::Div,
            ..
        } => 2,
        ExprKind::Neg(_) => 3,
        ExprKind::Binary {
            op: BinaryOp::Pow, ..
        } => 4,
        _ => 5,
    }
}

impl fmt::Display for DisplayExpr<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let model = self.model;
        let sub = |expr: &'_ Expr, parenthesize: bool, f: &mut fmt::Formatter<'_>| {
            let inner = DisplayExpr { model, expr };
            if parenthesize {
                write!(f, "({inner})")
            } else {
                write!(f, "{inner}")
            }
        };
        // Ids come from the checker for this very model; `get` keeps printing total anyway.
        let name =
            |list: Option<&crate::model::Name>| list.map_or("?", |n| n.name.as_str()).to_string();
        match &self.expr.kind {
            ExprKind::Number { text, .. } => f.write_str(text),
            ExprKind::Time => f.write_str("t"),
            ExprKind::Pi => f.write_str("pi"),
            ExprKind::Coordinate(id) => {
                f.write_str(&name(model.coordinates.get(id.index()).map(|c| &c.name)))
            }
            ExprKind::Rate(id) => write!(
                f,
                "{}'",
                name(model.coordinates.get(id.index()).map(|c| &c.name))
            ),
            ExprKind::Parameter(id) => {
                f.write_str(&name(model.parameters.get(id.index()).map(|c| &c.name)))
            }
            ExprKind::Input(id) => {
                f.write_str(&name(model.inputs.get(id.index()).map(|c| &c.name)))
            }
            ExprKind::Constant(id) => {
                f.write_str(&name(model.constants.get(id.index()).map(|c| &c.name)))
            }
            ExprKind::Point(id) => {
                f.write_str(&name(model.points.get(id.index()).map(|c| &c.name)))
            }
            ExprKind::UnitVector { frame, axis } => {
                write!(
                    f,
                    "{}.{}",
                    name(model.frames.get(frame.index()).map(|c| &c.name)),
                    axis.name()
                )
            }
            ExprKind::Neg(operand) => {
                f.write_str("-")?;
                sub(operand, precedence(operand) < 3, f)
            }
            ExprKind::Binary { op, lhs, rhs } => {
                let own = precedence(self.expr);
                let (left, right) = if *op == BinaryOp::Pow {
                    (precedence(lhs) <= own, precedence(rhs) < own)
                } else {
                    (precedence(lhs) < own, precedence(rhs) <= own)
                };
                sub(lhs, left, f)?;
                match op {
                    BinaryOp::Add | BinaryOp::Sub => write!(f, " {} ", op.symbol())?,
                    _ => f.write_str(op.symbol())?,
                }
                sub(rhs, right, f)
            }
            ExprKind::Call { function, args } => {
                write!(f, "{}(", function.name())?;
                for (i, arg) in args.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    sub(arg, false, f)?;
                }
                f.write_str(")")
            }
        }
    }
}
