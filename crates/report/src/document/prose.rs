//! Prose with mathematics in it, for the Markdown and LaTeX writers alike: the notes, the
//! problem statement and the report's own sentences carry symbols (`m_A`, `θ`, `ω²`, `x̂`,
//! `U = −½ k x² + m_B g ℓ cos θ`), which both writers set as inline mathematics (`$m_A$`,
//! `$\theta$`) — never as text (`m\_A`, a Unicode θ beside MathJax).
//!
//! [`pieces`] cuts a sentence into [`Piece`]s: text, inline mathematics (already in LaTeX) and
//! code (a word in backticks, a model's name). A formula is a run of words that are
//! mathematics — a word with a Greek letter, an accent, a superscript, a minus sign or a
//! subscripted symbol (`m_A`, `Q_θ`) — together with the operators (`=`, `+`, `−`, `≤`), single
//! letters, numbers and function names (`cos`) between them. A lone single letter stays text
//! ("a point A"): English has words of one letter.

use super::latex::{accented_letter, math_symbol};

/// A piece of a sentence.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Piece {
    /// Prose, as written.
    Text(String),
    /// Inline mathematics, in LaTeX (without the `$`).
    Math(String),
    /// A name in backticks, without them.
    Code(String),
}

/// What one word of a sentence is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// Surely mathematics: `m_A`, `θ̇`, `ω²`.
    Math,
    /// An operator between mathematics: `=`, `+`, `−`.
    Operator,
    /// Mathematics only beside other mathematics: `k`, `2`, `cos`.
    Maybe,
    /// Prose.
    Text,
}

/// The sentence `s` cut into text, mathematics and code (see the module documentation).
pub(crate) fn pieces(s: &str) -> Vec<Piece> {
    let words: Vec<&str> = s.split(' ').collect();
    let mut out: Vec<Piece> = Vec::new();
    let mut i = 0;
    while i < words.len() {
        let (lead, core, _) = split_punctuation(words[i]);
        let run_end = run_from(&words, i);
        match run_end {
            Some(end) => {
                push_text(&mut out, lead, i > 0);
                let (_, _, trail) = split_punctuation(words[end]);
                let formula: Vec<&str> = (i..=end)
                    .map(|k| {
                        let (l, _, t) = split_punctuation(words[k]);
                        let start = if k == i { l.len() } else { 0 };
                        let stop = if k == end {
                            words[k].len() - t.len()
                        } else {
                            words[k].len()
                        };
                        &words[k][start..stop]
                    })
                    .collect();
                out.push(Piece::Math(math_latex(&formula.join(" "))));
                push_text(&mut out, trail, false);
                i = end + 1;
            }
            None if core.len() > 2 && core.starts_with('`') && core.ends_with('`') => {
                push_text(&mut out, lead, i > 0);
                out.push(Piece::Code(core[1..core.len() - 1].to_string()));
                let (_, _, trail) = split_punctuation(words[i]);
                push_text(&mut out, trail, false);
                i += 1;
            }
            None => {
                push_text(&mut out, words[i], i > 0);
                i += 1;
            }
        }
    }
    out
}

/// Appends text to the last text piece (a space before it when `space`), or as a new piece.
fn push_text(out: &mut Vec<Piece>, text: &str, space: bool) {
    let text = if space {
        format!(" {text}")
    } else {
        text.to_string()
    };
    if text.is_empty() {
        return;
    }
    if let Some(Piece::Text(last)) = out.last_mut() {
        last.push_str(&text);
    } else {
        out.push(Piece::Text(text));
    }
}

/// The last word of the formula that starts at word `i`, if one does: the run of mathematics,
/// operators and letters from `i` that holds at least one word of surely mathematics, ending
/// at a word followed by punctuation, and neither starting nor ending with an operator.
fn run_from(words: &[&str], i: usize) -> Option<usize> {
    let kind = |k: usize| {
        let (_, core, _) = split_punctuation(words[k]);
        kind_of(core)
    };
    if matches!(kind(i), Kind::Text | Kind::Operator) {
        return None;
    }
    let mut last_good = None;
    let mut has_math = false;
    // Brackets opened inside the formula, which its later words may close.
    let mut depth = 0usize;
    let mut k = i;
    while k < words.len() {
        let (lead, core, trail) = split_punctuation(words[k]);
        let kk = kind(k);
        if kk == Kind::Text || (k > i && !lead.chars().all(|c| c == '(')) {
            break;
        }
        depth += if k > i { lead.len() } else { 0 } + core.matches('(').count();
        depth = depth.saturating_sub(core.matches(')').count());
        has_math |= kk == Kind::Math || is_value_of_symbol(words, k);
        if kk != Kind::Operator && has_math {
            last_good = Some(k);
        }
        // A closing bracket after the word closes one the formula opened: the formula goes on.
        let closes = trail.chars().take_while(|c| *c == ')').count();
        if closes > 0 && closes <= depth && closes == trail.len() {
            depth -= closes;
        } else if !trail.is_empty() {
            break;
        }
        k += 1;
    }
    last_good
}

