//! The lexer: model text → [`Token`]s with byte spans, built on `logos`.
//!
//! Line structure matters (one statement per line), so line breaks are tokens. [`lex`] then
//! removes the breaks that do not end a statement: a break after a trailing `\`, and a break
//! inside an open parenthesis, unless the next line starts with a statement keyword (which
//! means a parenthesis was left open by mistake and the error should stay on its own line).

use logos::Logos;

use crate::diagnostic::{Diagnostic, DiagnosticKind};
use crate::span::Span;

/// The kinds of token of the model language.
#[derive(Logos, Clone, Copy, Debug, PartialEq, Eq, Hash)]
// No-break spaces and a byte-order mark are whitespace too: editors insert them unseen.
#[logos(skip r"[ \t\r\f\u{A0}\u{FEFF}]+")]
// A comment runs to the end of its line; greedy is exactly what is meant.
#[logos(skip(r"#[^\n]*", allow_greedy = true))]
pub enum Token {
    /// A line break: the end of a statement.
    #[token("\n")]
    Newline,
    /// A backslash, which continues a statement on the next line.
    #[token("\\")]
    Backslash,
    /// A name: letters, digits (also subscripts: `m₁`), marks and `_`, not starting with a
    /// digit. Keywords are contextual,
    /// so they lex as names too.
    #[regex(r"[\p{Alphabetic}_][\p{Alphabetic}\p{N}\p{M}_]*")]
    Name,
    /// A number: `3`, `0.5`, `.5`, `2.`, `1e-8`, `6.02E23`.
    #[regex(r"([0-9]+(\.[0-9]*)?|\.[0-9]+)([eE][+-]?[0-9]+)?")]
    Number,
    /// `+`
    #[token("+")]
    Plus,
    /// `-`
    #[token("-")]
    Minus,
    /// `*`
    #[token("*")]
    Star,
    /// `/`
    #[token("/")]
    Slash,
    /// `^` or `**`: power.
    #[token("^")]
    #[token("**")]
    Caret,
    /// `(`
    #[token("(")]
    LParen,
    /// `)`
    #[token(")")]
    RParen,
    /// `,`
    #[token(",")]
    Comma,
    /// `=`
    #[token("=")]
    Equals,
    /// `:`
    #[token(":")]
    Colon,
    /// `.`: a frame's unit vector, `N.x`.
    #[token(".")]
    Dot,
    /// `'`: the rate of a coordinate, `theta'`.
    #[token("'")]
    Prime,
    /// Prose in double quotes on one line, for `title`, `problem` and `note`: `"A cart"`.
    #[regex(r#""[^"\n]*""#)]
    Text,
    /// A `"` whose line ends before its closing quote (reported, then read as [`Token::Text`]).
    #[regex(r#""[^"\n]*"#)]
    UnclosedText,
    /// The end of the input (added by [`lex`], never produced by `logos`).
    Eof,
}

impl Token {
    /// How the token is named in "expected …, found …" messages.
    #[must_use]
    pub fn describe(self) -> &'static str {
        match self {
            Token::Newline => "end of line",
            Token::Backslash => "`\\`",
            Token::Name => "a name",
            Token::Number => "a number",
            Token::Plus => "`+`",
            Token::Minus => "`-`",
            Token::Star => "`*`",
            Token::Slash => "`/`",
            Token::Caret => "`^`",
            Token::LParen => "`(`",
            Token::RParen => "`)`",
            Token::Comma => "`,`",
            Token::Equals => "`=`",
            Token::Colon => "`:`",
            Token::Dot => "`.`",
            Token::Prime => "`'`",
            Token::Text | Token::UnclosedText => "a text in double quotes",
            Token::Eof => "end of file",
        }
    }
}

/// One token and where it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Spanned {
    /// The kind of token.
    pub token: Token,
    /// Its bytes in the source.
    pub span: Span,
}

/// Words that start a statement. A line that starts with one of them is a new statement even
/// if the previous line left a parenthesis open.
pub(crate) const STATEMENT_KEYWORDS: &[&str] = &[
    "coordinate",
    "coordinates",
    "parameter",
    "parameters",
    "input",
    "inputs",
    "constant",
    "constants",
    "driven",
    "frame",
    "point",
    "particle",
    "body",
    "gravity",
    "spring",
    "damper",
    "dissipation",
    "potential",
    "force",
    "couple",
    "generalized",
    "constraint",
    "reaction",
    "reactions",
    "initial",
    "simulate",
    "output",
    "outputs",
    "title",
    "problem",
    "note",
];

/// Split `source` into tokens, ending with one [`Token::Eof`]. Characters that are not part of
/// the language become diagnostics (one per run of bad characters) and are skipped.
#[must_use]
pub fn lex(source: &str) -> (Vec<Spanned>, Vec<Diagnostic>) {
    let mut raw = Vec::new();
    let mut diagnostics: Vec<Diagnostic> = Vec::new();
    let mut lexer = Token::lexer(source);
    while let Some(result) = lexer.next() {
        let span = Span::from(lexer.span());
        match result {
            Ok(Token::UnclosedText) => {
                diagnostics.push(
                    Diagnostic::new(DiagnosticKind::UnclosedText, span)
                        .with_help("Close the text with `\"` on the same line; continue a long text on the next line with `\\` and another `\"…\"`."),
                );
                raw.push(Spanned {
                    token: Token::Text,
                    span,
                });
            }
            Ok(token) => raw.push(Spanned { token, span }),
            Err(()) => {
                // Merge adjacent bad characters into one diagnostic.
                if let Some(last) = diagnostics.last_mut() {
                    if last.span.end == span.start
                        && matches!(last.kind, DiagnosticKind::InvalidCharacter { .. })
                    {
                        last.span = last.span.to(span);
                        last.kind = DiagnosticKind::InvalidCharacter {
                            text: source.get(last.span.range()).unwrap_or("").to_string(),
                        };
                        continue;
                    }
                }
                let text = source.get(span.range()).unwrap_or("").to_string();
                let help = confusable_help(&text);
                diagnostics.push(
                    Diagnostic::new(DiagnosticKind::InvalidCharacter { text }, span)
                        .with_help(help),
                );
            }
        }
    }
    (join_lines(source, &raw), diagnostics)
}

