//! The LaTeX rendering: a standalone document, display mathematics broken to the page width,
//! prose escaped.

use std::fmt::Write as _;

use super::prose::{pieces, Piece};
use super::{Block, Cell, Document, Equation};

impl Document {
    /// A standalone LaTeX document (`article`, Latin Modern in T1, `amsmath`, `graphicx`,
    /// `caption`) that compiles with `pdflatex`.
    #[must_use]
    pub fn to_latex(&self) -> String {
        let mut out = String::new();
        out.push_str(
            "\\documentclass[11pt]{article}\n\\usepackage[utf8]{inputenc}\n\\usepackage[T1]{fontenc}\n\
             \\usepackage{lmodern}\n\\usepackage{amsmath,amssymb}\n\\usepackage{graphicx}\n\\usepackage{caption}\n\
             \\usepackage[margin=2cm]{geometry}\n\
             \\allowdisplaybreaks\n\\setlength{\\parindent}{0pt}\n\\setlength{\\parskip}{0.6em}\n\n",
        );
        let _ = writeln!(
            out,
            "\\title{{{}}}\n\\author{{}}\n\\date{{}}\n\n\\begin{{document}}\n\\maketitle\n",
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
                        let _ = writeln!(out, "{}\n", latex_prose(p));
                    }
                    Block::Remark(p) => {
                        let _ = writeln!(out, "\\textit{{Obs.}} {}\n", latex_prose(p));
                    }
                    Block::List(items) => {
                        let _ = writeln!(out, "\\begin{{itemize}}");
                        for item in items {
                            let _ = writeln!(out, "\\item {}", latex_prose(item));
                        }
                        let _ = writeln!(out, "\\end{{itemize}}\n");
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
                            column_spec(header, rows)
                        );
                        let titles: Vec<String> = header.iter().map(|h| latex_text(h)).collect();
                        let _ = writeln!(out, "\\hline\n{} \\\\\n\\hline", titles.join(" & "));
                        for r in rows {
                            let cells: Vec<String> = r
                                .iter()
                                .map(|c| match c {
                                    Cell::Text(t) => latex_prose(t),
                                    Cell::Math(m) => format!("${}$", m.latex),
                                })
                                .collect();
                            let _ = writeln!(out, "{} \\\\", cells.join(" & "));
                        }
                        let _ = writeln!(out, "\\hline\n\\end{{tabular}}\n\\end{{center}}\n");
                    }
                    Block::Figure {
                        path,
                        caption,
                        width,
                    } => {
                        let _ = writeln!(
                            out,
                            // Not a float: the figure stays in its section, where the text
                            // refers to it.
                            "\\begin{{center}}\n\\includegraphics[width={}\\textwidth]{{{path}}}\n\\captionof*{{figure}}{{{}}}\n\\end{{center}}\n",
                            f64::from(*width) / 100.0,
                            latex_prose(caption)
                        );
                    }
                    Block::Link { path, text } => {
                        let _ = writeln!(
                            out,
                            "{}: \\texttt{{{}}}\n",
                            latex_text(text),
                            latex_text(path)
                        );
                    }
                }
            }
        }
        out.push_str("\\end{document}\n");
        out
    }
}

/// Glyphs of text a table row may hold before its columns wrap.
const TABLE_LINE: usize = 80;

/// The columns of a table: `l` when a row fits the line, else paragraph columns `p{…}` whose
/// widths share the line in proportion to each column's longest cell (a long cell wraps).
fn column_spec(header: &[String], rows: &[Vec<Cell>]) -> String {
    let glyphs = |c: &Cell| match c {
        Cell::Text(t) => t.chars().count(),
        Cell::Math(m) => m.unicode.chars().count(),
    };
    let widths: Vec<usize> = (0..header.len())
        .map(|j| {
            let longest = rows.iter().filter_map(|r| r.get(j)).map(glyphs).max();
            longest.unwrap_or(0).max(header[j].chars().count()).max(1)
        })
        .collect();
    let total: usize = widths.iter().sum();
    if total <= TABLE_LINE {
        return "l".repeat(header.len());
    }
    // The columns' padding (2 × 6 pt each) comes off the line first; no column narrower
    // than its longest word (a glyph of 11 pt text is about 1.25 % of the line).
    let share = 0.95 - 0.025 * header.len() as f64;
    let longest_word = |j: usize| {
        let words = |t: &str| t.split_whitespace().map(|w| w.chars().count()).max();
        let cells = rows
            .iter()
            .filter_map(|r| r.get(j))
            .filter_map(|c| match c {
                Cell::Text(t) => words(t),
                Cell::Math(m) => words(&m.unicode),
            });
        cells.chain(words(&header[j])).max().unwrap_or(1)
    };
    let fractions: Vec<f64> = widths
        .iter()
        .enumerate()
        .map(|(j, &w)| (share * w as f64 / total as f64).max(0.0125 * longest_word(j) as f64))
        .collect();
    let scale = (share / fractions.iter().sum::<f64>()).min(1.0);
    fractions
        .iter()
        .map(|f| format!("p{{{:.3}\\linewidth}}", f * scale))
        .collect()
}

