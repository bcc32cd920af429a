//! The LaTeX rendering: a standalone document, display mathematics broken to the page width,
//! prose escaped.

use std::fmt::Write as _;

use super::{Block, Cell, Document, Equation};

impl Document {
    /// A standalone LaTeX document (`article`, `amsmath`, `graphicx`) that compiles with
    /// `pdflatex`.
    #[must_use]
    pub fn to_latex(&self) -> String {
        let mut out = String::new();
        out.push_str(
            "\\documentclass[11pt]{article}\n\\usepackage[utf8]{inputenc}\n\\usepackage[T1]{fontenc}\n\
             \\usepackage{amsmath,amssymb}\n\\usepackage{graphicx}\n\\usepackage[margin=2cm]{geometry}\n\
             \\allowdisplaybreaks\n\\setlength{\\parindent}{0pt}\n\\setlength{\\parskip}{0.6em}\n\n",
        );
        let _ = writeln!(
            out,
            "\\title{{{}}}\n\\date{{}}\n\n\\begin{{document}}\n\\maketitle\n",
            latex_text(&self.title)
        );
        for s in &self.sections {
            let command = if s.level <= 2 {
                "section"
            } else {
                "subsection"
            };
            let _ = writeln!(out, "\\{command}*{{{}}}\n", latex_text(&s.title));
            for b in &s.blocks {
                match b {
                    Block::Paragraph(p) => {
                        let _ = writeln!(out, "{}\n", latex_text(p));
                    }
                    Block::Remark(p) => {
                        let _ = writeln!(out, "\\textit{{Obs.}} {}\n", latex_text(p));
                    }
                    Block::Equations(lines) => {
                        let _ = writeln!(out, "\\begin{{align*}}");
                        let _ = writeln!(out, "{}", aligned_lines(lines));
                        let _ = writeln!(out, "\\end{{align*}}\n");
                    }
                    Block::Table { header, rows } => {
                        let _ = writeln!(
                            out,
                            "\\begin{{center}}\n\\begin{{tabular}}{{{}}}",
                            "l".repeat(header.len())
                        );
                        let titles: Vec<String> = header.iter().map(|h| latex_text(h)).collect();
                        let _ = writeln!(out, "\\hline\n{} \\\\\n\\hline", titles.join(" & "));
                        for r in rows {
                            let cells: Vec<String> = r
                                .iter()
                                .map(|c| match c {
                                    Cell::Text(t) => latex_text(t),
                                    Cell::Math(m) => format!("${}$", m.latex),
                                })
                                .collect();
                            let _ = writeln!(out, "{} \\\\", cells.join(" & "));
                        }
                        let _ = writeln!(out, "\\hline\n\\end{{tabular}}\n\\end{{center}}\n");
                    }
                    Block::Figure { path, caption } => {
                        let _ = writeln!(
                            out,
                            "\\begin{{figure}}[h]\n\\centering\n\\includegraphics[width=0.9\\textwidth]{{{path}}}\n\\caption*{{{}}}\n\\end{{figure}}\n",
                            latex_text(caption)
                        );
                    }
                }
            }
        }
        out.push_str("\\end{document}\n");
        out
    }
}

/// Glyphs per display line (see [`visible_width`]) before a long right-hand side is broken:
/// the text width of the LaTeX document (2 cm margins) in 10 pt mathematics, with room to spare.
pub(super) const LATEX_LINE: usize = 75;

/// The body of an `aligned`/`align*` display: `lhs &= rhs`, a long `rhs` broken before a
/// `+`/`-` onto continuation lines `&\quad + …`. Top-level signs are tried first; a right-hand
/// side that still does not fit is rewritten so that it can break inside its brackets too
/// ([`breakable_latex`]).
pub(super) fn aligned_lines(lines: &[Equation]) -> String {
    let mut rows = Vec::new();
    for e in lines {
        // A long left-hand side (an equation of motion `… = 0`) is broken like a right-hand
        // side: the whole equation goes right of the alignment point.
        let (head, body) = if visible_width(&e.lhs.latex) > LATEX_LINE / 2 {
            (
                "& ".to_string(),
                format!("{} = {}", e.lhs.latex, e.rhs.latex),
            )
        } else {
            (format!("{} &= ", e.lhs.latex), e.rhs.latex.clone())
        };
        let mut pieces = latex_terms(&body);
        let head_width = visible_width(&head);
        let room = LATEX_LINE - head_width.min(LATEX_LINE / 2);
        let rewritten;
        if pieces.iter().any(|p| visible_width(p) > room) {
            rewritten = breakable_latex(&body);
            pieces = latex_pieces(&rewritten, false);
        }
        let mut current = head;
        let mut width = head_width;
        let mut first = true;
        for term in pieces {
            let term_width = visible_width(term);
            if !first && width + term_width > LATEX_LINE {
                rows.push(current.trim_end().to_string());
                current = String::from("&\\quad ");
                width = 2;
            }
            current.push_str(term.trim_start());
            current.push(' ');
            width += term_width;
            first = false;
        }
        rows.push(current.trim_end().to_string());
    }
    rows.join(" \\\\\n")
}