/// Whether word `k` is the `=` of `x = 0.5`: a symbol of one letter (and digits) given a
/// number, which reads as mathematics like `θ = 0.5` beside it (`t = 3.000000`, a state's
/// `x = 0.030643`), though neither side is surely mathematics by itself.
fn is_value_of_symbol(words: &[&str], k: usize) -> bool {
    let core = |k: usize| words.get(k).map(|w| split_punctuation(w).1);
    core(k) == Some("=")
        && k > 0
        && core(k - 1).is_some_and(is_letter_and_digits)
        && core(k + 1).is_some_and(is_number)
}

/// A word's leading punctuation, its core and its trailing punctuation. Brackets that the core
/// balances stay in it (`(x` opens a bracket the formula closes, so it stays too when the word
/// is a formula's first).
fn split_punctuation(word: &str) -> (&str, &str, &str) {
    let lead_len = word
        .char_indices()
        .find(|(_, c)| !matches!(c, '(' | '[' | '"' | '“' | '‘'))
        .map_or(word.len(), |(k, _)| k);
    let rest = &word[lead_len..];
    let trail_start = rest
        .char_indices()
        .rev()
        .find(|(_, c)| {
            !matches!(
                c,
                ',' | '.' | ';' | ':' | ')' | ']' | '"' | '”' | '’' | '!' | '?'
            )
        })
        .map_or(0, |(k, c)| k + c.len_utf8());
    let (mut core, mut trail) = rest.split_at(trail_start);
    // A closing bracket the core opened belongs to it: `f(x),` keeps `f(x)`.
    let opens = core.matches('(').count();
    let closes = core.matches(')').count();
    if opens > closes && trail.starts_with(')') {
        let (c, t) = rest.split_at(trail_start + 1);
        core = c;
        trail = t;
    }
    (&word[..lead_len], core, trail)
}

fn kind_of(core: &str) -> Kind {
    const OPERATORS: [&str; 13] = [
        "=", "+", "−", "-", "·", "×", "/", "<", ">", "≤", "≥", "≠", "≈",
    ];
    const FUNCTIONS: [&str; 7] = ["cos", "sin", "tan", "exp", "ln", "sqrt", "abs"];
    if core.is_empty() || core.contains('`') {
        return Kind::Text;
    }
    if OPERATORS.contains(&core) {
        return Kind::Operator;
    }
    let bare = core.trim_matches(|c| c == '(' || c == ')');
    // A subscripted symbol anywhere in the word: `abs(C/(m_B`.
    let symbols = bare
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .any(is_subscripted_symbol);
    let mathematical = bare.chars().any(|c| {
        c != '—'
            && (math_symbol(c).is_some()
                || accented_letter(c).is_some()
                || matches!(c, '\u{302}' | '\u{307}' | '\u{308}'))
    });
    if symbols || mathematical {
        return Kind::Math;
    }
    if is_letter_and_digits(bare) || is_number(bare) || FUNCTIONS.contains(&bare) {
        return Kind::Maybe;
    }
    Kind::Text
}

/// `k`, `M0`, `q12`: one Latin letter and at most two digits.
fn is_letter_and_digits(word: &str) -> bool {
    let mut chars = word.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic())
        && word.len() <= 3
        && chars.all(|c| c.is_ascii_digit())
}

/// `2`, `0.5`, `-25.8256`.
fn is_number(word: &str) -> bool {
    let digits = word.trim_start_matches(['-', '−']);
    !digits.is_empty()
        && digits.chars().all(|c| c.is_ascii_digit() || c == '.')
        && digits.chars().next().is_some_and(|c| c.is_ascii_digit())
}

/// `m_A`, `y_B`, `Q_θ`, `I_xx`, `φ_1`: a symbol of one or two letters with a subscript (a
/// model's longer names with an underscore, like `hinge_A`, are names, not symbols).
fn is_subscripted_symbol(word: &str) -> bool {
    let Some((head, tail)) = word.split_once('_') else {
        return false;
    };
    let head_ok = (1..=2).contains(&head.chars().count()) && head.chars().all(char::is_alphabetic);
    let tail_ok = !tail.is_empty() && tail.chars().all(char::is_alphanumeric);
    head_ok && tail_ok
}