/// Glyphs per display line (see [`visible_width`]) before a long right-hand side is broken:
/// the text width of the LaTeX document (2 cm margins) in 10 pt mathematics, with room to spare.
pub(super) const LATEX_LINE: usize = 72;

/// The body of an `aligned`/`align*` display: `lhs &= rhs`, a long `rhs` broken before a
/// `+`/`-` onto continuation lines `&\quad + …`. Top-level signs are tried first; a right-hand
/// side that still does not fit is rewritten so that it can break inside its brackets too
/// ([`breakable_latex`]).
pub(super) fn aligned_lines(lines: &[Equation]) -> String {
    aligned_lines_to(lines, LATEX_LINE)
}

/// [`aligned_lines`] broken to `line` glyphs (see [`visible_width`]) instead of the LaTeX page's
/// [`LATEX_LINE`]: the Markdown rendering breaks to a book's narrower column.
pub(super) fn aligned_lines_to(lines: &[Equation], line: usize) -> String {
    let mut rows = Vec::new();
    // A long left-hand side (an equation of motion `… = 0`) is broken like a right-hand
    // side: the whole equation goes right of the alignment point — and then every row of
    // the display does, since a left-hand side left of that point would widen them all.
    let long_lhs = lines.iter().any(|e| visible_width(&e.lhs.latex) > line / 2);
    for e in lines {
        let (head, body) = if long_lhs {
            (
                "& ".to_string(),
                format!("{} = {}", e.lhs.latex, e.rhs.latex),
            )
        } else {
            (format!("{} &= ", e.lhs.latex), e.rhs.latex.clone())
        };
        // A chain `a = b` on the right (a matrix and its value) that does not fit goes on
        // rows of its own, each `&= …`.
        let chain = if !long_lhs && visible_width(&head) + visible_width(&body) > line {
            top_level_equals(&body)
        } else {
            vec![body.as_str()]
        };
        for (k, part) in chain.into_iter().enumerate() {
            let head = if k == 0 {
                head.clone()
            } else {
                "&= ".to_string()
            };
            break_row(&mut rows, head, part, line);
        }
    }
    rows.join(" \\\\\n")
}