/// How to mend a character that is not part of the language, for the usual look-alikes of
/// typeset mathematics.
fn confusable_help(text: &str) -> &'static str {
    match text.chars().next() {
        Some('’' | '‘' | '′' | '`') => "Write a rate with the ASCII apostrophe: `theta'`.",
        Some('×' | '·' | '⋅' | '∙') => "Multiply with `*`.",
        Some('−' | '–' | '—') => "Write minus as the ASCII `-`.",
        Some('²' | '³') => "Write powers with `^`: `x^2`.",
        Some('÷') => "Divide with `/`.",
        Some(';') => "Write one statement per line; `;` does not separate statements.",
        Some('[' | ']' | '{' | '}') => "Group with parentheses `( )`.",
        _ => "Remove it. (Comments start with `#`.)",
    }
}

/// Drop the line breaks that continue a statement (see the module doc) and the `\` before them.
fn join_lines(source: &str, raw: &[Spanned]) -> Vec<Spanned> {
    let mut tokens = Vec::with_capacity(raw.len() + 1);
    let mut depth = 0usize;
    let mut index = 0;
    while let Some(&current) = raw.get(index) {
        index += 1;
        match current.token {
            Token::LParen => depth += 1,
            Token::RParen => depth = depth.saturating_sub(1),
            // `\` + line break: skip both.
            Token::Backslash if raw.get(index).map(|next| next.token) == Some(Token::Newline) => {
                index += 1;
                continue;
            }
            Token::Newline if depth > 0 => {
                let starts_statement = raw.get(index).is_some_and(|next| {
                    next.token == Token::Name
                        && STATEMENT_KEYWORDS.contains(&source.get(next.span.range()).unwrap_or(""))
                });
                if starts_statement {
                    depth = 0;
                } else {
                    continue;
                }
            }
            _ => {}
        }
        tokens.push(current);
    }
    let end = source.len();
    tokens.push(Spanned {
        token: Token::Newline,
        span: Span::new(end, end),
    });
    tokens.push(Spanned {
        token: Token::Eof,
        span: Span::new(end, end),
    });
    tokens
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(source: &str) -> Vec<Token> {
        let (tokens, diagnostics) = lex(source);
        assert!(diagnostics.is_empty(), "{diagnostics:?}");
        tokens.into_iter().map(|t| t.token).collect()
    }

    #[test]
    fn numbers_names_and_operators() {
        use Token::*;
        assert_eq!(
            kinds("x = 1.5e-3*N.x ** 2 # comment"),
            vec![Name, Equals, Number, Star, Name, Dot, Name, Caret, Number, Newline, Eof]
        );
        assert_eq!(kinds("θ' .5"), vec![Name, Prime, Number, Newline, Eof]);
    }

    #[test]
    fn continuation_lines_are_joined() {
        use Token::*;
        assert_eq!(kinds("a \\\n b"), vec![Name, Name, Newline, Eof]);
        assert_eq!(
            kinds("f(a,\n b)\nc"),
            vec![Name, LParen, Name, Comma, Name, RParen, Newline, Name, Newline, Eof]
        );
        // An unclosed parenthesis does not swallow the next statement.
        assert_eq!(
            kinds("f(a\npoint"),
            vec![Name, LParen, Name, Newline, Name, Newline, Eof]
        );
    }

    #[test]
    fn typeset_look_alikes_get_a_hint() {
        let (_, diagnostics) = lex("x’ × 2 − y");
        let helps: Vec<&str> = diagnostics
            .iter()
            .filter_map(|d| d.help.as_deref())
            .collect();
        assert_eq!(helps.len(), 3);
        assert!(
            helps[0].contains("apostrophe") && helps[1].contains('*') && helps[2].contains("minus")
        );
        // Invisible spaces are spaces.
        assert!(lex("\u{FEFF}x\u{A0}= 1").1.is_empty());
    }

    #[test]
    fn texts_are_one_token_and_an_unclosed_one_is_reported() {
        use Token::*;
        assert_eq!(
            kinds("title \"A cart # not a comment\" # a comment"),
            vec![Name, Text, Newline, Eof]
        );
        assert_eq!(
            kinds("note \"a\" \\\n  \"b\""),
            vec![Name, Text, Text, Newline, Eof]
        );
        let (tokens, diagnostics) = lex("note \"open\nx");
        assert_eq!(diagnostics.len(), 1);
        assert_eq!(diagnostics[0].kind.code(), "E010");
        assert_eq!(tokens[1].token, Text);
        assert_eq!(tokens[2].token, Newline);
    }

    #[test]
    fn bad_characters_are_reported_once_per_run() {
        let (_, diagnostics) = lex("x = 1 $$$ 2 @");
        assert_eq!(diagnostics.len(), 2);
        assert_eq!(diagnostics[0].span, Span::new(6, 9));
    }
}