/// A formula as prose writes it in Unicode (`m_B g ℓ cos θ`, `ω²`, `Q_θ`), in LaTeX.
fn math_latex(s: &str) -> String {
    let mut out = String::new();
    let chars: Vec<char> = s.chars().collect();
    let mut k = 0;
    while k < chars.len() {
        let ch = chars[k];
        let accent = chars.get(k + 1).and_then(|next| match next {
            '\u{307}' => Some("dot"),
            '\u{308}' => Some("ddot"),
            '\u{302}' => Some("hat"),
            _ => None,
        });
        if let Some(accent) = accent {
            let base = math_symbol(ch).map_or_else(|| ch.to_string(), str::to_string);
            out.push_str(&format!("\\{accent}{{{base}}}"));
            k += 2;
            continue;
        }
        if let Some((base, accent)) = accented_letter(ch) {
            out.push_str(&format!("\\{accent}{{{base}}}"));
            k += 1;
            continue;
        }
        if ch == '_' {
            let start = k + 1;
            let mut end = start;
            while end < chars.len() && chars[end].is_alphanumeric() {
                end += 1;
            }
            let sub: String = chars[start..end].iter().collect();
            if sub.len() == 1 && sub.chars().all(|c| c.is_ascii_alphanumeric()) {
                out.push('_');
                out.push_str(&sub);
            } else {
                out.push_str(&format!("_{{{}}}", math_latex(&sub)));
            }
            k = end;
            continue;
        }
        if ch.is_ascii_alphabetic() {
            let mut end = k;
            while end < chars.len() && chars[end].is_ascii_alphabetic() {
                end += 1;
            }
            let word: String = chars[k..end].iter().collect();
            if ["cos", "sin", "tan", "exp", "ln"].contains(&word.as_str()) {
                out.push('\\');
            }
            out.push_str(&word);
            k = end;
            continue;
        }
        match math_symbol(ch) {
            Some(m) => {
                out.push_str(m);
                // A command followed by a letter needs a space between them.
                if m.starts_with('\\') && chars.get(k + 1).is_some_and(char::is_ascii_alphanumeric)
                {
                    out.push(' ');
                }
            }
            None if matches!(ch, '{' | '}' | '%' | '#' | '&' | '$') => {
                out.push('\\');
                out.push(ch);
            }
            None if ch.is_ascii() => out.push(ch),
            None => out.push('?'),
        }
        k += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn math(s: &str) -> String {
        s.to_string()
    }

    #[test]
    fn symbols_in_prose_are_mathematics() {
        assert_eq!(
            pieces("A cart A of mass m_A slides."),
            vec![
                Piece::Text("A cart A of mass ".into()),
                Piece::Math(math("m_A")),
                Piece::Text(" slides.".into())
            ]
        );
        assert_eq!(
            pieces("the pendulum (U = −½ k x² + m_B g y_B, as in the course)"),
            vec![
                Piece::Text("the pendulum (".into()),
                Piece::Math(math(r"U = -\tfrac{1}{2} k x^2 + m_B g y_B")),
                Piece::Text(", as in the course)".into())
            ]
        );
        assert_eq!(
            pieces("stable for ω² < 2 a g, where θ̇ = 0."),
            vec![
                Piece::Text("stable for ".into()),
                Piece::Math(math(r"\omega^2 < 2 a g")),
                Piece::Text(", where ".into()),
                Piece::Math(math(r"\dot{\theta} = 0")),
                Piece::Text(".".into())
            ]
        );
    }

    #[test]
    fn a_symbol_given_a_number_is_mathematics() {
        assert_eq!(
            pieces("At t = 3.000000: x = 0.030643, θ̇ = −9.600807. Relative error"),
            vec![
                Piece::Text("At ".into()),
                Piece::Math(math("t = 3.000000")),
                Piece::Text(": ".into()),
                Piece::Math(math("x = 0.030643")),
                Piece::Text(", ".into()),
                Piece::Math(math(r"\dot{\theta} = -9.600807")),
                Piece::Text(". Relative error".into())
            ]
        );
        assert_eq!(
            pieces("a point A = the hinge"),
            vec![Piece::Text("a point A = the hinge".into())]
        );
    }

    #[test]
    fn names_and_single_letters_stay_text() {
        assert_eq!(
            pieces("the reaction `mesh` and hinge_A at a point O."),
            vec![
                Piece::Text("the reaction ".into()),
                Piece::Code("mesh".into()),
                Piece::Text(" and hinge_A at a point O.".into())
            ]
        );
        assert_eq!(
            pieces("Q_θ = C, the course's choice."),
            vec![
                Piece::Math(math(r"Q_{\theta} = C")),
                Piece::Text(", the course's choice.".into())
            ]
        );
        assert_eq!(
            pieces("r_B = (x + ℓ sin θ) x̂ + ℓ cos θ ŷ: ŷ points down"),
            vec![
                Piece::Math(math(
                    r"r_B = (x + \ell \sin \theta) \hat{x} + \ell \cos \theta \hat{y}"
                )),
                Piece::Text(": ".into()),
                Piece::Math(math(r"\hat{y}")),
                Piece::Text(" points down".into())
            ]
        );
    }
}
