//! Checks that only matter when numbers are needed (simulation, numeric equilibria), and the
//! evaluation of constant expressions: [`Model::require_values`], [`Model::evaluate_constant`].

use crate::ast::BinaryOp;
use crate::diagnostic::{Diagnostic, DiagnosticKind, NameKind};
use crate::model::{ExprKind, Function, Model};
use crate::model::Expr;

impl Model {
    /// Diagnostics for what numeric work needs and the model lacks: parameters and inputs
    /// without a value, and a `simulate` without an end time. Empty when all is there.
    /// Symbolic work (deriving the equations) does not need any of these.
    #[must_use]
    pub fn require_values(&self) -> Vec<Diagnostic> {
        let mut diagnostics = Vec::new();
        for parameter in &self.parameters {
            if parameter.value.is_none() {
                diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::MissingValue { name: parameter.name.name.clone(), kind: NameKind::Parameter },
                        parameter.name.span,
                    )
                    .with_help(format!(
                        "Numeric work needs a value: write `parameters {} = …`.",
                        parameter.name.name
                    )),
                );
            }
        }
        for input in &self.inputs {
            if input.value.is_none() {
                diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::MissingValue { name: input.name.name.clone(), kind: NameKind::Input },
                        input.name.span,
                    )
                    .with_help(format!(
                        "Numeric work needs a value: write `inputs {} = …` (it may depend on `t`).",
                        input.name.name
                    )),
                );
            }
        }
        if let Some(simulation) = &self.simulation {
            if simulation.to.is_none() {
                diagnostics.push(
                    Diagnostic::new(DiagnosticKind::MissingEndTime, simulation.span)
                        .with_help("Add the end time: `simulate to 10`."),
                );
            }
        }
        diagnostics
    }

    /// The value of a scalar expression made of numbers, `pi`, parameters with values and
    /// scalar constants; `None` if it involves anything else or a value is missing.
    #[must_use]
    pub fn evaluate_constant(&self, expr: &Expr) -> Option<f64> {
        // Expressions are at most `MAX_DEPTH` deep and parameter values refer only to earlier
        // parameters, so this recursion is bounded.
        let value = match &expr.kind {
            ExprKind::Number { value, .. } => *value,
            ExprKind::Pi => std::f64::consts::PI,
            ExprKind::Parameter(id) => self.evaluate_constant(self.parameters.get(id.index())?.value.as_ref()?)?,
            ExprKind::Constant(id) => self.evaluate_constant(&self.constants.get(id.index())?.value)?,
            ExprKind::Neg(operand) => -self.evaluate_constant(operand)?,
            ExprKind::Binary { op, lhs, rhs } => {
                let (a, b) = (self.evaluate_constant(lhs)?, self.evaluate_constant(rhs)?);
                match op {
                    BinaryOp::Add => a + b,
                    BinaryOp::Sub => a - b,
                    BinaryOp::Mul => a * b,
                    BinaryOp::Div => a / b,
                    BinaryOp::Pow => a.powf(b),
                }
            }
            ExprKind::Call { function, args } => {
                let x = self.evaluate_constant(args.first()?)?;
                match function {
                    Function::Sin => x.sin(),
                    Function::Cos => x.cos(),
                    Function::Tan => x.tan(),
                    Function::Asin => x.asin(),
                    Function::Acos => x.acos(),
                    Function::Atan => x.atan(),
                    Function::Atan2 => x.atan2(self.evaluate_constant(args.get(1)?)?),
                    Function::Exp => x.exp(),
                    Function::Ln => x.ln(),
                    Function::Sqrt => x.sqrt(),
                    Function::Abs => x.abs(),
                    Function::Sign => {
                        if x == 0.0 {
                            0.0
                        } else {
                            x.signum()
                        }
                    }
                    _ => return None,
                }
            }
            _ => return None,
        };
        Some(value)
    }
}
