//! Checks that only matter when numbers are needed (simulation, numeric equilibria), and the
//! evaluation of constant expressions: [`Model::require_values`], [`Model::evaluate_constant`].

use crate::ast::BinaryOp;
use crate::diagnostic::{Diagnostic, DiagnosticKind, NameKind};
use crate::model::Expr;
use crate::model::{ExprKind, Function, Model};
use crate::span::Span;

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
        diagnostics.extend(self.value_diagnostics());
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

    /// Diagnostics for values numeric work cannot use, each at the offending expression: a
    /// parameter or constant value that divides by zero, overflows or underflows double
    /// precision or is not a real number, and a mass that is not positive or is too small to
    /// compute with (after `--set` overrides as much as in the file).
    #[must_use]
    pub fn value_diagnostics(&self) -> Vec<Diagnostic> {
        let mut diagnostics = Vec::new();
        let mut known = Known {
            parameters: Vec::new(),
            constants: Vec::new(),
        };
        let mut checked = |expr: Option<&Expr>, known: &Known| match expr {
            None => None,
            Some(expr) => match evaluate_checked(expr, known) {
                Ok(value) => value,
                Err(problem) => {
                    diagnostics.push(problem.diagnostic());
                    None
                }
            },
        };
        for parameter in &self.parameters {
            let value = checked(parameter.value.as_ref(), &known);
            known.parameters.push(value);
        }
        for constant in &self.constants {
            let value = checked(Some(&constant.value), &known);
            known.constants.push(value);
        }
        let masses = self
            .particles
            .iter()
            .map(|p| &p.mass)
            .chain(self.bodies.iter().map(|b| &b.mass));
        for mass in masses {
            match evaluate_checked(mass, &known) {
                Ok(Some(value)) if value <= 0.0 || !value.is_normal() => diagnostics.push(
                    Diagnostic::new(DiagnosticKind::NonPositiveMass { value }, mass.span)
                        .with_help("Give a positive mass of at least 2.2e-308 (use other units for smaller ones)."),
                ),
                Ok(_) => {}
                Err(problem) => diagnostics.push(problem.diagnostic()),
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

/// Why a constant expression has no usable double-precision value, and where.
struct ValueProblem {
    span: Span,
    reason: &'static str,
    help: &'static str,
}

impl ValueProblem {
    fn diagnostic(self) -> Diagnostic {
        Diagnostic::new(
            DiagnosticKind::UnusableValue {
                reason: self.reason,
            },
            self.span,
        )
        .with_help(self.help)
    }
}

/// [`evaluate`], with each operation checked: `Ok(None)` where a value is missing (not a
/// problem here), an error at the first operation whose result numeric work cannot use.
fn evaluate_checked(expr: &Expr, known: &Known) -> Result<Option<f64>, ValueProblem> {
    let problem = |reason, help| ValueProblem {
        span: expr.span,
        reason,
        help,
    };
    let mut operands = Vec::new();
    match &expr.kind {
        ExprKind::Neg(operand) => operands.push(operand.as_ref()),
        ExprKind::Binary { lhs, rhs, .. } => operands.extend([lhs.as_ref(), rhs.as_ref()]),
        ExprKind::Call { args, .. } => operands.extend(args.iter()),
        _ => {}
    }
    let mut values = Vec::with_capacity(operands.len());
    for operand in operands {
        match evaluate_checked(operand, known)? {
            Some(v) => values.push(v),
            None => return Ok(None),
        }
    }
    let Some(value) = evaluate(expr, known) else {
        return Ok(None);
    };
    if let ExprKind::Binary {
        op: BinaryOp::Div, ..
    } = &expr.kind
    {
        if values.get(1) == Some(&0.0) {
            return Err(problem(
                "divides by zero",
                "The divisor is zero with these values: change the value that makes it zero.",
            ));
        }
    }
    if value.is_nan() {
        return Err(problem(
            "is not a real number",
            "Check the argument of the function (a square root or a logarithm of a negative number, say).",
        ));
    }
    if value.is_infinite() {
        return Err(problem(
            "overflows double precision (|x| > 1.8e308)",
            "Use other units, so that the values stay within about 1e±300.",
        ));
    }
    let nonzero_operands = !values.is_empty() && values.iter().all(|v| *v != 0.0);
    let can_underflow = matches!(
        &expr.kind,
        ExprKind::Binary {
            op: BinaryOp::Mul | BinaryOp::Div | BinaryOp::Pow,
            ..
        } | ExprKind::Call {
            function: Function::Exp,
            ..
        }
    );
    if (value != 0.0 && !value.is_normal()) || (value == 0.0 && nonzero_operands && can_underflow) {
        return Err(problem(
            "underflows double precision (0 < |x| < 2.2e-308)",
            "Use other units, so that the values stay within about 1e±300, or write 0.",
        ));
    }
    Ok(Some(value))
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
