//! Checks that only matter when numbers are needed (simulation, numeric equilibria), and the
//! evaluation of constant expressions: [`Model::require_values`], [`Model::evaluate_constant`].

use crate::ast::BinaryOp;
use crate::diagnostic::{Diagnostic, DiagnosticKind, NameKind};
use crate::model::Expr;
use crate::model::{ExprKind, Function, Model};

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
                        DiagnosticKind::MissingValue {
                            name: parameter.name.name.clone(),
                            kind: NameKind::Parameter,
                        },
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
                        DiagnosticKind::MissingValue {
                            name: input.name.name.clone(),
                            kind: NameKind::Input,
                        },
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
        // Parameters and constants refer only to earlier ones, so one pass in order gives all
        // their values, and each is computed once: following references recursively instead
        // could go as deep as the file is long, and take exponential time on `a2 = a1 + a1`.
        let mut known = Known {
            parameters: Vec::new(),
            constants: Vec::new(),
        };
        for parameter in &self.parameters {
            let value = parameter.value.as_ref().and_then(|v| evaluate(v, &known));
            known.parameters.push(value);
        }
        for constant in &self.constants {
            let value = evaluate(&constant.value, &known);
            known.constants.push(value);
        }
        evaluate(expr, &known)
    }
}

/// Values of the parameters and constants computed so far, by id.
struct Known {
    parameters: Vec<Option<f64>>,
    constants: Vec<Option<f64>>,
}

fn evaluate(expr: &Expr, known: &Known) -> Option<f64> {
    let value = match &expr.kind {
        ExprKind::Number { value, .. } => *value,
        ExprKind::Pi => std::f64::consts::PI,
        ExprKind::Parameter(id) => (*known.parameters.get(id.index())?)?,
        ExprKind::Constant(id) => (*known.constants.get(id.index())?)?,
        ExprKind::Neg(operand) => -evaluate(operand, known)?,
        ExprKind::Binary { op, lhs, rhs } => {
            let (a, b) = (evaluate(lhs, known)?, evaluate(rhs, known)?);
            match op {
                BinaryOp::Add => a + b,
                BinaryOp::Sub => a - b,
                BinaryOp::Mul => a * b,
                BinaryOp::Div => a / b,
                BinaryOp::Pow => a.powf(b),
            }
        }
        ExprKind::Call { function, args } => {
            let x = evaluate(args.first()?, known)?;
            match function {
                Function::Sin => x.sin(),
                Function::Cos => x.cos(),
                Function::Tan => x.tan(),
                Function::Asin => x.asin(),
                Function::Acos => x.acos(),
                Function::Atan => x.atan(),
                Function::Atan2 => x.atan2(evaluate(args.get(1)?, known)?),
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
