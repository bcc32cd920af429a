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
use crate::diagnostic::{suggest, Diagnostic, DiagnosticKind};
use crate::lexer::{lex, Spanned, Token, STATEMENT_KEYWORDS};
use crate::span::Span;

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

/// Binding power of unary minus: tighter than `*`, looser than `^` (`-x^2` is `-(x^2)`).
const PREFIX_POWER: u8 = 5;

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

    // --- statements -----------------------------------------------------------------------

    fn file(&mut self) -> Vec<Statement> {
        let mut statements = Vec::new();
        loop {
            while self.eat(Token::Newline).is_some() {}
            if self.at(Token::Eof) {
                break;
            }
            let start = self.peek().span;
            let first_token = self.position;
            let result = self.statement().and_then(|kind| {
                if self.at(Token::Newline) {
                    Ok(kind)
                } else {
                    Err(self.unexpected("end of line").with_help(
                        "Write one statement per line; end a line with `\\` to continue it on the next.",
                    ))
                }
            });
            match result {
                Ok(kind) => statements.push(Statement {
                    kind,
                    span: self.span_from(start),
                }),
                Err(diagnostic) => {
                    self.diagnostics.push(diagnostic);
                    while !self.at(Token::Newline) && !self.at(Token::Eof) {
                        self.bump();
                    }
                    self.note_broken_declaration(first_token);
                }
            }
        }
        statements
    }

    /// Remember the names that the broken statement starting at token `first` seems to
    /// declare: the name after a declaring keyword, and for lists, each name after a comma
    /// outside parentheses.
    fn note_broken_declaration(&mut self, first: usize) {
        let tokens = self.tokens.get(first..self.position).unwrap_or(&[]);
        let Some(keyword) = tokens.first().filter(|t| t.token == Token::Name) else {
            return;
        };
        let list = match self.text(keyword.span) {
            "coordinate" | "coordinates" | "parameter" | "parameters" | "input" | "inputs"
            | "constant" | "constants" | "driven" => true,
            "frame" | "point" | "body" | "constraint" => false,
            _ => return,
        };
        let mut depth = 0usize;
        let mut expect_name = true;
        for token in tokens.iter().skip(1) {
            match token.token {
                Token::Name if expect_name => {
                    self.broken_names.push(self.text(token.span).to_string())
                }
                Token::LParen => depth += 1,
                Token::RParen => depth = depth.saturating_sub(1),
                Token::Comma if list && depth == 0 => {
                    expect_name = true;
                    continue;
                }
                _ => {}
            }
            expect_name = false;
        }
    }

    fn statement(&mut self) -> ParseResult<StatementKind> {
        let first = self.peek();
        if first.token != Token::Name {
            return Err(self.unexpected("a statement such as `coordinates`, `point` or `body`"));
        }
        let word = self.text(first.span);
        let keyword = match word {
            "coordinate" | "coordinates" | "parameter" | "parameters" | "input" | "inputs"
            | "constant" | "constants" | "driven" | "frame" | "point" | "particle" | "body"
            | "gravity" | "spring" | "damper" | "dissipation" | "potential" | "force"
            | "couple" | "generalized" | "constraint" | "reaction" | "reactions" | "initial"
            | "simulate" | "output" | "outputs" => word,
            _ => {
                let mut diagnostic = Diagnostic::new(
                    DiagnosticKind::UnknownStatement {
                        word: word.to_string(),
                    },
                    first.span,
                );
                diagnostic = match suggest(word, STATEMENT_KEYWORDS.iter().copied()) {
                    Some(best) => diagnostic.with_help(format!("Did you mean `{best}`?")),
                    None => diagnostic.with_help(
                        "A statement starts with a keyword such as `coordinates`, `parameters`, `frame`, \
                         `point`, `particle`, `body`, `force` or `constraint`; see docs/language.md.",
                    ),
                };
                return Err(diagnostic);
            }
        };
        self.bump();
        Ok(match keyword {
            "coordinate" | "coordinates" => {
                StatementKind::Coordinates(self.ident_list("a coordinate name")?)
            }
            "parameter" | "parameters" => StatementKind::Parameters(self.bindings(false)?),
            "input" | "inputs" => StatementKind::Inputs(self.bindings(false)?),
            "constant" | "constants" => StatementKind::Constants(self.bindings(true)?),
            "driven" => StatementKind::Driven(self.bindings(true)?),
            "frame" => self.frame()?,
            "point" => {
                let name = self.ident("a point name")?;
                self.expect(Token::Equals, "`=` and the point's position")?;
                StatementKind::Point {
                    name,
                    position: self.expr()?,
                }
            }
            "particle" => {
                let point = self.ident("the name of the point where the particle is")?;
                self.expect_keyword("mass")
                    .map_err(|d| d.with_help("Write `particle A mass m`."))?;
                StatementKind::Particle {
                    point,
                    mass: self.expr()?,
                }
            }
            "body" => self.body()?,
            "gravity" => StatementKind::Gravity(self.expr()?),
            "spring" => {
                let stiffness = self.expr()?;
                let connection = self.connection("spring")?;
                let rest =
                    if self.eat_keyword("length").is_some() || self.eat_keyword("rest").is_some() {
                        Some(self.expr()?)
                    } else {
                        None
                    };
                StatementKind::Spring {
                    stiffness,
                    connection,
                    rest,
                }
            }
            "damper" => {
                let coefficient = self.expr()?;
                StatementKind::Damper {
                    coefficient,
                    connection: self.connection("damper")?,
                }
            }
            "dissipation" => StatementKind::Dissipation(self.expr()?),
            "potential" => StatementKind::Potential(self.expr()?),
            "force" => {
                let force = self.expr()?;
                self.expect_keyword("at")
                    .map_err(|d| d.with_help("Write `force F*N.x at A`."))?;
                StatementKind::Force {
                    force,
                    point: self.expr()?,
                }
            }
            "couple" => {
                let moment = self.expr()?;
                self.expect_keyword("on")
                    .map_err(|d| d.with_help("Write `couple C*N.z on BODY`."))?;
                StatementKind::Couple {
                    moment,
                    body: self.ident("a body name")?,
                }
            }
            "generalized" => {
                self.expect_keyword("force")?;
                let force = self.expr()?;
                self.expect_keyword("on")
                    .map_err(|d| d.with_help("Write `generalized force Q on theta`."))?;
                StatementKind::GeneralizedForce {
                    force,
                    coordinate: self.ident("a coordinate name")?,
                }
            }
            "constraint" => self.constraint()?,
            "reaction" | "reactions" => {
                if self.at(Token::Name) && self.nth(1).token == Token::Colon {
                    self.release()?
                } else {
                    StatementKind::Reactions(self.ident_list("a constraint name")?)
                }
            }
            "initial" => self.initial()?,
            "simulate" => self.simulate()?,
            _ => self.output()?,
        })
    }

    fn ident_list(&mut self, what: &str) -> ParseResult<Vec<Ident>> {
        let mut names = vec![self.ident(what)?];
        while self.eat(Token::Comma).is_some() {
            names.push(self.ident(what)?);
        }
        Ok(names)
    }

    fn bindings(&mut self, value_required: bool) -> ParseResult<Vec<Binding>> {
        let mut bindings = Vec::new();
        loop {
            let name = self.ident("a name")?;
            let value = if self.eat(Token::Equals).is_some() {
                Some(self.expr()?)
            } else if value_required {
                return Err(self.unexpected(format!("`=` and the value of `{}`", name.name)));
            } else {
                None
            };
            bindings.push(Binding { name, value });
            if self.eat(Token::Comma).is_none() {
                return Ok(bindings);
            }
        }
    }

    fn frame(&mut self) -> ParseResult<StatementKind> {
        let name = self.ident("a frame name")?;
        if self.eat(Token::Equals).is_none() {
            return Ok(StatementKind::Frame {
                name,
                rotation: None,
            });
        }
        let parent = self.ident("the frame this one is rotated from")?;
        self.expect_keyword("rotated")
            .map_err(|d| d.with_help("Write `frame B = N rotated theta about z`."))?;
        let mut rotations = Vec::new();
        loop {
            let angle = self.expr()?;
            self.expect_keyword("about").map_err(|d| {
                d.with_help("Name the axis of the rotation: `… rotated theta about z`.")
            })?;
            let axis = self.ident("an axis: `x`, `y` or `z`")?;
            rotations.push(Rotation { angle, axis });
            if self.eat_keyword("then").is_none() {
                break;
            }
        }
        Ok(StatementKind::Frame {
            name,
            rotation: Some((parent, rotations)),
        })
    }

    fn body(&mut self) -> ParseResult<StatementKind> {
        let name = self.ident("a body name")?;
        let mut clauses = BodyClauses::default();
        while self.at(Token::Name) {
            let keyword = self.bump();
            let word = self.text(keyword.span);
            let duplicate = match word {
                "mass" => clauses.mass.replace(self.expr()?).is_some(),
                "at" => clauses
                    .centre
                    .replace(self.ident("the centre-of-mass point")?)
                    .is_some(),
                "frame" => clauses
                    .frame
                    .replace(self.ident("the body frame")?)
                    .is_some(),
                "inertia" => {
                    let spec = self.inertia()?;
                    let about = if self.eat_keyword("about").is_some() {
                        Some(self.ident("a point")?)
                    } else {
                        None
                    };
                    let clause = InertiaClause {
                        spec,
                        about,
                        span: self.span_from(keyword.span),
                    };
                    clauses.inertia.replace(clause).is_some()
                }
                _ => {
                    let kind = DiagnosticKind::UnknownOption {
                        option: word.to_string(),
                        statement: "body",
                    };
                    let mut diagnostic = Diagnostic::new(kind, keyword.span);
                    if let Some(best) = suggest(word, ["mass", "at", "frame", "inertia"]) {
                        diagnostic = diagnostic.with_help(format!("Did you mean `{best}`?"));
                    } else {
                        diagnostic = diagnostic.with_help(
                            "A body takes `mass m`, `at C`, `frame B` and `inertia I1, I2, I3`.",
                        );
                    }
                    return Err(diagnostic);
                }
            };
            if duplicate {
                let kind = DiagnosticKind::DuplicateClause {
                    clause: word.to_string(),
                };
                return Err(Diagnostic::new(kind, keyword.span)
                    .with_help("Give each clause of a body once."));
            }
        }
        Ok(StatementKind::Body { name, clauses })
    }

    fn inertia(&mut self) -> ParseResult<InertiaSpec> {
        if self.at(Token::Name) && self.nth(1).token == Token::Equals {
            let mut components = Vec::new();
            loop {
                let key = self.ident("a component: `xx`, `yy`, `zz`, `xy`, `xz` or `yz`")?;
                self.expect(Token::Equals, "`=`")?;
                components.push((key, self.expr()?));
                if self.eat(Token::Comma).is_none() {
                    return Ok(InertiaSpec::Components(components));
                }
            }
        }
        let start = self.peek().span;
        let mut moments = vec![self.expr()?];
        while self.eat(Token::Comma).is_some() {
            moments.push(self.expr()?);
        }
        if moments.len() != 3 {
            let kind = DiagnosticKind::UnexpectedToken {
                expected: "three principal moments".to_string(),
                found: format!("{}", moments.len()),
            };
            return Err(Diagnostic::new(kind, self.span_from(start)).with_help(
                "Write `inertia I1, I2, I3` (principal moments along the body frame's axes) or \
                 `inertia xx = …, yy = …, zz = …, xy = …` for a full tensor.",
            ));
        }
        Ok(InertiaSpec::Principal(moments))
    }

    fn connection(&mut self, statement: &str) -> ParseResult<Connection> {
        if self.eat_keyword("from").is_some() {
            let from = self.expr()?;
            self.expect_keyword("to")?;
            Ok(Connection::Points {
                from,
                to: self.expr()?,
            })
        } else if self.eat_keyword("on").is_some() {
            Ok(Connection::Scalar(self.expr()?))
        } else {
            Err(self.unexpected("`from` or `on`").with_help(format!(
                "Write `{statement} k from A to B` between two points, or `{statement} k on theta` on an angle."
            )))
        }
    }

    fn constraint(&mut self) -> ParseResult<StatementKind> {
        let name = if self.at(Token::Name) && self.nth(1).token == Token::Colon {
            let name = self.ident("a constraint name")?;
            self.bump();
            Some(name)
        } else {
            None
        };
        let word_follows = self.nth(1).token == Token::Name;
        let spec = if word_follows && self.eat_keyword("rolling").is_some() {
            let body = self.ident("a body name")?;
            self.expect_keyword("at")
                .map_err(|d| d.with_help("Write `rolling BODY at CONTACT`."))?;
            ConstraintSpec::Rolling {
                body,
                contact: self.ident("the contact point")?,
            }
        } else if word_follows && self.eat_keyword("gear").is_some() {
            let driver = self.ident("a coordinate")?;
            self.expect_keyword("to")
                .map_err(|d| d.with_help("Write `gear phi1 to phi2 ratio r`."))?;
            let driven = self.ident("a coordinate")?;
            self.expect_keyword("ratio")
                .map_err(|d| d.with_help("Write `gear phi1 to phi2 ratio r`."))?;
            ConstraintSpec::Gear {
                driver,
                driven,
                ratio: self.expr()?,
            }
        } else {
            let lhs = self.expr()?;
            if self.at(Token::Newline) {
                // Report, then go on as if `= 0` had been written: the constraint's name is
                // then declared, and its uses (in `reactions`, say) raise no further errors.
                self.diagnostics.push(
                    Diagnostic::new(DiagnosticKind::NotAnEquation, lhs.span).with_help(format!(
                        "Write the constraint as an equation, e.g. `{} = 0`.",
                        self.text(lhs.span)
                    )),
                );
                let end = Span::new(lhs.span.end, lhs.span.end);
                let zero = Number {
                    text: "0".to_string(),
                    value: 0.0,
                };
                let rhs = Expr {
                    kind: ExprKind::Number(zero),
                    span: end,
                };
                return Ok(StatementKind::Constraint {
                    name,
                    spec: ConstraintSpec::Equation { lhs, rhs },
                });
            }
            self.expect(Token::Equals, "`=`")?;
            ConstraintSpec::Equation {
                lhs,
                rhs: self.expr()?,
            }
        };
        Ok(StatementKind::Constraint { name, spec })
    }

    /// `reaction NAME: hinge|contact|rope|clamp P on B1, B2 [normal|along n]` or
    /// `reaction NAME: rolling ROLL normal n`.
    fn release(&mut self) -> ParseResult<StatementKind> {
        let name = self.ident("a reaction name")?;
        self.bump();
        let help = "Write `reaction NAME: hinge P on BODY`, `reaction NAME: clamp P on BODY`, `reaction NAME: contact P on BODY normal n` or `reaction NAME: rope P on BODY along n`.";
        let word = if self.eat_keyword("hinge").is_some() {
            ReleaseWord::Hinge
        } else if self.eat_keyword("contact").is_some() {
            ReleaseWord::Contact
        } else if self.eat_keyword("rope").is_some() {
            ReleaseWord::Rope
        } else if self.eat_keyword("clamp").is_some() {
            ReleaseWord::Clamp
        } else if self.eat_keyword("rolling").is_some() {
            let point = self.ident("the name of a rolling constraint")?;
            self.expect_keyword("normal")
                .map_err(|d| d.with_help("Write `reaction NAME: rolling ROLL normal n`."))?;
            return Ok(StatementKind::Release {
                name,
                spec: ReleaseSpec {
                    word: ReleaseWord::Rolling,
                    point,
                    members: Vec::new(),
                    direction: Some(self.expr()?),
                },
            });
        } else {
            return Err(self
                .unexpected("`hinge`, `contact`, `rope`, `clamp` or `rolling`")
                .with_help(help));
        };
        let point = self.ident("the point where the constraint acts")?;
        self.expect_keyword("on").map_err(|d| d.with_help(help))?;
        let members = self.ident_list("a body or particle")?;
        let direction = match word {
            ReleaseWord::Hinge | ReleaseWord::Clamp | ReleaseWord::Rolling => None,
            ReleaseWord::Contact => {
                self.expect_keyword("normal")
                    .map_err(|d| d.with_help(help))?;
                Some(self.expr()?)
            }
            ReleaseWord::Rope => {
                self.expect_keyword("along")
                    .map_err(|d| d.with_help(help))?;
                Some(self.expr()?)
            }
        };
        Ok(StatementKind::Release {
            name,
            spec: ReleaseSpec {
                word,
                point,
                members,
                direction,
            },
        })
    }

    fn initial(&mut self) -> ParseResult<StatementKind> {
        let mut values = Vec::new();
        loop {
            let name = self.ident("a coordinate")?;
            let rate = self.eat(Token::Prime).is_some();
            self.expect(Token::Equals, "`=` and an initial value")?;
            values.push(InitialValue {
                name,
                rate,
                value: self.expr()?,
            });
            if self.eat(Token::Comma).is_none() {
                return Ok(StatementKind::Initial(values));
            }
        }
    }

    fn simulate(&mut self) -> ParseResult<StatementKind> {
        let mut settings = Vec::new();
        while self.at(Token::Name) {
            let key = self.ident("a setting")?;
            if !["from", "to", "step", "rtol", "atol", "method"].contains(&key.name.as_str()) {
                let mut diagnostic = Diagnostic::new(
                    DiagnosticKind::UnknownOption {
                        option: key.name.clone(),
                        statement: "simulate",
                    },
                    key.span,
                );
                diagnostic =
                    match suggest(&key.name, ["from", "to", "step", "rtol", "atol", "method"]) {
                        Some(best) => diagnostic.with_help(format!("Did you mean `{best}`?")),
                        None => diagnostic.with_help(
                            "`simulate` takes `from`, `to`, `step`, `rtol`, `atol` and `method`.",
                        ),
                    };
                return Err(diagnostic);
            }
            settings.push(Setting {
                key,
                value: self.expr()?,
            });
            self.eat(Token::Comma);
        }
        Ok(StatementKind::Simulate(settings))
    }

    fn output(&mut self) -> ParseResult<StatementKind> {
        let mut items = Vec::new();
        loop {
            let name = if self.at(Token::Name) && self.nth(1).token == Token::Equals {
                let name = self.ident("a name")?;
                self.bump();
                Some(name)
            } else {
                None
            };
            items.push(OutputItem {
                name,
                value: self.expr()?,
            });
            if self.eat(Token::Comma).is_none() {
                return Ok(StatementKind::Output(items));
            }
        }
    }

    // --- expressions ----------------------------------------------------------------------

    fn expr(&mut self) -> ParseResult<Expr> {
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
            Token::Number => {
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
            Token::Name => {
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
            Token::Minus | Token::Plus => {
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
            _ => Err(self.unexpected("an expression")),
        }
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
