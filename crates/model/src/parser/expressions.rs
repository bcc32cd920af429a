//! Expression parsing: the Pratt loop for binary operators, prefix forms (literals, names,
//! unit vectors, rates, parentheses, unary signs), calls, and the nesting-depth cap.

use super::{ParseResult, Parser, MAX_DEPTH};
use crate::ast::*;
use crate::diagnostic::{Diagnostic, DiagnosticKind};
use crate::lexer::{Spanned, Token};
use crate::span::Span;

/// Binding power of unary minus: tighter than `*`, looser than `^` (`-x^2` is `-(x^2)`).
const PREFIX_POWER: u8 = 5;

impl Parser<'_> {
    pub(super) fn expr(&mut self) -> ParseResult<Expr> {
        self.expr_bp(0).map(|(expr, _)| expr)
    }

    /// Pratt loop. Returns the expression and the depth of its tree.
    fn expr_bp(&mut self, min_power: u8) -> ParseResult<(Expr, usize)> {
        self.depth += 1;
        let result = self.expr_bp_inner(min_power);
        self.depth -= 1;
        result
    }

    fn too_deep(&self, span: Span) -> Diagnostic {
        Diagnostic::new(DiagnosticKind::TooDeep { limit: MAX_DEPTH }, span)
            .with_help("Split the expression with named `constants`.")
    }

    fn expr_bp_inner(&mut self, min_power: u8) -> ParseResult<(Expr, usize)> {
        if self.depth > MAX_DEPTH {
            return Err(self.too_deep(self.peek().span));
        }
        let (mut lhs, mut depth) = self.prefix()?;
        loop {
            let op = match self.peek().token {
                Token::Plus => BinaryOp::Add,
                Token::Minus => BinaryOp::Sub,
                Token::Star => BinaryOp::Mul,
                Token::Slash => BinaryOp::Div,
                Token::Caret => BinaryOp::Pow,
                _ => break,
            };
            // `^` is right-associative; the others associate to the left.
            let (left_power, right_power) = match op {
                BinaryOp::Add | BinaryOp::Sub => (1, 2),
                BinaryOp::Mul | BinaryOp::Div => (3, 4),
                BinaryOp::Pow => (7, 6),
            };
            if left_power < min_power {
                break;
            }
            self.bump();
            let (rhs, rhs_depth) = self.expr_bp(right_power)?;
            depth = depth.max(rhs_depth) + 1;
            let span = lhs.span.to(rhs.span);
            if depth > MAX_DEPTH {
                return Err(self.too_deep(span));
            }
            lhs = Expr {
                kind: ExprKind::Binary {
                    op,
                    lhs: Box::new(lhs),
                    rhs: Box::new(rhs),
                },
                span,
            };
        }
        Ok((lhs, depth))
    }

    fn prefix(&mut self) -> ParseResult<(Expr, usize)> {
        let token = self.peek();
        match token.token {
            Token::Number => self.number(token),
            Token::Name => self.name(token),
            Token::LParen => {
                self.bump();
                let (inner, depth) = self.expr_bp(0)?;
                let close = self.close_paren(token.span)?;
                Ok((
                    Expr {
                        kind: inner.kind,
                        span: token.span.to(close),
                    },
                    depth,
                ))
            }
            Token::Minus | Token::Plus => self.sign(token),
            _ => Err(self.unexpected("an expression")),
        }
    }

    fn number(&mut self, token: Spanned) -> ParseResult<(Expr, usize)> {
        self.bump();
        let text = self.text(token.span);
        let value = number_value(text).map_err(|kind| {
            let help = match kind {
                DiagnosticKind::NumberUnderflow { .. } => {
                    "Numeric work uses double precision: a non-zero number must be at least 2.2e-308 in size. Write 0, or use other units."
                }
                _ => "Numbers must be finite double-precision values (|x| < 1.8e308): use other units.",
            };
            Diagnostic::new(kind, token.span).with_help(help)
        })?;
        let number = Number {
            text: text.to_string(),
            value,
        };
        Ok((
            Expr {
                kind: ExprKind::Number(number),
                span: token.span,
            },
            1,
        ))
    }

    /// A name, and what follows it: a call, a unit vector `N.x`, or a rate `q'`.
    fn name(&mut self, token: Spanned) -> ParseResult<(Expr, usize)> {
        self.bump();
        let ident = Ident {
            name: self.text(token.span).to_string(),
            span: token.span,
        };
        match self.peek().token {
            Token::LParen => self.call(ident),
            Token::Dot => {
                self.bump();
                let axis = self.ident("an axis: `x`, `y` or `z`")?;
                let span = ident.span.to(axis.span);
                Ok((
                    Expr {
                        kind: ExprKind::UnitVector { frame: ident, axis },
                        span,
                    },
                    1,
                ))
            }
            Token::Prime => {
                let prime = self.bump();
                let span = ident.span.to(prime.span);
                Ok((
                    Expr {
                        kind: ExprKind::Rate(ident),
                        span,
                    },
                    1,
                ))
            }
            _ => Ok((
                Expr {
                    kind: ExprKind::Name(ident.clone()),
                    span: ident.span,
                },
                1,
            )),
        }
    }

    /// Unary `-` or `+` (the latter only widens the span).
    fn sign(&mut self, token: Spanned) -> ParseResult<(Expr, usize)> {
        self.bump();
        let (operand, depth) = self.expr_bp(PREFIX_POWER)?;
        let span = token.span.to(operand.span);
        if token.token == Token::Plus {
            return Ok((
                Expr {
                    kind: operand.kind,
                    span,
                },
                depth,
            ));
        }
        if depth + 1 > MAX_DEPTH {
            return Err(self.too_deep(span));
        }
        Ok((
            Expr {
                kind: ExprKind::Neg(Box::new(operand)),
                span,
            },
            depth + 1,
        ))
    }

    fn call(&mut self, function: Ident) -> ParseResult<(Expr, usize)> {
        let open = self.bump().span;
        let mut args = Vec::new();
        let mut depth = 1;
        if !self.at(Token::RParen) {
            loop {
                let (arg, arg_depth) = self.expr_bp(0)?;
                depth = depth.max(arg_depth + 1);
                args.push(arg);
                if self.eat(Token::Comma).is_none() {
                    break;
                }
            }
        }
        let close = self.close_paren(open)?;
        if depth > MAX_DEPTH {
            return Err(self.too_deep(function.span.to(close)));
        }
        let span = function.span.to(close);
        Ok((
            Expr {
                kind: ExprKind::Call { function, args },
                span,
            },
            depth,
        ))
    }

    fn close_paren(&mut self, open: Span) -> ParseResult<Span> {
        if let Some(close) = self.eat(Token::RParen) {
            return Ok(close.span);
        }
        if matches!(self.peek().token, Token::Newline | Token::Eof) {
            Err(Diagnostic::new(DiagnosticKind::UnclosedParenthesis, open)
                .with_label("this parenthesis is never closed")
                .with_help("Add the missing `)`."))
        } else {
            Err(self
                .unexpected("`)`")
                .with_related(open, "to close this parenthesis"))
        }
    }
}

/// The double-precision value of a number literal, whose exact value (`cas::Number`) is what
/// the symbolic work uses: refused when numeric work could not use it — too large for a
/// double, or non-zero but below the smallest normal double (`1e-320` is subnormal, `1e-400`
/// would read as 0), which turns into NaNs and stalls far from the literal.
fn number_value(text: &str) -> Result<f64, DiagnosticKind> {
    let out_of_range = || DiagnosticKind::NumberOutOfRange {
        text: text.to_string(),
    };
    let exact = cas::Number::parse_literal(text).map_err(|_| out_of_range())?;
    let value: f64 = text.parse().map_err(|_| out_of_range())?;
    if !value.is_finite() {
        return Err(out_of_range());
    }
    if !exact.is_zero() && !value.is_normal() {
        return Err(DiagnosticKind::NumberUnderflow {
            text: text.to_string(),
        });
    }
    Ok(value)
}
