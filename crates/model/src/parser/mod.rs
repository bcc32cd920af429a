//! The parser: tokens → [`Ast`], hand-written recursive descent for statements and a Pratt
//! parser for expressions.
//!
//! Recovery is per statement: a statement with a syntax error is reported and skipped up to the
//! end of its line, and parsing goes on, so one run reports every broken line. Expression
//! nesting is capped at [`MAX_DEPTH`] (both the parser's recursion and the depth of the tree it
//! builds), so no input can overflow the stack here or in later passes over the tree.

// A parse error is made once per broken statement, on the error path only, and then moved
// into the diagnostics list: its size (a whole `Diagnostic`) costs nothing measurable, and
// boxing it would only add noise to every `?`.
#![allow(clippy::result_large_err)]

use crate::ast::*;
use crate::diagnostic::{Diagnostic, DiagnosticKind};
use crate::lexer::{lex, Spanned, Token};
use crate::span::Span;

mod expressions;
mod statements;

/// The deepest expression nesting accepted; deeper expressions are an error.
pub const MAX_DEPTH: usize = 64;

/// Parse a model file. Returns the statements that parsed and a diagnostic for each line that
/// did not (an empty list means the file is syntactically valid).
#[must_use]
pub fn parse(source: &str) -> (Ast, Vec<Diagnostic>) {
    let (tokens, diagnostics) = lex(source);
    let mut parser = Parser {
        source,
        tokens,
        position: 0,
        depth: 0,
        diagnostics,
        broken_names: Vec::new(),
    };
    let statements = parser.file();
    let ast = Ast {
        statements,
        names_in_broken_declarations: parser.broken_names,
    };
    (ast, parser.diagnostics)
}

type ParseResult<T> = Result<T, Diagnostic>;

struct Parser<'s> {
    source: &'s str,
    // Invariant: non-empty and ends with `Token::Eof`.
    tokens: Vec<Spanned>,
    position: usize,
    depth: usize,
    diagnostics: Vec<Diagnostic>,
    broken_names: Vec<String>,
}

impl<'s> Parser<'s> {
    // --- token access ---------------------------------------------------------------------

    fn peek(&self) -> Spanned {
        self.nth(0)
    }

    fn nth(&self, n: usize) -> Spanned {
        let end = Spanned {
            token: Token::Eof,
            span: Span::new(self.source.len(), self.source.len()),
        };
        self.tokens
            .get(self.position + n)
            .or(self.tokens.last())
            .copied()
            .unwrap_or(end)
    }

    fn bump(&mut self) -> Spanned {
        let token = self.peek();
        if token.token != Token::Eof {
            self.position += 1;
        }
        token
    }

