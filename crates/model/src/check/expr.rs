//! Checking one expression: resolve its names, infer its type (scalar or vector), and enforce
//! what the place it appears in allows ([`Place`]: rates or not, how much it may vary).

use std::collections::HashSet;

use crate::ast::{self, BinaryOp};
use crate::diagnostic::{suggest, Diagnostic, DiagnosticKind, NameKind, Type};
use crate::model::{Axis, Expr, ExprKind, Function, PointId};

use super::scope::{Level, Scope, Target};

/// What an expression's place allows.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Place {
    /// The place in words, for messages: "a parameter value".
    pub what: &'static str,
    /// The most the expression may vary.
    pub level: Level,
    /// Whether rates `q'` may appear.
    pub rates: bool,
}

impl Place {
    pub(crate) const fn constant(what: &'static str) -> Place {
        Place {
            what,
            level: Level::Constant,
            rates: false,
        }
    }

    pub(crate) const fn time(what: &'static str) -> Place {
        Place {
            what,
            level: Level::Time,
            rates: false,
        }
    }

    pub(crate) const fn configuration(what: &'static str) -> Place {
        Place {
            what,
            level: Level::Configuration,
            rates: false,
        }
    }

    pub(crate) const fn motion(what: &'static str) -> Place {
        Place {
            what,
            level: Level::Configuration,
            rates: true,
        }
    }
}

fn allowed(level: Level) -> &'static str {
    match level {
        Level::Constant => "numbers, parameters and constants",
        Level::Time => "numbers, parameters, constants, inputs and time `t`",
        Level::Configuration => "anything",
    }
}

pub(crate) struct ExprChecker<'a> {
    pub scope: &'a Scope,
    /// Names used so far (for the unused-name warnings).
    pub used: &'a mut HashSet<String>,
    pub diagnostics: &'a mut Vec<Diagnostic>,
    pub place: Place,
}

