//! The expression parser: reads the text syntax that [`crate::print::to_sympy`] writes (SymPy
//! syntax) back into an [`Expr`], with errors that point at the offending column.
//!
//! * [`parse`] — text → [`Expr`], given a [`ParseContext`] that says which names are functions
//!   of time (coordinates and inputs).
//! * [`ParseError`] — what went wrong ([`ParseErrorKind`]), where (a byte [`ParseError::span`]
//!   and a 1-based [`ParseError::column`]) and how to mend it ([`ParseError::help`]);
//!   [`ParseError::render`] draws the source line with the offending columns underlined.
//!
//! The grammar, loosest binding first (the same precedences as Python, so SymPy's output reads
//! back as SymPy meant it):
//!
//! ```text
//! sum     = product (("+" | "-") product)*
//! product = unary (("*" | "/") unary)*
//! unary   = ("+" | "-") unary | power
//! power   = atom (("^" | "**") unary)?          right-associative; -x^2 is -(x^2)
//! atom    = number | name | name "(" sum ("," sum)* ")" | "(" sum ")"
//! ```
//!
//! Names resolve as follows: a name listed in the context, or whose rate the text uses
//! (`x` in `sin(x)*x_d`), is a coordinate `q(t)`; `NAME_d`,
//! `NAME_dd`, … are the rates of `NAME` (always: the suffix says it is a function of time); `t`
//! is time, `pi` is π, `E` is Euler's number, `oo` and `nan` are the floats SymPy names so;
//! anything else is a constant symbol. Implicit
//! multiplication (`2x`) is an error with a hint, never a guess. The parser never panics: nesting
//! is capped at [`MAX_DEPTH`] and numeric powers that would build astronomically large exact
//! numbers are refused.

use std::collections::BTreeSet;
use std::ops::Range;

use crate::expr::{Expr, Node, SymbolKind};
use crate::number::{LiteralError, Number};
use crate::Func;

/// The deepest nesting of parentheses, signs and powers the parser accepts.
pub const MAX_DEPTH: usize = 256;

/// The largest exact number (in bits) a numeric power in the input may produce; `2^100000`
/// is fine, `2^10^10` is refused rather than exhausting memory.
const MAX_POWER_BITS: u64 = 1 << 20;

/// Parses an expression.
///
/// ```
/// use cas::parse::{parse, ParseContext};
/// use cas::Expr;
/// let ctx = ParseContext::new().with_coordinate("theta");
/// let e = parse("l*theta_d**2*sin(theta)", &ctx).unwrap();
/// let th = Expr::coordinate("theta");
/// assert_eq!(e, Expr::symbol("l") * Expr::rate("theta", 1).powi(2) * th.sin());
/// ```
pub fn parse(text: &str, ctx: &ParseContext) -> Result<Expr, ParseError> {
    let tokens = lex(text)?;
    let ctx = &with_rated_names(text, &tokens, ctx);
    let mut p = Parser {
        src: text,
        tokens,
        pos: 0,
        ctx,
        depth: 0,
    };
    if p.peek().tok == Tok::End {
        return Err(p.error(ParseErrorKind::Empty, p.peek().span.clone()));
    }
    let e = p.sum()?;
    let t = p.peek().clone();
    match t.tok {
        Tok::End => Ok(e),
        Tok::RParen => Err(p.error(ParseErrorKind::UnmatchedClose, t.span)),
        _ => Err(p.unexpected_after_operand(&t)),
    }
}

/// `ctx` with every name whose rate the text uses (`x_d`, `θ̇`) declared a function of time:
/// `sin(x)*x_d` means the coordinate `x` and its rate, so that `d/dt` gives `cos x ẋ²`
/// (issue 14), rather than a constant `x` beside a rate of another `x`.
fn with_rated_names(text: &str, tokens: &[Token], ctx: &ParseContext) -> ParseContext {
    let mut out = ctx.clone();
    for t in tokens.iter().filter(|t| t.tok == Tok::Name) {
        let (name, marks) = from_unicode_name(&text[t.span.clone()]);
        if marks > 0 {
            out.time_functions.insert(name);
        } else if let Some((base, _)) = split_rate_suffix(&name) {
            out.time_functions.insert(base.to_owned());
        }
    }
    out
}

/// Which names denote functions of time; everything else the parser resolves by itself.
///
/// Default: no coordinates (rates `q_d`, `q_dd` are still recognised by their suffix).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
#[must_use]
pub struct ParseContext {
    time_functions: BTreeSet<String>,
}

impl ParseContext {
    /// A context with no coordinates.
    pub fn new() -> ParseContext {
        ParseContext::default()
    }

    /// Declares `name` a function of time (a coordinate or a time-dependent input).
    pub fn with_coordinate(mut self, name: &str) -> ParseContext {
        self.time_functions.insert(name.to_owned());
        self
    }

    /// Declares every name in `names` a function of time.
    pub fn with_coordinates<S: AsRef<str>>(
        mut self,
        names: impl IntoIterator<Item = S>,
    ) -> ParseContext {
        self.time_functions
            .extend(names.into_iter().map(|s| s.as_ref().to_owned()));
        self
    }