    fn text(&self, span: Span) -> &'s str {
        self.source.get(span.range()).unwrap_or("")
    }

    fn at(&self, token: Token) -> bool {
        self.peek().token == token
    }

    fn at_keyword(&self, keyword: &str) -> bool {
        let next = self.peek();
        next.token == Token::Name && self.text(next.span) == keyword
    }

    fn eat(&mut self, token: Token) -> Option<Spanned> {
        if self.at(token) {
            Some(self.bump())
        } else {
            None
        }
    }

    fn eat_keyword(&mut self, keyword: &str) -> Option<Span> {
        if self.at_keyword(keyword) {
            Some(self.bump().span)
        } else {
            None
        }
    }

    /// How the current token is described in "found …".
    fn found(&self) -> String {
        let next = self.peek();
        match next.token {
            Token::Name | Token::Number => format!("`{}`", self.text(next.span)),
            other => other.describe().to_string(),
        }
    }

    fn unexpected(&self, expected: impl Into<String>) -> Diagnostic {
        let kind = DiagnosticKind::UnexpectedToken {
            expected: expected.into(),
            found: self.found(),
        };
        Diagnostic::new(kind, self.peek().span)
    }

    fn expect(&mut self, token: Token, expected: &str) -> ParseResult<Spanned> {
        self.eat(token).ok_or_else(|| self.unexpected(expected))
    }

    fn expect_keyword(&mut self, keyword: &str) -> ParseResult<Span> {
        self.eat_keyword(keyword)
            .ok_or_else(|| self.unexpected(format!("`{keyword}`")))
    }

    fn ident(&mut self, what: &str) -> ParseResult<Ident> {
        let token = self.expect(Token::Name, what)?;
        Ok(Ident {
            name: self.text(token.span).to_string(),
            span: token.span,
        })
    }

    fn span_from(&self, start: Span) -> Span {
        let end = self
            .tokens
            .get(self.position.wrapping_sub(1))
            .map_or(start, |t| t.span);
        start.to(end)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_ok(source: &str) -> Ast {
        let (ast, diagnostics) = parse(source);
        assert!(diagnostics.is_empty(), "{diagnostics:#?}");
        ast
    }

    /// Print an expression fully parenthesized, to test precedence and associativity.
    fn show(expr: &Expr) -> String {
        match &expr.kind {
            ExprKind::Number(n) => n.text.clone(),
            ExprKind::Name(i) => i.name.clone(),
            ExprKind::Rate(i) => format!("{}'", i.name),
            ExprKind::UnitVector { frame, axis } => format!("{}.{}", frame.name, axis.name),
            ExprKind::Neg(e) => format!("(-{})", show(e)),
            ExprKind::Binary { op, lhs, rhs } => {
                format!("({} {} {})", show(lhs), op.symbol(), show(rhs))
            }
            ExprKind::Call { function, args } => {
                format!(
                    "{}({})",
                    function.name,
                    args.iter().map(show).collect::<Vec<_>>().join(", ")
                )
            }
        }
    }

    fn expr(source: &str) -> String {
        let ast = parse_ok(&format!("gravity {source}"));
        match &ast.statements[0].kind {
            StatementKind::Gravity(e) => show(e),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn precedence_and_associativity() {
        assert_eq!(expr("a + b*c"), "(a + (b * c))");
        assert_eq!(expr("a - b - c"), "((a - b) - c)");
        assert_eq!(expr("a / b / c"), "((a / b) / c)");
        assert_eq!(expr("a ^ b ^ c"), "(a ^ (b ^ c))");
        assert_eq!(expr("a ** 2"), "(a ^ 2)");
        assert_eq!(expr("-x^2"), "(-(x ^ 2))");
        assert_eq!(expr("2^-x"), "(2 ^ (-x))");
        assert_eq!(expr("(a + b)*c"), "((a + b) * c)");
        assert_eq!(
            expr("A + l*sin(theta)*N.x"),
            "(A + ((l * sin(theta)) * N.x))"
        );
        assert_eq!(expr("atan2(y, x) + x'"), "(atan2(y, x) + x')");
        assert_eq!(expr("+1.5e3"), "1.5e3");
    }

    #[test]
    fn spans_cover_the_text() {
        let source = "gravity  (a + b) * c";
        let ast = parse_ok(source);
        let StatementKind::Gravity(e) = &ast.statements[0].kind else {
            panic!()
        };
        assert_eq!(&source[e.span.range()], "(a + b) * c");
        let ExprKind::Binary { lhs, .. } = &e.kind else {
            panic!()
        };
        assert_eq!(&source[lhs.span.range()], "(a + b)");
        assert_eq!(&source[ast.statements[0].span.range()], source);
    }

    #[test]
    fn design_sketch_parses() {
        let ast = parse_ok(
            "coordinates x, theta\nparameters m_A = 2, l\nframe N\nframe B = N rotated theta about z then phi about x\n\
             point B = A + l*sin(theta)*N.x\nparticle B mass m_B\nspring k from origin to A length l0\n\
             body disc mass m at C frame B inertia I1, I2, I3 about O\n\
             body rod mass m at C frame B inertia xx = a, yy = b, zz = c, xy = d\n\
             generalized force C on theta\nconstraint roll: rolling disc at A\n\
             constraint gear phi1 to phi2 ratio r\nconstraint c: x' + y' = 0\ninitial x = 0.1, x' = 0\n\
             simulate from 0 to 10 step 0.01\noutput x, yB = dot(B, N.y)\nreactions roll\n",
        );
        assert_eq!(ast.statements.len(), 17);
        let StatementKind::Frame {
            rotation: Some((_, rotations)),
            ..
        } = &ast.statements[3].kind
        else {
            panic!()
        };
        assert_eq!(rotations.len(), 2);
    }

    #[test]
    fn continuation_lines() {
        let ast = parse_ok(
            "body disc mass m \\\n  at C frame B \\\n  inertia a, b, c\npoint P = f(a,\n  b)\n",
        );
        assert_eq!(ast.statements.len(), 2);
    }

    #[test]
    fn several_errors_are_reported_and_good_lines_kept() {
        let (ast, diagnostics) =
            parse("coordinates x\npoint = 3\nframe N\ngravity (1 +\nforce 1 at\nfrobnicate x\n");
        assert_eq!(diagnostics.len(), 4, "{diagnostics:#?}");
        assert_eq!(ast.statements.len(), 2);
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_crash() {
        let deep = format!("gravity {}x{}", "(".repeat(10_000), ")".repeat(10_000));
        let (_, diagnostics) = parse(&deep);
        assert!(matches!(
            diagnostics[0].kind,
            DiagnosticKind::TooDeep { .. }
        ));
        let long = format!("gravity x{}", "+x".repeat(10_000));
        let (_, diagnostics) = parse(&long);
        assert!(matches!(
            diagnostics[0].kind,
            DiagnosticKind::TooDeep { .. }
        ));
        let minus = format!("gravity {}x", "-".repeat(10_000));
        let (_, diagnostics) = parse(&minus);
        assert!(matches!(
            diagnostics[0].kind,
            DiagnosticKind::TooDeep { .. }
        ));
    }

    fn only(source: &str) -> StatementKind {
        let mut ast = parse_ok(source);
        assert_eq!(ast.statements.len(), 1);
        ast.statements.remove(0).kind
    }

    #[test]
    fn body_clauses_in_any_order_and_full_tensors() {
        let StatementKind::Body { name, clauses } =
            only("body rod inertia xx = a, yy = b, zz = c, yx = d about O frame B at G mass m")
        else {
            panic!()
        };
        assert_eq!(name.name, "rod");
        assert!(clauses.mass.is_some() && clauses.centre.is_some() && clauses.frame.is_some());
        let inertia = clauses.inertia.expect("inertia");
        assert_eq!(inertia.about.map(|p| p.name), Some("O".to_string()));
        let InertiaSpec::Components(components) = inertia.spec else {
            panic!()
        };
        let keys: Vec<&str> = components.iter().map(|(k, _)| k.name.as_str()).collect();
        assert_eq!(keys, ["xx", "yy", "zz", "yx"]);
    }

    #[test]
    fn constraint_forms() {
        assert!(matches!(
            only("constraint roll: rolling disc at A"),
            StatementKind::Constraint {
                name: Some(_),
                spec: ConstraintSpec::Rolling { .. }
            }
        ));
        assert!(matches!(
            only("constraint gear a to b ratio 2"),
            StatementKind::Constraint {
                name: None,
                spec: ConstraintSpec::Gear { .. }
            }
        ));
        // `rolling` and `gear` are keywords only when a name follows them.
        assert!(matches!(
            only("constraint rolling + gear = 1"),
            StatementKind::Constraint {
                name: None,
                spec: ConstraintSpec::Equation { .. }
            }
        ));
    }

    #[test]
    fn initial_rates_settings_and_outputs() {
        let StatementKind::Initial(values) = only("initial x = 1, x' = -2") else {
            panic!()
        };
        assert_eq!(
            values.iter().map(|v| v.rate).collect::<Vec<_>>(),
            [false, true]
        );
        let StatementKind::Simulate(settings) =
            only("simulate from 0, to 10 rtol 1e-9 method rk45")
        else {
            panic!()
        };
        let keys: Vec<&str> = settings.iter().map(|s| s.key.name.as_str()).collect();
        assert_eq!(keys, ["from", "to", "rtol", "method"]);
        let StatementKind::Output(items) = only("output x, h = dot(P, N.y), energy") else {
            panic!()
        };
        assert_eq!(items.len(), 3);
        assert_eq!(items[1].name.as_ref().map(|n| n.name.as_str()), Some("h"));
    }

    #[test]
    fn title_problem_and_note_take_quoted_prose() {
        assert_eq!(
            only("title \"Exercise 7.1 — a cart\""),
            StatementKind::Title("Exercise 7.1 — a cart".into())
        );
        assert_eq!(
            only("problem \"A cart of mass m_A \" \\\n   \" slides.\""),
            StatementKind::Problem("A cart of mass m_A slides.".into())
        );
        assert_eq!(only("note \"x\""), StatementKind::Note("x".into()));
        let (_, diagnostics) = parse("note\n");
        assert_eq!(diagnostics.len(), 1);
        assert_eq!(diagnostics[0].kind.code(), "E002");
    }

    #[test]
    fn springs_dampers_and_frames() {
        let StatementKind::Spring {
            connection: Connection::Scalar(_),
            rest: Some(_),
            ..
        } = only("spring k on theta2 - theta1 rest 0.1")
        else {
            panic!()
        };
        let StatementKind::Damper {
            connection: Connection::Points { .. },
            ..
        } = only("damper c from A to B")
        else {
            panic!()
        };
        let StatementKind::Frame {
            rotation: Some((parent, rotations)),
            ..
        } = only("frame E = N rotated psi about z then theta about x then phi about z")
        else {
            panic!()
        };
        assert_eq!(parent.name, "N");
        let axes: Vec<&str> = rotations.iter().map(|r| r.axis.name.as_str()).collect();
        assert_eq!(axes, ["z", "x", "z"]);
    }

    #[test]
    fn unicode_names() {
        let StatementKind::Coordinates(names) = only("coordinates θ, φ₁, ẋ") else {
            panic!()
        };
        assert_eq!(
            names.iter().map(|n| n.name.as_str()).collect::<Vec<_>>(),
            ["θ", "φ₁", "ẋ"]
        );
    }

    mod display_round_trip {
        use super::*;
        use proptest::prelude::*;

        fn leaf() -> impl Strategy<Value = String> {
            prop_oneof![
                Just("x".to_string()),
                Just("theta'".to_string()),
                Just("N.y".to_string()),
                Just("2".to_string()),
                Just("0.5".to_string()),
                Just("pi".to_string()),
            ]
        }

        fn expression() -> impl Strategy<Value = String> {
            leaf().prop_recursive(5, 40, 3, |inner| {
                prop_oneof![
                    (
                        inner.clone(),
                        prop::sample::select(vec!["+", "-", "*", "/", "^", "**"]),
                        inner.clone()
                    )
                        .prop_map(|(a, op, b)| format!("{a} {op} {b}")),
                    inner.clone().prop_map(|a| format!("-{a}")),
                    inner.clone().prop_map(|a| format!("({a})")),
                    (inner.clone(), inner).prop_map(|(a, b)| format!("atan2({a}, {b})")),
                ]
            })
        }

        fn tree(source: &str) -> Expr {
            let (ast, diagnostics) = parse(&format!("gravity {source}"));
            assert!(diagnostics.is_empty(), "{source}: {diagnostics:?}");
            match ast.statements.into_iter().next().map(|s| s.kind) {
                Some(StatementKind::Gravity(e)) => e,
                other => panic!("{other:?}"),
            }
        }

        /// Compare shapes, ignoring spans.
        fn shape(expr: &Expr) -> String {
            super::show(expr)
        }

        proptest! {
            #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

            /// Printing an expression and parsing it back gives the same tree: `Display` puts
            /// parentheses exactly where precedence and associativity need them.
            #[test]
            fn printing_then_parsing_is_the_identity(source in expression()) {
                let first = tree(&source);
                let printed = first.to_string();
                let second = tree(&printed);
                prop_assert_eq!(shape(&first), shape(&second), "printed as {}", printed);
            }
        }
    }
}