impl ExprChecker<'_> {
    /// Check `expr` and require type `expected`.
    pub(crate) fn expect(&mut self, expr: &ast::Expr, expected: Type) -> Option<Expr> {
        let checked = self.check(expr)?;
        if checked.ty != expected {
            let help = match expected {
                Type::Scalar => "Take a component with `dot(v, N.x)` or a length with `norm(v)`.",
                Type::Vector => "Multiply by a unit vector such as `N.x` to make a vector.",
            };
            self.diagnostics.push(
                Diagnostic::new(
                    DiagnosticKind::TypeMismatch {
                        expected,
                        found: checked.ty,
                    },
                    expr.span,
                )
                .with_label(format!("this is a {}", checked.ty))
                .with_help(format!(
                    "{} needs a {expected}. {help}",
                    capitalize(self.place.what)
                )),
            );
            return None;
        }
        Some(checked)
    }

    /// Check `expr`; `None` when it has errors (all of them reported).
    pub(crate) fn check(&mut self, expr: &ast::Expr) -> Option<Expr> {
        let span = expr.span;
        let typed = |kind, ty| Some(Expr { kind, span, ty });
        match &expr.kind {
            ast::ExprKind::Number(number) => typed(
                ExprKind::Number {
                    text: number.text.clone(),
                    value: number.value,
                },
                Type::Scalar,
            ),
            ast::ExprKind::Name(ident) => self.name(ident),
            ast::ExprKind::Rate(ident) => self.rate(ident, span),
            ast::ExprKind::UnitVector { frame, axis } => self.unit_vector(frame, axis, span),
            ast::ExprKind::Neg(operand) => {
                let operand = self.check(operand)?;
                let ty = operand.ty;
                typed(ExprKind::Neg(Box::new(operand)), ty)
            }
            ast::ExprKind::Binary { op, lhs, rhs } => {
                // Check both sides before giving up, so both sides' errors are reported.
                let lhs = self.check(lhs);
                let rhs = self.check(rhs);
                let (lhs, rhs) = (lhs?, rhs?);
                let ty = self.binary_type(*op, &lhs, &rhs, span)?;
                typed(
                    ExprKind::Binary {
                        op: *op,
                        lhs: Box::new(lhs),
                        rhs: Box::new(rhs),
                    },
                    ty,
                )
            }
            ast::ExprKind::Call { function, args } => self.call(function, args, span),
        }
    }

    /// A coordinate's rate `q'`: only coordinates have one, and only where rates are allowed.
    fn rate(&mut self, ident: &ast::Ident, span: crate::span::Span) -> Option<Expr> {
        let entry = match self.scope.get(&ident.name) {
            Some(entry) => *entry,
            None => {
                self.diagnostics.push(self.scope.not_found(ident, None));
                return None;
            }
        };
        self.used.insert(ident.name.clone());
        let id = match entry.target {
            Target::Coordinate(id) => id,
            Target::Poisoned => return None,
            _ => {
                self.diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::RateOfNonCoordinate {
                            name: ident.name.clone(),
                            kind: entry.kind,
                        },
                        span,
                    )
                    .with_help("Only coordinates have rates; remove the `'`."),
                );
                return None;
            }
        };
        if !self.place.rates {
            self.diagnostics.push(
                Diagnostic::new(
                    DiagnosticKind::RateNotAllowed { name: ident.name.clone(), place: self.place.what },
                    span,
                )
                .with_help(
                    "Positions, frames, potentials and holonomic constraints depend on coordinates, \
                     not on their rates; rates belong in forces, dissipation and velocity constraints.",
                ),
            );
            return None;
        }
        if !self.level_ok(entry.level, ident) {
            return None;
        }
        Some(Expr {
            kind: ExprKind::Rate(id),
            span,
            ty: Type::Scalar,
        })
    }

    /// A frame's unit vector `B.x`.
    fn unit_vector(
        &mut self,
        frame: &ast::Ident,
        axis: &ast::Ident,
        span: crate::span::Span,
    ) -> Option<Expr> {
        let entry = self
            .scope
            .expect_kind(frame, NameKind::Frame, self.diagnostics)?;
        let Target::Frame(id) = entry.target else {
            return None;
        };
        let Some(axis_value) = Axis::from_name(&axis.name) else {
            let mut diagnostic = Diagnostic::new(
                DiagnosticKind::UnknownAxis {
                    frame: frame.name.clone(),
                    axis: axis.name.clone(),
                },
                axis.span,
            );
            diagnostic = match suggest(&axis.name, ["x", "y", "z"]) {
                Some(best) => {
                    diagnostic.with_help(format!("Did you mean `{}.{best}`?", frame.name))
                }
                None => diagnostic.with_help(format!(
                    "A frame's unit vectors are `{0}.x`, `{0}.y` and `{0}.z`.",
                    frame.name
                )),
            };
            self.diagnostics.push(diagnostic);
            return None;
        };
        if !self.level_ok(entry.level, frame) {
            return None;
        }
        Some(Expr {
            kind: ExprKind::UnitVector {
                frame: id,
                axis: axis_value,
            },
            span,
            ty: Type::Vector,
        })
    }

    fn level_ok(&mut self, level: Level, ident: &ast::Ident) -> bool {
        if level <= self.place.level {
            return true;
        }
        self.diagnostics.push(
            Diagnostic::new(
                DiagnosticKind::NotConstant {
                    place: self.place.what,
                    allowed: allowed(self.place.level),
                    name: ident.name.clone(),
                },
                ident.span,
            )
            .with_help(match self.place.level {
                Level::Constant => "Use a parameter or a number here.",
                _ => "Use time, inputs and parameters here, not coordinates.",
            }),
        );
        false
    }

    fn name(&mut self, ident: &ast::Ident) -> Option<Expr> {
        let span = ident.span;
        let (kind, ty, level) = match ident.name.as_str() {
            "t" => (ExprKind::Time, Type::Scalar, Level::Time),
            "pi" => (ExprKind::Pi, Type::Scalar, Level::Constant),
            "origin" if self.scope.get("origin").is_none() => {
                (ExprKind::Point(PointId(0)), Type::Vector, Level::Constant)
            }
            name => {
                self.used.insert(name.to_string());
                let Some(entry) = self.scope.get(name).copied() else {
                    let diagnostic = if Function::from_name(name).is_some() {
                        Diagnostic::new(
                            DiagnosticKind::NotAValue {
                                name: name.to_string(),
                                kind: NameKind::Builtin,
                            },
                            span,
                        )
                        .with_help(format!(
                            "`{name}` is a function: call it, as in `{name}(theta)`."
                        ))
                    } else {
                        self.scope.not_found(ident, None)
                    };
                    self.diagnostics.push(diagnostic);
                    return None;
                };
                let kind = match entry.target {
                    Target::Coordinate(id) => ExprKind::Coordinate(id),
                    Target::Parameter(id) => ExprKind::Parameter(id),
                    Target::Input(id) => ExprKind::Input(id),
                    Target::Constant(id, _) => ExprKind::Constant(id),
                    Target::Point(id) => ExprKind::Point(id),
                    Target::Poisoned => return None,
                    Target::Frame(_) | Target::Body(_) | Target::Constraint(_) => {
                        let help = match entry.kind {
                            NameKind::Frame => format!("Use a unit vector of the frame: `{name}.x`, `{name}.y` or `{name}.z`."),
                            NameKind::Body => "Use the body's centre-of-mass point instead.".to_string(),
                            _ => "Constraints are not values; name them in `reactions`.".to_string(),
                        };
                        self.diagnostics.push(
                            Diagnostic::new(
                                DiagnosticKind::NotAValue {
                                    name: name.to_string(),
                                    kind: entry.kind,
                                },
                                span,
                            )
                            .with_help(help),
                        );
                        return None;
                    }
                };
                let ty = match entry.target {
                    Target::Point(_) => Type::Vector,
                    Target::Constant(_, ty) => ty,
                    _ => Type::Scalar,
                };
                (kind, ty, entry.level)
            }
        };
        if !self.level_ok(level, ident) {
            return None;
        }
        Some(Expr { kind, span, ty })
    }

    fn binary_type(
        &mut self,
        op: BinaryOp,
        lhs: &Expr,
        rhs: &Expr,
        span: crate::span::Span,
    ) -> Option<Type> {
        use Type::{Scalar, Vector};
        let (result, operation, help) = match (op, lhs.ty, rhs.ty) {
            (BinaryOp::Add | BinaryOp::Sub, a, b) if a == b => (Some(a), "", ""),
            (BinaryOp::Add, _, _) => (
                None,
                "add",
                "Both sides of `+` must be scalars, or both vectors.",
            ),
            (BinaryOp::Sub, _, _) => (
                None,
                "subtract",
                "Both sides of `-` must be scalars, or both vectors.",
            ),
            (BinaryOp::Mul, Vector, Vector) => (
                None,
                "multiply",
                "Use `dot(u, v)` for the scalar product or `cross(u, v)` for the vector product.",
            ),
            (BinaryOp::Mul, a, b) => (
                Some(if a == Vector || b == Vector {
                    Vector
                } else {
                    Scalar
                }),
                "",
                "",
            ),
            (BinaryOp::Div, a, Scalar) => (Some(a), "", ""),
            (BinaryOp::Div, _, Vector) => (None, "divide", "Only division by a scalar is defined."),
            (BinaryOp::Pow, Scalar, Scalar) => (Some(Scalar), "", ""),
            (BinaryOp::Pow, _, _) => (
                None,
                "raise to a power",
                "Powers are for scalars; for |v|² write `dot(v, v)`.",
            ),
        };
        if result.is_none() {
            self.diagnostics.push(
                Diagnostic::new(
                    DiagnosticKind::InvalidOperands {
                        operation,
                        lhs: lhs.ty,
                        rhs: rhs.ty,
                    },
                    span,
                )
                .with_related(lhs.span, format!("this is a {}", lhs.ty))
                .with_related(rhs.span, format!("this is a {}", rhs.ty))
                .with_help(help),
            );
        }
        result
    }

    fn call(
        &mut self,
        function: &ast::Ident,
        args: &[ast::Expr],
        span: crate::span::Span,
    ) -> Option<Expr> {
        let Some(resolved) = Function::from_name(&function.name) else {
            let mut diagnostic = Diagnostic::new(
                DiagnosticKind::UnknownFunction {
                    name: function.name.clone(),
                },
                function.span,
            );
            diagnostic = if let Some(entry) = self.scope.get(&function.name) {
                diagnostic.with_help(format!(
                    "`{0}` is {1}; to multiply, write `{0}*(…)`.",
                    function.name,
                    entry.kind.with_article()
                ))
            } else if let Some(best) = suggest(&function.name, Function::NAMES.iter().copied()) {
                diagnostic.with_help(format!("Did you mean `{best}`?"))
            } else {
                diagnostic.with_help(format!("The functions are {}.", Function::NAMES.join(", ")))
            };
            self.diagnostics.push(diagnostic);
            // Still check the arguments, for their own errors.
            for arg in args {
                self.check(arg);
            }
            return None;
        };
        let (parameter_types, result) = resolved.signature();
        if args.len() != parameter_types.len() {
            self.diagnostics.push(
                Diagnostic::new(
                    DiagnosticKind::WrongArity {
                        function: resolved.name(),
                        expected: parameter_types.len(),
                        found: args.len(),
                    },
                    span,
                )
                .with_help(match resolved {
                    Function::Atan2 => "Write `atan2(y, x)`.",
                    Function::Dot => "Write `dot(u, v)`.",
                    Function::Cross => "Write `cross(u, v)`.",
                    _ => "This function takes one argument.",
                }),
            );
            for arg in args {
                self.check(arg);
            }
            return None;
        }
        if resolved == Function::Vel && !self.place.rates {
            // A velocity holds rates: it belongs where rates do (velocity constraints, forces).
            self.diagnostics.push(
                Diagnostic::new(
                    DiagnosticKind::RateNotAllowed {
                        name: "vel".to_string(),
                        place: self.place.what,
                    },
                    span,
                )
                .with_help(
                    "`vel(P)` is a velocity; it belongs in forces, dissipation and velocity \
                     constraints, not in positions, potentials or holonomic constraints.",
                ),
            );
            return None;
        }
        let mut checked = Vec::with_capacity(args.len());
        let mut ok = true;
        for (arg, &ty) in args.iter().zip(parameter_types) {
            match self.expect(arg, ty) {
                Some(arg) => checked.push(arg),
                None => ok = false,
            }
        }
        ok.then_some(Expr {
            kind: ExprKind::Call {
                function: resolved,
                args: checked,
            },
            span,
            ty: result,
        })
    }
}