    /// The context that reads back what [`crate::print::to_sympy`] printed for `e`: every
    /// function of time that occurs in `e` (at any derivative order) is a coordinate.
    pub fn for_expr(e: Expr) -> ParseContext {
        let mut ctx = ParseContext::new();
        let mut stack = vec![e];
        let mut seen = rustc_hash::FxHashSet::default();
        while let Some(x) = stack.pop() {
            if !seen.insert(x) {
                continue;
            }
            if let Node::Symbol(s) = x.node() {
                if let SymbolKind::TimeFunction { .. } = s.kind() {
                    ctx.time_functions.insert(s.name().to_owned());
                }
            }
            stack.extend_from_slice(x.children());
        }
        ctx
    }

    /// The names declared functions of time, sorted.
    pub fn coordinate_names(&self) -> impl Iterator<Item = String> + '_ {
        self.time_functions.iter().cloned()
    }

    /// Whether `name` was declared a function of time.
    pub fn is_coordinate(&self, name: &str) -> bool {
        self.time_functions.contains(name)
    }
}

/// A malformed expression: what is wrong, where, and how to mend it.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{kind} at column {column}")]
pub struct ParseError {
    kind: ParseErrorKind,
    span: Range<usize>,
    column: usize,
    line: usize,
}

/// What is wrong with a malformed expression.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ParseErrorKind {
    /// The input holds no expression.
    #[error("expected an expression, found nothing")]
    Empty,
    /// A character that is not part of the syntax.
    #[error("unexpected character `{0}`")]
    UnexpectedChar(char),
    /// A number literal that does not read as a number.
    #[error("malformed number `{0}`")]
    BadNumber(String),
    /// An operator or separator with nothing after it.
    #[error("expected an expression after `{after}`, found {found}")]
    ExpectedOperand {
        /// The operator before the gap.
        after: String,
        /// What came instead (a quoted token or "the end of the input").
        found: String,
    },
    /// A token where an operator or the end was expected.
    #[error("unexpected {0}")]
    Unexpected(String),
    /// Two operands side by side (`2x`, `x y`, `2(x+1)`).
    #[error("missing operator between `{left}` and `{right}`")]
    ImplicitMultiplication {
        /// The operand on the left.
        left: String,
        /// The operand on the right.
        right: String,
    },
    /// A `(` that is never closed.
    #[error("unbalanced parenthesis: this `(` is never closed")]
    UnclosedParen,
    /// A `)` with no matching `(`.
    #[error("unbalanced parenthesis: this `)` has no matching `(`")]
    UnmatchedClose,
    /// A call of a function the core does not know.
    #[error("unknown function `{name}`")]
    UnknownFunction {
        /// The name as written.
        name: String,
        /// The closest known function name, if one is close.
        suggestion: Option<&'static str>,
    },
    /// A function name used without an argument list (`sin x`).
    #[error("`{0}` is a function and needs its argument in parentheses")]
    FunctionWithoutCall(String),
    /// A call with the wrong number of arguments.
    #[error("`{name}` takes {expected} argument{}, found {found}", if *expected == 1 { "" } else { "s" })]
    WrongArity {
        /// The function.
        name: String,
        /// How many arguments it takes.
        expected: usize,
        /// How many were written.
        found: usize,
    },
    /// A rate suffix (`_ddd…`) of more than 255 derivatives.
    #[error("derivative order {0} is too high (at most 255)")]
    RateOrderTooHigh(usize),
    /// Nesting deeper than [`MAX_DEPTH`].
    #[error("expression nested more than {0} levels deep")]
    TooDeep(usize),
    /// A number literal whose written exponent is beyond the limit.
    #[error("the exponent of `{text}` is too large (at most ±{limit})")]
    ExponentTooLarge {
        /// The literal as written.
        text: String,
        /// The largest exponent allowed.
        limit: u32,
    },
    /// A division by an expression that is zero (`1/0`, `x/(y - y)`, `0^-1`).
    #[error("division by zero")]
    DivisionByZero,
    /// A numeric power whose exact value would be astronomically large.
    #[error("this power of a number is too large to compute exactly")]
    NumberTooLarge,
}

impl ParseError {
    /// What is wrong.
    pub fn kind(&self) -> &ParseErrorKind {
        &self.kind
    }

    /// The byte range of the offending text in the source (empty at the end of the input).
    pub fn span(&self) -> Range<usize> {
        self.span.clone()
    }

    /// The 1-based column (in characters) where the offending text starts.
    pub fn column(&self) -> usize {
        self.column
    }

    /// The 1-based line where the offending text starts.
    pub fn line(&self) -> usize {
        self.line
    }

