//! Statement parsing: one method per statement keyword, and the per-line error recovery that
//! lets one run report every broken line.

use super::{ParseResult, Parser};
use crate::ast::*;
use crate::diagnostic::{suggest, Diagnostic, DiagnosticKind};
use crate::lexer::{Token, STATEMENT_KEYWORDS};
use crate::span::Span;

impl<'s> Parser<'s> {
    pub(super) fn file(&mut self) -> Vec<Statement> {
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
        let keyword = self.statement_keyword()?;
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
            "point" => self.point()?,
            "particle" => self.particle()?,
            "body" => self.body()?,
            "gravity" => StatementKind::Gravity(self.expr()?),
            "spring" => self.spring()?,
            "damper" => self.damper()?,
            "dissipation" => StatementKind::Dissipation(self.expr()?),
            "potential" => StatementKind::Potential(self.expr()?),
            "force" => self.force()?,
            "couple" => self.couple()?,
            "generalized" => self.generalized_force()?,
            "constraint" => self.constraint()?,
            "reaction" | "reactions" => self.reactions()?,
            "initial" => self.initial()?,
            "simulate" => self.simulate()?,
            "title" => StatementKind::Title(self.prose("title")?),
            "problem" => StatementKind::Problem(self.prose("problem")?),
            "note" => StatementKind::Note(self.prose("note")?),
            _ => self.output()?,
        })
    }

    /// The keyword that starts the current statement, not yet consumed; an unknown word is an
    /// error with a suggestion.
    fn statement_keyword(&self) -> ParseResult<&'s str> {
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
            | "simulate" | "output" | "outputs" | "title" | "problem" | "note" => word,
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
        Ok(keyword)
    }

    fn point(&mut self) -> ParseResult<StatementKind> {
        let name = self.ident("a point name")?;
        self.expect(Token::Equals, "`=` and the point's position")?;
        Ok(StatementKind::Point {
            name,
            position: self.expr()?,
        })
    }

    fn particle(&mut self) -> ParseResult<StatementKind> {
        let point = self.ident("the name of the point where the particle is")?;
        self.expect_keyword("mass")
            .map_err(|d| d.with_help("Write `particle A mass m`."))?;
        Ok(StatementKind::Particle {
            point,
            mass: self.expr()?,
        })
    }

    fn spring(&mut self) -> ParseResult<StatementKind> {
        let stiffness = self.expr()?;
        let connection = self.connection("spring")?;
        let rest = if self.eat_keyword("length").is_some() || self.eat_keyword("rest").is_some() {
            Some(self.expr()?)
        } else {
            None
        };
        Ok(StatementKind::Spring {
            stiffness,
            connection,
            rest,
        })
    }

    fn damper(&mut self) -> ParseResult<StatementKind> {
        let coefficient = self.expr()?;
        Ok(StatementKind::Damper {
            coefficient,
            connection: self.connection("damper")?,
        })
    }

    fn force(&mut self) -> ParseResult<StatementKind> {
        let force = self.expr()?;
        self.expect_keyword("at")
            .map_err(|d| d.with_help("Write `force F*N.x at A`."))?;
        Ok(StatementKind::Force {
            force,
            point: self.expr()?,
        })
    }

    fn couple(&mut self) -> ParseResult<StatementKind> {
        let moment = self.expr()?;
        self.expect_keyword("on")
            .map_err(|d| d.with_help("Write `couple C*N.z on BODY`."))?;
        Ok(StatementKind::Couple {
            moment,
            body: self.ident("a body name")?,
        })
    }

    fn generalized_force(&mut self) -> ParseResult<StatementKind> {
        self.expect_keyword("force")?;
        let force = self.expr()?;
        self.expect_keyword("on")
            .map_err(|d| d.with_help("Write `generalized force Q on theta`."))?;
        Ok(StatementKind::GeneralizedForce {
            force,
            coordinate: self.ident("a coordinate name")?,
        })
    }

    /// `reactions A, B` lists constraints; `reaction NAME: ...` releases one.
    fn reactions(&mut self) -> ParseResult<StatementKind> {
        if self.at(Token::Name) && self.nth(1).token == Token::Colon {
            self.release()
        } else {
            Ok(StatementKind::Reactions(
                self.ident_list("a constraint name")?,
            ))
        }
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
            let direction = Some(self.expr()?);
            return Ok(StatementKind::Release {
                name,
                spec: ReleaseSpec {
                    word: ReleaseWord::Rolling,
                    point,
                    members: Vec::new(),
                    direction,
                    projection: self.release_projection(true)?,
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
        let projection = self.release_projection(word != ReleaseWord::Rope)?;
        Ok(StatementKind::Release {
            name,
            spec: ReleaseSpec {
                word,
                point,
                members,
                direction,
                projection,
            },
        })
    }

    /// The optional `in frame R` or (when `along` is free, not a rope's direction) `along n`
    /// that ends a `reaction NAME: …` statement.
    fn release_projection(&mut self, along: bool) -> ParseResult<Option<ReleaseProjection>> {
        if self.eat_keyword("in").is_some() {
            self.expect_keyword("frame").map_err(|d| {
                d.with_help("Write `… in frame R` to have the force's components along R's axes.")
            })?;
            return Ok(Some(ReleaseProjection::Frame(self.ident("a frame")?)));
        }
        if along && self.eat_keyword("along").is_some() {
            return Ok(Some(ReleaseProjection::Along(self.expr()?)));
        }
        Ok(None)
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

    /// The prose of `title`, `problem` or `note`: one or more texts in double quotes (several
    /// when `\` continues the statement), joined by single spaces.
    fn prose(&mut self, keyword: &str) -> ParseResult<String> {
        let mut parts = Vec::new();
        while let Some(token) = self.eat(Token::Text) {
            let quoted = self.text(token.span);
            let inner = quoted.strip_prefix('"').unwrap_or(quoted);
            parts.push(inner.strip_suffix('"').unwrap_or(inner).trim());
        }
        if parts.is_empty() {
            return Err(self
                .unexpected("a text in double quotes")
                .with_help(format!("Write `{keyword} \"…\"`.")));
        }
        Ok(parts.join(" "))
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
}