/// About how many glyph widths LaTeX mathematics takes on the page: a command such as
/// `\theta` is one glyph, accents, brackets' sizes, braces and spaces none, `\cos` three,
/// an operator with its spacing two, and a `\frac` as wide as the wider of its parts.
pub(super) fn visible_width(s: &str) -> usize {
    let mut width = 0;
    let mut rest = s;
    while let Some(ch) = rest.chars().next() {
        if let Some(after) = rest.strip_prefix("\\frac{") {
            if let Some((num, tail)) = braced(after) {
                if let Some((den, tail)) = tail.strip_prefix('{').and_then(braced) {
                    width += visible_width(num).max(visible_width(den));
                    rest = tail;
                    continue;
                }
            }
        }
        if ch == '\\' {
            let name: String = rest[1..]
                .chars()
                .take_while(char::is_ascii_alphabetic)
                .collect();
            width += match name.as_str() {
                "" => 1,
                "left" | "right" | "bigl" | "bigr" | "big" | "dot" | "ddot" | "hat" | "vec"
                | "mathrm" | "text" | "quad" => 0,
                "sin" | "cos" | "tan" | "exp" | "sqrt" => 3,
                "ln" => 2,
                "arcsin" | "arccos" | "arctan" => 6,
                _ => 1,
            };
            // `\name`, or a backslash and one character (`\,`, `\{`, `\\`).
            let skip = if name.is_empty() {
                1 + rest[1..].chars().next().map_or(0, char::len_utf8)
            } else {
                1 + name.len()
            };
            rest = &rest[skip..];
            continue;
        }
        width += match ch {
            '{' | '}' | '^' | '_' | ' ' | '&' => 0,
            '+' | '-' | '=' => 2,
            _ => 1,
        };
        rest = &rest[ch.len_utf8()..];
    }
    width
}

/// Splits LaTeX before the ` + ` and ` - ` outside braces and `\left … \right` pairs.
fn latex_terms(s: &str) -> Vec<&str> {
    latex_pieces(s, true)
}

/// Splits LaTeX before the ` + ` and ` - ` outside braces, and also outside `\left … \right`
/// pairs when `pairs_group` (an `align*` line cannot end inside such a pair; it can inside
/// `\bigl( … \bigr)`).
fn latex_pieces(s: &str, pairs_group: bool) -> Vec<&str> {
    let bytes = s.as_bytes();
    let mut depth = 0i32;
    let mut pieces = Vec::new();
    let mut start = 0;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'{' => depth += 1,
            b'}' => depth -= 1,
            // A line cannot end inside an environment (a matrix) either.
            b'\\' if s[i..].starts_with("\\begin{") => depth += 1,
            b'\\' if s[i..].starts_with("\\end{") => depth -= 1,
            b'\\' if pairs_group && s[i..].starts_with("\\left") => depth += 1,
            b'\\' if pairs_group && s[i..].starts_with("\\right") => depth -= 1,
            b' ' if depth == 0
                && i > start
                && (s[i..].starts_with(" + ") || s[i..].starts_with(" - ")) =>
            {
                pieces.push(&s[start..i]);
                start = i;
            }
            _ => {}
        }
        i += 1;
    }
    pieces.push(&s[start..]);
    pieces
}

/// A fraction whose parts are longer than this is written inline (`\bigl(a + b\bigr) / c`) in
/// a breakable right-hand side.
const INLINE_FRACTION: usize = 40;

/// The same mathematics with line-break opportunities inside brackets: `\left( … \right)`
/// become `\bigl( … \bigr)` (which do not group, so a line may end between them) and long
/// `\frac{a}{b}` become `\bigl(a\bigr) / \bigl(b\bigr)` (a line cannot end inside `\frac`'s
/// braces). Only used for right-hand sides too long for one line.
pub(super) fn breakable_latex(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 16);
    let mut rest = s;
    while !rest.is_empty() {
        if let Some(after) = rest.strip_prefix("\\frac{") {
            if let Some((num, tail)) = braced(after) {
                if let Some((den, tail)) = tail.strip_prefix('{').and_then(braced) {
                    if num.len() + den.len() > INLINE_FRACTION {
                        let num = breakable_latex(num);
                        let den = breakable_latex(den);
                        out.push_str(&inline_operand(&num, true));
                        out.push_str(" / ");
                        out.push_str(&inline_operand(&den, false));
                    } else {
                        let _ = write!(out, "\\frac{{{num}}}{{{den}}}");
                    }
                    rest = tail;
                    continue;
                }
            }
        }
        // Every sized pair, `\left|` of an absolute value too: a line may end inside neither.
        let sized = [("\\left", "\\bigl"), ("\\right", "\\bigr")]
            .into_iter()
            .find_map(|(pair, big)| {
                let after = rest.strip_prefix(pair)?;
                let delimiter = after.chars().next().filter(|c| "()[]|".contains(*c))?;
                Some((big, delimiter, &after[1..]))
            });
        if let Some((big, delimiter, after)) = sized {
            out.push_str(big);
            out.push(delimiter);
            rest = after;
            continue;
        }
        let Some(ch) = rest.chars().next() else { break };
        out.push(ch);
        rest = &rest[ch.len_utf8()..];
    }
    out
}