    /// How to mend it, when there is something useful to say.
    pub fn help(&self) -> Option<String> {
        match &self.kind {
            ParseErrorKind::Empty => Some("write an expression such as `m*g*l*cos(theta)`".into()),
            ParseErrorKind::UnexpectedChar(_) => Some(
                "expressions use names, numbers, `+ - * / ^ **`, parentheses and commas".into(),
            ),
            ParseErrorKind::BadNumber(_) => {
                Some("write numbers as `12`, `0.5`, `1e-3` or `2.5E+4`".into())
            }
            ParseErrorKind::ExpectedOperand { .. } => {
                Some("an operator needs an expression on both sides".into())
            }
            ParseErrorKind::Unexpected(_) => Some(
                "an operator (`+ - * / ^`) or the end of the expression was expected here".into(),
            ),
            ParseErrorKind::ImplicitMultiplication { left, right } => Some(format!(
                "multiplication must be written out: `{left}*{right}`"
            )),
            ParseErrorKind::UnclosedParen => Some("add a `)` where the group ends".into()),
            ParseErrorKind::UnmatchedClose => Some("remove it, or add the `(` it closes".into()),
            ParseErrorKind::UnknownFunction {
                suggestion: Some(s),
                ..
            } => Some(format!("did you mean `{s}`?")),
            ParseErrorKind::UnknownFunction {
                suggestion: None, ..
            } => Some(format!(
                "the functions are {}; for a product write `*`",
                KNOWN_FUNCTIONS.join(", ")
            )),
            ParseErrorKind::FunctionWithoutCall(name) => Some(format!("write `{name}(x)`")),
            ParseErrorKind::WrongArity {
                name, expected: 2, ..
            } => Some(format!("write `{name}(a, b)`")),
            ParseErrorKind::WrongArity { name, .. } => Some(format!("write `{name}(x)`")),
            ParseErrorKind::RateOrderTooHigh(_) => None,
            ParseErrorKind::TooDeep(_) => {
                Some("split the expression or remove redundant parentheses".into())
            }
            ParseErrorKind::ExponentTooLarge { .. } => {
                Some("numbers are exact: write the quantity in other units, or as a symbol".into())
            }
            ParseErrorKind::DivisionByZero => {
                Some("this divisor is zero: the expression has no value".into())
            }
            ParseErrorKind::NumberTooLarge => {
                Some("numbers are exact: use a smaller exponent, or keep the base a symbol".into())
            }
        }
    }

    /// Draws the offending source line with the offending columns underlined, the message and
    /// the help, as plain text:
    ///
    /// ```text
    /// sn(x) + 1
    /// ^^ unknown function `sn`
    /// help: did you mean `sin`?
    /// ```
    pub fn render(&self, source: &str) -> String {
        let start = floor_char_boundary(source, self.span.start);
        let line_start = source[..start].rfind('\n').map_or(0, |i| i + 1);
        let line_end = source[start..]
            .find('\n')
            .map_or(source.len(), |i| start + i);
        let line = &source[line_start..line_end];
        let end = floor_char_boundary(source, self.span.end.clamp(start, line_end));
        // Columns count characters, so a Greek name before the error does not shift the caret;
        // tabs are drawn as single spaces to keep the caret under its character.
        let pad = source[line_start..start].chars().count();
        let width = source[start..end].chars().count().max(1);
        let mut out = String::new();
        out.push_str(&line.replace('\t', " "));
        out.push('\n');
        out.push_str(&" ".repeat(pad));
        out.push_str(&"^".repeat(width));
        out.push(' ');
        out.push_str(&self.kind.to_string());
        if let Some(help) = self.help() {
            out.push_str("\nhelp: ");
            out.push_str(&help);
        }
        out
    }
}

// ---------------------------------------------------------------------------------------------
// Lexer.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Tok {
    Number,
    Name,
    Plus,
    Minus,
    Star,
    Slash,
    Power,
    LParen,
    RParen,
    Comma,
    End,
}

#[derive(Clone, Debug)]
struct Token {
    tok: Tok,
    span: Range<usize>,
}

/// Combining dot above and diaeresis: the rate marks the Unicode printer puts on a name.
const COMBINING_DOT: char = '\u{307}';
const COMBINING_DOTS: char = '\u{308}';