/// The parts of `body` between its ` = ` signs outside braces and environments.
fn top_level_equals(body: &str) -> Vec<&str> {
    let mut parts = Vec::new();
    let mut depth = 0i32;
    let mut start = 0;
    let bytes = body.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        let rest = &body[i..];
        if rest.starts_with("\\begin{") || rest.starts_with("\\left") {
            depth += 1;
        } else if rest.starts_with("\\end{") || rest.starts_with("\\right") {
            depth -= 1;
        }
        match bytes[i] {
            b'{' => depth += 1,
            b'}' => depth -= 1,
            b' ' if depth == 0 && rest.starts_with(" = ") => {
                parts.push(body[start..i].trim());
                start = i + 3;
                i += 3;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    parts.push(body[start..].trim());
    parts
}

/// One display row `head body`, broken before a `+`/`-` onto continuation rows when wider
/// than `line` glyphs.
fn break_row(rows: &mut Vec<String>, head: String, body: &str, line: usize) {
    let mut pieces = latex_terms(body);
    let head_width = visible_width(&head);
    let room = line - head_width.min(line / 2);
    let rewritten;
    if pieces.iter().any(|p| visible_width(p) > room) {
        rewritten = breakable_latex(body);
        pieces = latex_pieces(&rewritten, false);
    }
    let mut current = head;
    let mut width = head_width;
    let mut first = true;
    for term in pieces {
        let term_width = visible_width(term);
        if !first && width + term_width > line {
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

/// Prose for LaTeX through the prose layer shared with the Markdown writer: its mathematics
/// as inline `$…$`, names in backticks in `\texttt`, the rest by [`latex_text`].
fn latex_prose(s: &str) -> String {
    pieces(s)
        .into_iter()
        .map(|p| match p {
            Piece::Text(t) => latex_text(&t),
            Piece::Math(m) => format!("${m}$"),
            Piece::Code(c) => format!("\\texttt{{{}}}", latex_text(&c)),
        })
        .collect()
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
        // The same, precomposed (`ẋ`, `ŷ`, `Ṙ`): a rate or a unit vector, in mathematics.
        if let Some((base, accent)) = accented_letter(ch) {
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
            '…' => out.push_str("\\ldots{}"),
            c if c.is_ascii() => out.push(c),
            c => match math_symbol(c) {
                Some(m) => {
                    let _ = write!(out, "${m}$");
                }
                // Latin-1 and Latin Extended-A letters (`é`, `ñ`, `ł`): the T1 encoding has
                // them, and `inputenc` reads them as they are.
                None if ('\u{c0}'..='\u{17f}').contains(&c) && c.is_alphabetic() => out.push(c),
                // Nothing else is written by the report; a stray character should not stop
                // the document from compiling.
                None => out.push('?'),
            },
        }
    }
    out
}

/// A precomposed Latin letter with a dot, two dots or a hat above: its base letter and the
/// LaTeX accent (the table is Unicode's canonical decomposition of these letters).
pub(super) fn accented_letter(ch: char) -> Option<(char, &'static str)> {
    const LETTERS: [(char, char, &str); 84] = [
        ('Â', 'A', "hat"),
        ('Ä', 'A', "ddot"),
        ('Ê', 'E', "hat"),
        ('Ë', 'E', "ddot"),
        ('Î', 'I', "hat"),
        ('Ï', 'I', "ddot"),
        ('Ô', 'O', "hat"),
        ('Ö', 'O', "ddot"),
        ('Û', 'U', "hat"),
        ('Ü', 'U', "ddot"),
        ('â', 'a', "hat"),
        ('ä', 'a', "ddot"),
        ('ê', 'e', "hat"),
        ('ë', 'e', "ddot"),
        ('î', 'i', "hat"),
        ('ï', 'i', "ddot"),
        ('ô', 'o', "hat"),
        ('ö', 'o', "ddot"),
        ('û', 'u', "hat"),
        ('ü', 'u', "ddot"),
        ('ÿ', 'y', "ddot"),
        ('Ĉ', 'C', "hat"),
        ('ĉ', 'c', "hat"),
        ('Ċ', 'C', "dot"),
        ('ċ', 'c', "dot"),
        ('Ė', 'E', "dot"),
        ('ė', 'e', "dot"),
        ('Ĝ', 'G', "hat"),
        ('ĝ', 'g', "hat"),
        ('Ġ', 'G', "dot"),
        ('ġ', 'g', "dot"),
        ('Ĥ', 'H', "hat"),
        ('ĥ', 'h', "hat"),
        ('İ', 'I', "dot"),
        ('Ĵ', 'J', "hat"),
        ('ĵ', 'j', "hat"),
        ('Ŝ', 'S', "hat"),
        ('ŝ', 's', "hat"),
        ('Ŵ', 'W', "hat"),
        ('ŵ', 'w', "hat"),
        ('Ŷ', 'Y', "hat"),
        ('ŷ', 'y', "hat"),
        ('Ÿ', 'Y', "ddot"),
        ('Ż', 'Z', "dot"),
        ('ż', 'z', "dot"),
        ('Ȧ', 'A', "dot"),
        ('ȧ', 'a', "dot"),
        ('Ȯ', 'O', "dot"),
        ('ȯ', 'o', "dot"),
        ('Ḃ', 'B', "dot"),
        ('ḃ', 'b', "dot"),
        ('Ḋ', 'D', "dot"),
        ('ḋ', 'd', "dot"),
        ('Ḟ', 'F', "dot"),
        ('ḟ', 'f', "dot"),
        ('Ḣ', 'H', "dot"),
        ('ḣ', 'h', "dot"),
        ('Ḧ', 'H', "ddot"),
        ('ḧ', 'h', "ddot"),
        ('Ṁ', 'M', "dot"),
        ('ṁ', 'm', "dot"),
        ('Ṅ', 'N', "dot"),
        ('ṅ', 'n', "dot"),
        ('Ṗ', 'P', "dot"),
        ('ṗ', 'p', "dot"),
        ('Ṙ', 'R', "dot"),
        ('ṙ', 'r', "dot"),
        ('Ṡ', 'S', "dot"),
        ('ṡ', 's', "dot"),
        ('Ṫ', 'T', "dot"),
        ('ṫ', 't', "dot"),
        ('Ẅ', 'W', "ddot"),
        ('ẅ', 'w', "ddot"),
        ('Ẇ', 'W', "dot"),
        ('ẇ', 'w', "dot"),
        ('Ẋ', 'X', "dot"),
        ('ẋ', 'x', "dot"),
        ('Ẍ', 'X', "ddot"),
        ('ẍ', 'x', "ddot"),
        ('Ẏ', 'Y', "dot"),
        ('ẏ', 'y', "dot"),
        ('Ẑ', 'Z', "hat"),
        ('ẑ', 'z', "hat"),
        ('ẗ', 't', "ddot"),
    ];
    LETTERS
        .iter()
        .find(|(c, _, _)| *c == ch)
        .map(|(_, base, accent)| (*base, *accent))
}

/// The math-mode spelling of the non-ASCII characters prose may contain.
pub(super) fn math_symbol(ch: char) -> Option<&'static str> {
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
    const OTHER: [(char, &str); 34] = [
        ('−', "-"),
        ('ℒ', r"\mathcal{L}"),
        ('½', r"\tfrac{1}{2}"),
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
        ('⁰', "^0"),
        ('¹', "^1"),
        ('⁵', "^5"),
        ('⁶', "^6"),
        ('⁷', "^7"),
        ('⁸', "^8"),
        ('⁹', "^9"),
        ('⁻', "^-"),
        ('₀', "_0"),
        ('₁', "_1"),
        ('₂', "_2"),
        ('₃', "_3"),
        ('₄', "_4"),
        ('₅', "_5"),
        ('₆', "_6"),
        ('₇', "_7"),
        ('₈', "_8"),
        ('₉', "_9"),
    ];
    GREEK
        .iter()
        .chain(OTHER.iter())
        .find(|(c, _)| *c == ch)
        .map(|(_, m)| *m)
}