fn capitalize(text: &str) -> String {
    let mut chars = text.chars();
    chars.next().map_or_else(String::new, |first| {
        first.to_uppercase().chain(chars).collect()
    })
}

/// The polynomial degree of `expr` in the rates, or `None` when rates appear other than
/// polynomially (inside a function, in a denominator, under a non-integer power).
pub(crate) fn rate_degree(expr: &Expr) -> Option<u32> {
    match &expr.kind {
        ExprKind::Rate(_) => Some(1),
        ExprKind::Neg(operand) => rate_degree(operand),
        ExprKind::Binary { op, lhs, rhs } => {
            let (a, b) = (rate_degree(lhs)?, rate_degree(rhs)?);
            match op {
                BinaryOp::Add | BinaryOp::Sub => Some(a.max(b)),
                BinaryOp::Mul => Some(a.saturating_add(b)),
                BinaryOp::Div => (b == 0).then_some(a),
                BinaryOp::Pow => match (&rhs.kind, b) {
                    _ if a == 0 && b == 0 => Some(0),
                    (ExprKind::Number { value, .. }, 0)
                        if *value >= 0.0 && value.fract() == 0.0 && *value < 64.0 =>
                    {
                        Some(a.saturating_mul(*value as u32))
                    }
                    _ => None,
                },
            }
        }
        ExprKind::Call { function, args } => {
            let degrees: Option<Vec<u32>> = args.iter().map(rate_degree).collect();
            let degrees = degrees?;
            match function {
                Function::Dot | Function::Cross => Some(degrees.iter().sum()),
                // A velocity is linear in the rates when its argument holds none.
                Function::Vel if degrees.iter().all(|&d| d == 0) => Some(1),
                Function::Vel => None,
                _ if degrees.iter().all(|&d| d == 0) => Some(0),
                _ => None,
            }
        }
        _ => Some(0),
    }
}