fn lex(src: &str) -> Result<Vec<Token>, ParseError> {
    let mut tokens = Vec::new();
    let mut it = src.char_indices().peekable();
    while let Some((i, c)) = it.next() {
        let single = |tok| Token {
            tok,
            span: i..i + c.len_utf8(),
        };
        match c {
            c if c.is_whitespace() => {}
            '+' => tokens.push(single(Tok::Plus)),
            // The Unicode minus is what our own Unicode printer writes.
            '-' | '\u{2212}' => tokens.push(single(Tok::Minus)),
            '*' => {
                if let Some(&(j, '*')) = it.peek() {
                    it.next();
                    tokens.push(Token {
                        tok: Tok::Power,
                        span: i..j + 1,
                    });
                } else {
                    tokens.push(single(Tok::Star));
                }
            }
            '·' | '×' => tokens.push(single(Tok::Star)),
            '/' | '÷' => tokens.push(single(Tok::Slash)),
            '^' => tokens.push(single(Tok::Power)),
            '(' => tokens.push(single(Tok::LParen)),
            ')' => tokens.push(single(Tok::RParen)),
            ',' => tokens.push(single(Tok::Comma)),
            c if c.is_ascii_digit() || c == '.' => {
                let end = number_end(src, i);
                let text = &src[i..end];
                if let Err(e) = Number::parse_literal(text) {
                    return Err(error_at(src, literal_error_kind(e), i..end));
                }
                while it.peek().is_some_and(|&(j, _)| j < end) {
                    it.next();
                }
                tokens.push(Token {
                    tok: Tok::Number,
                    span: i..end,
                });
            }
            c if c.is_alphabetic() || c == '_' => {
                let mut end = i + c.len_utf8();
                while let Some(&(j, d)) = it.peek() {
                    if d.is_alphanumeric() || d == '_' || d == COMBINING_DOT || d == COMBINING_DOTS
                    {
                        end = j + d.len_utf8();
                        it.next();
                    } else {
                        break;
                    }
                }
                tokens.push(Token {
                    tok: Tok::Name,
                    span: i..end,
                });
            }
            c => {
                return Err(error_at(
                    src,
                    ParseErrorKind::UnexpectedChar(c),
                    single(Tok::End).span,
                ))
            }
        }
    }
    tokens.push(Token {
        tok: Tok::End,
        span: src.len()..src.len(),
    });
    Ok(tokens)
}

/// The end of the number literal starting at byte `start`: digits, an optional fraction and an
/// optional exponent. An `e` not followed by digits is left alone (`2E` is `2` then `E`).
fn number_end(src: &str, start: usize) -> usize {
    let b = src.as_bytes();
    let mut i = start;
    while i < b.len() && b[i].is_ascii_digit() {
        i += 1;
    }
    if i < b.len() && b[i] == b'.' {
        i += 1;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
        }
    }
    if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
        let mut j = i + 1;
        if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
            j += 1;
        }
        if j < b.len() && b[j].is_ascii_digit() {
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
            i = j;
        }
    }
    i
}

fn floor_char_boundary(s: &str, mut i: usize) -> usize {
    i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

fn error_at(src: &str, kind: ParseErrorKind, span: Range<usize>) -> ParseError {
    let start = floor_char_boundary(src, span.start);
    let before = &src[..start];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = src[line_start..start].chars().count() + 1;
    ParseError {
        kind,
        span,
        column,
        line,
    }
}

// ---------------------------------------------------------------------------------------------
// Parser.

/// Names the parser treats as functions, for suggestions.
const KNOWN_FUNCTIONS: &[&str] = &[
    "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "exp", "ln", "log", "sqrt", "abs", "Abs",
    "sign", "Rational",
];

struct Parser<'a> {
    src: &'a str,
    tokens: Vec<Token>,
    pos: usize,
    ctx: &'a ParseContext,
    depth: usize,
}

