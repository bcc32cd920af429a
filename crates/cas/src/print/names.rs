//! How symbol names look in each dialect: Greek names become letters (`theta` → `θ`,
//! `\theta`), `l` becomes `ℓ`, trailing digits and `_` subscripts become subscripts, and rates
//! get their dots (`θ̇`, `\dot{\theta}`).

use crate::expr::{Symbol, SymbolKind};

/// ASCII names and their Unicode letters and LaTeX commands.
const GREEK: &[(&str, char, &str)] = &[
    ("alpha", 'α', r"\alpha"),
    ("beta", 'β', r"\beta"),
    ("gamma", 'γ', r"\gamma"),
    ("delta", 'δ', r"\delta"),
    ("epsilon", 'ε', r"\epsilon"),
    ("varepsilon", 'ε', r"\varepsilon"),
    ("zeta", 'ζ', r"\zeta"),
    ("eta", 'η', r"\eta"),
    ("theta", 'θ', r"\theta"),
    ("vartheta", 'ϑ', r"\vartheta"),
    ("iota", 'ι', r"\iota"),
    ("kappa", 'κ', r"\kappa"),
    ("lambda", 'λ', r"\lambda"),
    ("mu", 'μ', r"\mu"),
    ("nu", 'ν', r"\nu"),
    ("xi", 'ξ', r"\xi"),
    ("pi", 'π', r"\pi"),
    ("rho", 'ρ', r"\rho"),
    ("sigma", 'σ', r"\sigma"),
    ("tau", 'τ', r"\tau"),
    ("upsilon", 'υ', r"\upsilon"),
    ("phi", 'φ', r"\varphi"),
    ("varphi", 'φ', r"\varphi"),
    ("chi", 'χ', r"\chi"),
    ("psi", 'ψ', r"\psi"),
    ("omega", 'ω', r"\omega"),
    ("Gamma", 'Γ', r"\Gamma"),
    ("Delta", 'Δ', r"\Delta"),
    ("Theta", 'Θ', r"\Theta"),
    ("Lambda", 'Λ', r"\Lambda"),
    ("Xi", 'Ξ', r"\Xi"),
    ("Pi", 'Π', r"\Pi"),
    ("Sigma", 'Σ', r"\Sigma"),
    ("Phi", 'Φ', r"\Phi"),
    ("Psi", 'Ψ', r"\Psi"),
    ("Omega", 'Ω', r"\Omega"),
    ("l", 'ℓ', r"\ell"),
];

/// The ASCII name of a Unicode letter the printer writes (`θ` → `theta`, `ℓ` → `l`), so the
/// parser can read Unicode output back.
pub(crate) fn ascii_name_of(c: char) -> Option<&'static str> {
    // The first entry for a letter wins: `φ` reads as `phi`, `ε` as `epsilon`.
    GREEK.iter().find(|(_, u, _)| *u == c).map(|(n, _, _)| *n)
}

fn greek(name: &str) -> Option<(char, &'static str)> {
    GREEK
        .iter()
        .find(|(n, _, _)| *n == name)
        .map(|(_, u, t)| (*u, *t))
}

/// Whether a name is spelled as a Greek letter (used to order Latin coordinates first).
pub(super) fn is_greek(name: &str) -> bool {
    let (letters, _, _) = split(name);
    letters != "l" && greek(letters).is_some()
}

/// `theta1` → (`theta`, `1`, ``); `m_A` → (`m`, ``, `A`); `theta_12` → (`theta`, ``, `12`).
fn split(name: &str) -> (&str, &str, &str) {
    let (head, sub) = match name.split_once('_') {
        Some((h, s)) if !h.is_empty() => (h, s),
        _ => (name, ""),
    };
    let letters = head.trim_end_matches(|c: char| c.is_ascii_digit());
    if letters.is_empty() {
        return (head, "", sub);
    }
    (letters, &head[letters.len()..], sub)
}