/// The text up to the brace that closes an already opened `{`, and what follows it.
fn braced(s: &str) -> Option<(&str, &str)> {
    let mut depth = 1;
    for (i, b) in s.bytes().enumerate() {
        match b {
            b'{' => depth += 1,
            b'}' => {
                depth -= 1;
                if depth == 0 {
                    return Some((&s[..i], &s[i + 1..]));
                }
            }
            _ => {}
        }
    }
    None
}

/// An inline fraction's operand, bracketed when it needs to be: a numerator with a `+`/`-`
/// outside braces, a denominator with anything more than one factor.
fn inline_operand(s: &str, numerator: bool) -> String {
    let trimmed = s.trim();
    let needs = if numerator {
        latex_pieces(trimmed, false).len() > 1 || trimmed.starts_with('-')
    } else {
        trimmed.contains(' ')
    };
    if needs {
        format!("\\bigl({trimmed}\\bigr)")
    } else {
        trimmed.to_string()
    }
}

/// Prose for LaTeX: special characters escaped; the Unicode mathematics prose carries (Greek
/// letters, `θ̇`, `x̂`, `−`, `²`) written as inline math, so that `pdflatex` compiles it.
fn latex_text(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut chars = s.chars().peekable();
    while let Some(ch) = chars.next() {
        // A base character followed by a combining accent: `θ̇` → `$\dot{\theta}$`.
        let accent = chars.peek().and_then(|&next| match next {
            '\u{307}' => Some("dot"),
            '\u{308}' => Some("ddot"),
            '\u{302}' => Some("hat"),
            _ => None,
        });
        if let Some(accent) = accent {
            chars.next();
            let base = math_symbol(ch).map_or_else(|| ch.to_string(), str::to_string);
            let _ = write!(out, "$\\{accent}{{{base}}}$");
            continue;
        }
        match ch {
            '\\' => out.push_str("\\textbackslash{}"),
            '&' | '%' | '$' | '#' | '_' | '{' | '}' => {
                out.push('\\');
                out.push(ch);
            }
            '~' => out.push_str("\\textasciitilde{}"),
            '^' => out.push_str("\\textasciicircum{}"),
            '—' => out.push_str("---"),
            '–' => out.push_str("--"),
            c if c.is_ascii() => out.push(c),
            c => match math_symbol(c) {
                Some(m) => {
                    let _ = write!(out, "${m}$");
                }
                // Nothing else is written by the report; a stray character should not stop
                // the document from compiling.
                None => out.push('?'),
            },
        }
    }
    out
}

/// The math-mode spelling of the non-ASCII characters prose may contain.
fn math_symbol(ch: char) -> Option<&'static str> {
    const GREEK: [(char, &str); 41] = [
        ('α', r"\alpha"),
        ('β', r"\beta"),
        ('γ', r"\gamma"),
        ('δ', r"\delta"),
        ('ε', r"\varepsilon"),
        ('ζ', r"\zeta"),
        ('η', r"\eta"),
        ('θ', r"\theta"),
        ('ι', r"\iota"),
        ('κ', r"\kappa"),
        ('λ', r"\lambda"),
        ('μ', r"\mu"),
        ('ν', r"\nu"),
        ('ξ', r"\xi"),
        ('π', r"\pi"),
        ('ρ', r"\rho"),
        ('σ', r"\sigma"),
        ('τ', r"\tau"),
        ('υ', r"\upsilon"),
        ('φ', r"\varphi"),
        ('χ', r"\chi"),
        ('ψ', r"\psi"),
        ('ω', r"\omega"),
        ('Γ', r"\Gamma"),
        ('Δ', r"\Delta"),
        ('Θ', r"\Theta"),
        ('Λ', r"\Lambda"),
        ('Ξ', r"\Xi"),
        ('Π', r"\Pi"),
        ('Σ', r"\Sigma"),
        ('Φ', r"\Phi"),
        ('Ψ', r"\Psi"),
        ('Ω', r"\Omega"),
        ('ℓ', r"\ell"),
        ('∂', r"\partial"),
        ('ϕ', r"\phi"),
        ('ϑ', r"\vartheta"),
        ('∞', r"\infty"),
        ('∑', r"\sum"),
        ('√', r"\surd"),
        ('∇', r"\nabla"),
    ];
    const OTHER: [(char, &str); 14] = [
        ('−', "-"),
        ('×', r"\times"),
        ('·', r"\cdot"),
        ('≤', r"\le"),
        ('≥', r"\ge"),
        ('≠', r"\ne"),
        ('≈', r"\approx"),
        ('→', r"\to"),
        ('²', "^2"),
        ('³', "^3"),
        ('⁴', "^4"),
        ('±', r"\pm"),
        ('°', r"^\circ"),
        ('ᵀ', "^T"),
    ];
    GREEK
        .iter()
        .chain(OTHER.iter())
        .find(|(c, _)| *c == ch)
        .map(|(_, m)| *m)
}