impl Parser<'_> {
    fn peek(&self) -> &Token {
        // The token list always ends with `End`, and `pos` never moves past it.
        &self.tokens[self.pos.min(self.tokens.len() - 1)]
    }

    fn bump(&mut self) -> Token {
        let t = self.peek().clone();
        if t.tok != Tok::End {
            self.pos += 1;
        }
        t
    }

    fn text(&self, span: &Range<usize>) -> &str {
        &self.src[span.clone()]
    }

    fn error(&self, kind: ParseErrorKind, span: Range<usize>) -> ParseError {
        error_at(self.src, kind, span)
    }

    fn describe(&self, t: &Token) -> String {
        match t.tok {
            Tok::End => "the end of the input".to_owned(),
            _ => format!("`{}`", self.text(&t.span)),
        }
    }

    fn enter(&mut self) -> Result<(), ParseError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self.error(ParseErrorKind::TooDeep(MAX_DEPTH), self.peek().span.clone()));
        }
        Ok(())
    }

    /// The error for token `t` found right after a complete operand.
    fn unexpected_after_operand(&self, t: &Token) -> ParseError {
        match t.tok {
            Tok::Number | Tok::Name | Tok::LParen => {
                let prev = &self.tokens[self.pos.saturating_sub(1)];
                let left = self.text(&prev.span).to_owned();
                let right = match t.tok {
                    Tok::LParen => "(".to_owned(),
                    _ => self.text(&t.span).to_owned(),
                };
                self.error(
                    ParseErrorKind::ImplicitMultiplication { left, right },
                    t.span.clone(),
                )
            }
            _ => self.error(ParseErrorKind::Unexpected(self.describe(t)), t.span.clone()),
        }
    }

    /// Requires an operand to start at the current token; `after` is the operator before it.
    fn expect_operand(&self, after: &Token) -> Result<(), ParseError> {
        let t = self.peek();
        match t.tok {
            Tok::Number | Tok::Name | Tok::LParen | Tok::Plus | Tok::Minus => Ok(()),
            Tok::RParen if after.tok == Tok::LParen => Err(self.error(
                ParseErrorKind::ExpectedOperand {
                    after: "(".into(),
                    found: "`)`".into(),
                },
                t.span.clone(),
            )),
            _ => Err(self.error(
                ParseErrorKind::ExpectedOperand {
                    after: self.text(&after.span).to_owned(),
                    found: self.describe(t),
                },
                t.span.clone(),
            )),
        }
    }

    fn sum(&mut self) -> Result<Expr, ParseError> {
        // Terms are gathered and summed once: `add_all` flattens, so this builds the same node
        // as folding left to right, in linear rather than quadratic time.
        let mut terms = vec![self.product()?];
        loop {
            let t = self.peek().clone();
            let negate = match t.tok {
                Tok::Plus => false,
                Tok::Minus => true,
                _ => break,
            };
            self.bump();
            self.expect_operand(&t)?;
            let term = self.product()?;
            terms.push(if negate { -term } else { term });
        }
        Ok(if terms.len() == 1 {
            terms[0]
        } else {
            Expr::add_all(terms)
        })
    }

    fn product(&mut self) -> Result<Expr, ParseError> {
        let mut factors = vec![self.unary()?];
        loop {
            let t = self.peek().clone();
            let divide = match t.tok {
                Tok::Star => false,
                Tok::Slash => true,
                _ => break,
            };
            self.bump();
            self.expect_operand(&t)?;
            let start = self.peek().span.start;
            let f = self.unary()?;
            if divide {
                self.nonzero_divisor(f, start)?;
            }
            factors.push(if divide { f.powi(-1) } else { f });
        }
        Ok(if factors.len() == 1 {
            factors[0]
        } else {
            Expr::mul_all(factors)
        })
    }

    fn unary(&mut self) -> Result<Expr, ParseError> {
        let t = self.peek().clone();
        match t.tok {
            Tok::Plus | Tok::Minus => {
                self.bump();
                self.enter()?;
                self.expect_operand(&t)?;
                let e = self.unary()?;
                self.depth -= 1;
                Ok(if t.tok == Tok::Minus { -e } else { e })
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Expr, ParseError> {
        let start = self.peek().span.start;
        let base = self.atom()?;
        let t = self.peek().clone();
        if t.tok != Tok::Power {
            return Ok(base);
        }
        self.bump();
        self.enter()?;
        self.expect_operand(&t)?;
        let exp = self.unary()?;
        self.depth -= 1;
        let end = self.tokens[self.pos.saturating_sub(1)].span.end;
        if power_too_large(base, exp) {
            return Err(self.error(ParseErrorKind::NumberTooLarge, start..end));
        }
        if base.is_literal_zero() && exp.as_number().is_some_and(|n| n.signum() < 0) {
            return Err(self.error(ParseErrorKind::DivisionByZero, start..end));
        }
        Ok(base.pow(exp))
    }

    /// Refuses a divisor that is zero as built (`0`, `x - x`, `2 - 2`): the constructors
    /// would otherwise fold `0 * (1/0)` or `(x-x)/(x-x)` to a silent 0. A divisor that is zero
    /// only after normalisation (`sin(x)^2 + cos(x)^2 - 1`) is not detected here.
    fn nonzero_divisor(&self, divisor: Expr, start: usize) -> Result<(), ParseError> {
        if divisor.is_literal_zero() {
            let end = self.tokens[self.pos.saturating_sub(1)].span.end;
            return Err(self.error(ParseErrorKind::DivisionByZero, start..end));
        }
        Ok(())
    }

    fn atom(&mut self) -> Result<Expr, ParseError> {
        let t = self.bump();
        let e = match t.tok {
            Tok::Number => {
                let text = self.text(&t.span);
                let n = Number::parse_literal(text)
                    .map_err(|e| self.error(literal_error_kind(e), t.span.clone()))?;
                Expr::number(n)
            }
            Tok::Name => {
                if self.peek().tok == Tok::LParen {
                    self.call(&t)?
                } else {
                    self.name(&t)?
                }
            }
            Tok::LParen => {
                self.enter()?;
                self.expect_operand(&t)?;
                let e = self.sum()?;
                self.depth -= 1;
                match self.peek().tok {
                    Tok::RParen => {
                        self.bump();
                    }
                    Tok::End => return Err(self.error(ParseErrorKind::UnclosedParen, t.span)),
                    _ => {
                        let u = self.peek().clone();
                        return Err(self.unexpected_after_operand(&u));
                    }
                }
                e
            }
            Tok::RParen => return Err(self.error(ParseErrorKind::UnmatchedClose, t.span)),
            Tok::End => {
                return Err(self.error(
                    ParseErrorKind::ExpectedOperand {
                        after: String::new(),
                        found: "the end of the input".into(),
                    },
                    t.span,
                ))
            }
            _ => return Err(self.error(ParseErrorKind::Unexpected(self.describe(&t)), t.span)),
        };
        // Two operands side by side: report it here, where both are known.
        let next = self.peek().clone();
        if matches!(next.tok, Tok::Number | Tok::Name | Tok::LParen) {
            return Err(self.unexpected_after_operand(&next));
        }
        Ok(e)
    }

    fn name(&self, t: &Token) -> Result<Expr, ParseError> {
        let raw = self.text(&t.span);
        if Func::from_name(raw).is_some() || raw == "sqrt" || raw == "Rational" {
            return Err(self.error(
                ParseErrorKind::FunctionWithoutCall(raw.to_owned()),
                t.span.clone(),
            ));
        }
        let (name, marks) = from_unicode_name(raw);
        if marks > 0 {
            return Ok(Expr::rate(&name, marks));
        }
        if self.ctx.is_coordinate(&name) {
            return Ok(Expr::coordinate(&name));
        }
        match name.as_str() {
            "t" => return Ok(Expr::time()),
            "pi" => return Ok(Expr::pi()),
            "E" => return Ok(Expr::one().exp()),
            // SymPy's infinity and not-a-number, which float arithmetic can produce.
            "oo" => return Ok(Expr::float(f64::INFINITY)),
            "nan" => return Ok(Expr::float(f64::NAN)),
            _ => {}
        }
        if let Some((base, k)) = split_rate_suffix(&name) {
            let order = u8::try_from(k)
                .map_err(|_| self.error(ParseErrorKind::RateOrderTooHigh(k), t.span.clone()))?;
            return Ok(Expr::rate(base, order));
        }
        Ok(Expr::symbol(&name))
    }

    fn call(&mut self, name_tok: &Token) -> Result<Expr, ParseError> {
        let name = self.text(&name_tok.span).to_owned();
        let open = self.bump();
        self.enter()?;
        let mut args = Vec::new();
        if self.peek().tok == Tok::RParen {
            self.bump();
        } else {
            loop {
                let before = self.tokens[self.pos.saturating_sub(1)].clone();
                self.expect_operand(&before)?;
                args.push(self.sum()?);
                let t = self.peek().clone();
                match t.tok {
                    Tok::Comma => {
                        self.bump();
                    }
                    Tok::RParen => {
                        self.bump();
                        break;
                    }
                    Tok::End => return Err(self.error(ParseErrorKind::UnclosedParen, open.span)),
                    _ => return Err(self.unexpected_after_operand(&t)),
                }
            }
        }
        self.depth -= 1;
        let span = name_tok.span.start..self.tokens[self.pos - 1].span.end;
        let arity = |expected: usize| -> Result<(), ParseError> {
            if args.len() == expected {
                Ok(())
            } else {
                Err(self.error(
                    ParseErrorKind::WrongArity {
                        name: name.clone(),
                        expected,
                        found: args.len(),
                    },
                    span.clone(),
                ))
            }
        };
        if let Some(f) = Func::from_name(&name) {
            arity(f.arity())?;
            return Ok(Expr::func(f, args.clone()));
        }
        match name.as_str() {
            "sqrt" => {
                arity(1)?;
                Ok(args[0].sqrt())
            }
            "Rational" => {
                arity(2)?;
                if args[1].is_literal_zero() {
                    return Err(self.error(ParseErrorKind::DivisionByZero, span.clone()));
                }
                Ok(args[0] / args[1])
            }
            // SymPy writes a function of time as `theta(t)`; read it as the coordinate.
            _ if args.len() == 1 && args[0] == Expr::time() => {
                let (base, _) = from_unicode_name(&name);
                Ok(Expr::coordinate(&base))
            }
            _ => Err(self.error(
                ParseErrorKind::UnknownFunction {
                    suggestion: suggest(&name),
                    name: name.clone(),
                },
                name_tok.span.clone(),
            )),
        }
    }
}

fn literal_error_kind(e: LiteralError) -> ParseErrorKind {
    match e {
        LiteralError::ExponentTooLarge { text, limit } => {
            ParseErrorKind::ExponentTooLarge { text, limit }
        }
        LiteralError::Malformed(text) => ParseErrorKind::BadNumber(text),
    }
}

/// `theta_dd` → `("theta", 2)`; `None` when the name has no rate suffix.
fn split_rate_suffix(name: &str) -> Option<(&str, usize)> {
    let trimmed = name.trim_end_matches('d');
    let k = name.len() - trimmed.len();
    let base = trimmed.strip_suffix('_')?;
    (k > 0 && !base.is_empty()).then_some((base, k))
}

/// Reads a name as the Unicode printer writes it: Greek letters and `ℓ` back to their ASCII
/// names, and rate dots (combining dot above, diaeresis) counted and removed.
fn from_unicode_name(raw: &str) -> (String, u8) {
    if raw.is_ascii() {
        return (raw.to_owned(), 0);
    }
    let mut out = String::with_capacity(raw.len() * 2);
    let mut marks: u8 = 0;
    for c in raw.chars() {
        match c {
            COMBINING_DOT => marks = marks.saturating_add(1),
            COMBINING_DOTS => marks = marks.saturating_add(2),
            'ẋ' | 'ẏ' | 'ż' | 'ẍ' | 'ÿ' => {
                let (letter, k) = match c {
                    'ẋ' => ('x', 1),
                    'ẏ' => ('y', 1),
                    'ż' => ('z', 1),
                    'ẍ' => ('x', 2),
                    _ => ('y', 2),
                };
                out.push(letter);
                marks = marks.saturating_add(k);
            }
            _ => match crate::print::ascii_name_of(c) {
                Some(name) => out.push_str(name),
                None => out.push(c),
            },
        }
    }
    (out, marks)
}

fn suggest(name: &str) -> Option<&'static str> {
    let lower = name.to_lowercase();
    KNOWN_FUNCTIONS
        .iter()
        .map(|&k| (edit_distance(&lower, &k.to_lowercase()), k))
        .filter(|&(d, _)| d <= 2 && d < name.chars().count().max(2))
        .min_by_key(|&(d, _)| d)
        .map(|(_, k)| k)
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, &cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

/// Whether `base ^ exp` would compute an exact number too large to hold: the constructors
/// evaluate numeric powers exactly, so `2^10^10` must be refused before it is built.
fn power_too_large(base: Expr, exp: Expr) -> bool {
    let Some(e) = exp.as_number() else {
        return false;
    };
    let Some((p, _)) = e.to_small_ratio() else {
        return false;
    };
    let p = p.unsigned_abs();
    if p <= 64 {
        return false;
    }
    let bits = number_bits(base, 0);
    bits.saturating_mul(p) > MAX_POWER_BITS
}

/// An upper bound on the bits of the exact numbers a power of `e` would multiply out: the
/// largest numeric factor, weighted by the exponent it already carries.
fn number_bits(e: Expr, depth: usize) -> u64 {
    if depth > MAX_DEPTH {
        return u64::MAX;
    }
    match e.node() {
        Node::Number(n) => match n.to_big_ratio() {
            Some((num, den)) => {
                let (a, b) = (num.bits(), den.bits());
                // 0 and ±1 stay small under any power.
                if b == 1 && a <= 1 {
                    0
                } else {
                    a + b
                }
            }
            None => 0,
        },
        Node::Mul(f) => f
            .iter()
            .map(|x| number_bits(*x, depth + 1))
            .max()
            .unwrap_or(0),
        Node::Pow([b, x]) => {
            let inner = number_bits(*b, depth + 1);
            let k = x
                .as_number()
                .and_then(|n| n.to_small_ratio())
                .map_or(1, |(p, _)| p.unsigned_abs().max(1));
            inner.saturating_mul(k)
        }
        _ => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn ctx() -> ParseContext {
        ParseContext::new().with_coordinates(["x", "theta"])
    }

    fn p(s: &str) -> Expr {
        parse(s, &ctx()).unwrap_or_else(|e| panic!("{s}: {}", e.render(s)))
    }

    fn err(s: &str) -> ParseError {
        parse(s, &ctx()).expect_err(s)
    }

    #[test]
    fn names_resolve_by_context_suffix_and_reserved_words() {
        assert_eq!(p("x"), Expr::coordinate("x"));
        assert_eq!(p("theta_d"), Expr::rate("theta", 1));
        assert_eq!(p("phi_ddd"), Expr::rate("phi", 3));
        assert_eq!(p("y"), Expr::symbol("y"));
        assert_eq!(p("t"), Expr::time());
        assert_eq!(p("pi"), Expr::pi());
        assert_eq!(p("E"), Expr::one().exp());
        assert_eq!(p("m_A"), Expr::symbol("m_A"));
        assert_eq!(p("θ̇"), Expr::rate("theta", 1));
        assert_eq!(p("ℓ"), Expr::symbol("l"));
        assert_eq!(p("ẍ"), Expr::rate("x", 2));
        assert_eq!(p("theta(t)"), Expr::coordinate("theta"));
    }

    #[test]
    fn precedence_matches_python() {
        let (x, y) = (Expr::coordinate("x"), Expr::symbol("y"));
        assert_eq!(p("-x^2"), -(x.powi(2)));
        assert_eq!(p("-x**2"), -(x.powi(2)));
        assert_eq!(p("2**3**2"), Expr::int(512));
        assert_eq!(p("x**-1"), x.powi(-1));
        assert_eq!(p("1 - x - y"), Expr::one() - x - y);
        assert_eq!(p("x/2/y"), x / 2 / y);
        assert_eq!(p("(-2)**y"), Expr::int(-2).pow(y));
        assert_eq!(p("Rational(1, 2)*x"), x / 2);
        assert_eq!(p("sqrt(x)"), x.sqrt());
        assert_eq!(p("atan2(y, x)"), Expr::atan2(y, x));
        assert_eq!(p("0.5"), Expr::rational(1, 2).unwrap());
        assert_eq!(p("2E-3"), Expr::rational(1, 500).unwrap());
        assert_eq!(
            p("12345678901234567890123")
                .as_number()
                .map(Number::is_integer),
            Some(true)
        );
    }

    #[test]
    fn errors_point_at_the_column() {
        let e = err("sn(x) + 1");
        assert_eq!((e.column(), e.span()), (1, 0..2));
        assert_eq!(e.help().as_deref(), Some("did you mean `sin`?"));
        assert_eq!(
            e.render("sn(x) + 1"),
            "sn(x) + 1\n^^ unknown function `sn`\nhelp: did you mean `sin`?"
        );

        let e = err("1 + (x * 2");
        assert_eq!(e.kind(), &ParseErrorKind::UnclosedParen);
        assert_eq!(e.column(), 5);

        let e = err("x * ");
        assert_eq!(
            e.to_string(),
            "expected an expression after `*`, found the end of the input at column 5"
        );

        let e = err("2x + 1");
        assert!(matches!(
            e.kind(),
            ParseErrorKind::ImplicitMultiplication { .. }
        ));
        assert_eq!(e.column(), 2);
        assert_eq!(
            e.help().as_deref(),
            Some("multiplication must be written out: `2*x`")
        );

        let e = err("θ + 3 $");
        assert_eq!(e.column(), 7);
        assert_eq!(e.render("θ + 3 $"), "θ + 3 $\n      ^ unexpected character `$`\nhelp: expressions use names, numbers, `+ - * / ^ **`, parentheses and commas");

        assert_eq!(err("x)").kind(), &ParseErrorKind::UnmatchedClose);
        assert_eq!(err("atan2(x)").column(), 1);
        assert!(matches!(
            err("atan2(x)").kind(),
            ParseErrorKind::WrongArity {
                expected: 2,
                found: 1,
                ..
            }
        ));
        assert!(matches!(
            err("sin x").kind(),
            ParseErrorKind::FunctionWithoutCall(_)
        ));
        assert_eq!(err("").kind(), &ParseErrorKind::Empty);
        assert_eq!(err("2**10**10").kind(), &ParseErrorKind::NumberTooLarge);
        assert_eq!(
            err("1e10001").kind(),
            &ParseErrorKind::ExponentTooLarge {
                text: "1e10001".into(),
                limit: 10_000
            }
        );
        assert_eq!(err("2 + 1e-1000000000").column(), 5);
        assert_eq!(
            err(&"(".repeat(1000)).kind(),
            &ParseErrorKind::TooDeep(MAX_DEPTH)
        );
        assert_eq!(
            err(&"-".repeat(1000)).kind(),
            &ParseErrorKind::TooDeep(MAX_DEPTH)
        );
    }

    /// Issue 14: `sin(x)*x_d` read `x` as a constant, so its time derivative lost `cos x ẋ²`.
    #[test]
    fn a_name_with_a_rate_in_the_text_is_a_coordinate() {
        let e = parse("sin(x)*x_d", &ParseContext::new()).unwrap();
        let x = Expr::coordinate("x");
        assert_eq!(e, x.sin() * Expr::rate("x", 1));
        let expected = x.cos() * Expr::rate("x", 1).powi(2) + x.sin() * Expr::rate("x", 2);
        assert!(e.dt().equals(expected));
        assert_eq!(
            parse("ẋ + x", &ParseContext::new()).unwrap(),
            Expr::rate("x", 1) + x
        );
        // Without a rate, a name stays a constant.
        assert_eq!(
            parse("sin(y)", &ParseContext::new()).unwrap(),
            Expr::symbol("y").sin()
        );
    }

    /// Issue 14: a division by zero is an error at the divisor, never a silent 0.
    #[test]
    fn division_by_zero_is_an_error_at_the_divisor() {
        for (text, column) in [
            ("0/0", 3),
            ("(x-x)/(x-x)", 7),
            ("0*(1/0)", 6),
            ("1/0-1/0", 3),
            ("y/(2 - 2)", 3),
            ("1 + 0^-1", 5),
            ("(y - y)**(-2)", 1),
            ("Rational(1, 0)", 1),
            ("x/0.0", 3),
        ] {
            let e = err(text);
            assert_eq!(
                (e.kind(), e.column()),
                (&ParseErrorKind::DivisionByZero, column),
                "{text}"
            );
        }
        // Zero divided by something, and zero to a positive power, are fine.
        assert_eq!(p("0/x"), Expr::zero());
        assert_eq!(p("0^2"), Expr::zero());
    }

    proptest! {
        #![proptest_config(ProptestConfig { failure_persistence: None, ..ProptestConfig::with_cases(256) })]

        #[test]
        fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..64)) {
            let s = String::from_utf8_lossy(&bytes);
            if let Err(e) = parse(&s, &ctx()) {
                let _ = e.render(&s);
            }
        }

        #[test]
        fn random_token_soup_never_panics(parts in proptest::collection::vec(
            prop::sample::select(vec!["x", "theta_dd", "2", "0.5", "1e3", "+", "-", "*", "/", "^", "**",
                "(", ")", ",", "sin", "atan2", "sqrt", "Rational", " ", "θ̇", "E", "pi", "9999999999999999999"]),
            0..40,
        )) {
            let s: String = parts.concat();
            if let Err(e) = parse(&s, &ctx()) {
                let _ = e.render(&s);
                prop_assert!(e.span().start <= s.len());
            }
        }
    }
}