/// The symbol in Unicode: `θ̇1`, `ẍ`, `m_A`, `ℓ`.
pub(super) fn unicode(s: Symbol) -> String {
    let name = s.name();
    if s.kind() == SymbolKind::Time {
        return name.to_owned();
    }
    let (letters, digits, sub) = split(name);
    let mut out = String::new();
    match greek(letters) {
        Some((c, _)) => out.push(c),
        None => out.push_str(letters),
    }
    // Fonts draw the precomposed `ẋ ẍ ẏ ÿ ż` better than a letter with a combining dot.
    let precomposed = match (letters, s.order()) {
        ("x", 1) => Some('ẋ'),
        ("x", 2) => Some('ẍ'),
        ("y", 1) => Some('ẏ'),
        ("y", 2) => Some('ÿ'),
        ("z", 1) => Some('ż'),
        _ => None,
    };
    if let Some(c) = precomposed {
        out.clear();
        out.push(c);
    }
    // A dot over the last of several Latin letters (`tḣ1`) reads as a dot over that letter
    // alone: a multi-letter name takes primes after its digits instead, as the model language
    // writes rates (`th1'`, `th1''`).
    let primes = greek(letters).is_none() && letters.chars().count() > 1;
    match s.order() {
        _ if precomposed.is_some() => {}
        k if primes => {
            out.push_str(digits);
            out.push_str(&"'".repeat(usize::from(k)));
            return finish_subscript(out, sub);
        }
        0 => {}
        // Combining dots above: one, two, three, four.
        1 => out.push('\u{307}'),
        2 => out.push('\u{308}'),
        3 => out.push('\u{20db}'),
        4 => out.push('\u{20dc}'),
        k => {
            out.push('⁽');
            out.push_str(&superscript(&k.to_string()));
            out.push('⁾');
        }
    }
    out.push_str(digits);
    finish_subscript(out, sub)
}

/// Appends `_sub` (a Greek subscript as its letter: `m_α`).
fn finish_subscript(mut out: String, sub: &str) -> String {
    if !sub.is_empty() {
        out.push('_');
        let (sl, sd, ss) = split(sub);
        match greek(sl) {
            Some((c, _)) if ss.is_empty() => {
                out.push(c);
                out.push_str(sd);
            }
            _ => out.push_str(sub),
        }
    }
    out
}

/// The symbol in LaTeX: `\dot{\theta}_1`, `\ddot{x}`, `m_A`, `m_{AB}`, `\ell`.
pub(super) fn latex(s: Symbol) -> String {
    let name = s.name();
    if s.kind() == SymbolKind::Time {
        return name.to_owned();
    }
    let (letters, digits, sub) = split(name);
    let base = match greek(letters) {
        Some((_, t)) => t.to_owned(),
        None if letters.chars().count() > 1 => format!(r"\mathrm{{{}}}", escape(letters)),
        None => escape(letters),
    };
    let mut out = match s.order() {
        0 => base,
        1 => format!(r"\dot{{{base}}}"),
        2 => format!(r"\ddot{{{base}}}"),
        3 => format!(r"\dddot{{{base}}}"),
        4 => format!(r"\ddddot{{{base}}}"),
        k => format!("{base}^{{({k})}}"),
    };
    let subscript = match (digits.is_empty(), sub.is_empty()) {
        (true, true) => String::new(),
        (false, true) => digits.to_owned(),
        (true, false) => latex_sub(sub),
        (false, false) => format!("{digits},{}", latex_sub(sub)),
    };
    match subscript.chars().count() {
        0 => {}
        1 => {
            out.push('_');
            out.push_str(&subscript);
        }
        _ => {
            out.push_str("_{");
            out.push_str(&subscript);
            out.push('}');
        }
    }
    out
}

fn latex_sub(sub: &str) -> String {
    let (l, d, s) = split(sub);
    match greek(l) {
        Some((_, t)) if s.is_empty() => format!("{t}{d}"),
        _ => escape(sub),
    }
}

/// Escapes the characters LaTeX treats specially in a name.
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '_' | '&' | '%' | '$' | '#' | '{' | '}' => {
                out.push('\\');
                out.push(c);
            }
            _ => out.push(c),
        }
    }
    out
}

/// Digits and a minus sign as superscripts (`-12` → `⁻¹²`).
pub(super) fn superscript(s: &str) -> String {
    s.chars()
        .map(|c| match c {
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            '9' => '⁹',
            '-' => '⁻',
            c => c,
        })
        .collect()
}
