//! A solution as a document — sections of prose, aligned equations, tables, figures and
//! remarks — and its renderings: the terminal (Unicode, 80 columns), MyST Markdown (math in
//! `$$…$$`, ready for a Jupyter Book like the seed's) and a standalone LaTeX document.
//!
//! The mechanics fills a [`Document`]; the renderers know nothing about mechanics. Every piece
//! of mathematics is carried in both notations ([`Math`]), printed by the symbolic core, so the
//! three renderings say the same thing.

use std::fmt::Write as _;

use cas::print::{to_latex, to_unicode};
use cas::Expr;

/// How a report writes the system's expressions: the model's named constants folded back in
/// (`m g b sin θ`, not `m g d cos² α sin θ`) and a time-independent denominator spread over
/// the terms (`(I1 + I2 r²) φ̈1`, not one fraction over `R2²`); see
/// [`cas::print::spread_and_fold`]. The value is never changed.
#[derive(Clone, Debug, Default)]
pub struct Notation {
    names: Vec<(Expr, Expr)>,
}

impl Notation {
    /// The notation of a system: its named constants.
    #[must_use]
    pub fn of(system: &mechanics::System) -> Notation {
        Notation {
            names: system
                .constants()
                .iter()
                .map(|(name, value)| (Expr::symbol(name), *value))
                .collect(),
        }
    }

    /// The expression as people read it in this notation.
    #[must_use]
    pub fn shape(&self, e: Expr) -> Expr {
        cas::print::spread_and_fold(e, &self.names)
    }

    /// [`Math::expr`] of the shaped expression.
    #[must_use]
    pub fn math(&self, e: Expr) -> Math {
        Math::expr(self.shape(e))
    }

    /// [`Math::vector`] of the shaped components.
    #[must_use]
    pub fn vector(&self, components: &[Expr; 3]) -> Math {
        Math::vector(&components.map(|c| self.shape(c)))
    }
}

/// A piece of mathematics in the two notations people read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Math {
    /// For terminals: `θ̇`, `ℓ`, `cos(θ1 − θ2)`.
    pub unicode: String,
    /// For Markdown and LaTeX: `\dot{\theta}`, `\ell`.
    pub latex: String,
}

impl Math {
    /// An expression, in the compact form people read.
    #[must_use]
    pub fn expr(e: Expr) -> Math {
        Math {
            unicode: to_unicode(e),
            latex: to_latex(e),
        }
    }

    /// A symbol or label written by hand in both notations.
    #[must_use]
    pub fn label(unicode: impl Into<String>, latex: impl Into<String>) -> Math {
        Math {
            unicode: unicode.into(),
            latex: latex.into(),
        }
    }

    /// A vector from its inertial components, as the seed writes it: `a x̂ + b ŷ + c ẑ`.
    #[must_use]
    pub fn vector(components: &[Expr; 3]) -> Math {
        const UNITS: [(&str, &str); 3] = [("x̂", r"\hat{x}"), ("ŷ", r"\hat{y}"), ("ẑ", r"\hat{z}")];
        let mut unicode = String::new();
        let mut latex = String::new();
        for (c, (u, l)) in components.iter().zip(UNITS) {
            if c.is_literal_zero() {
                continue;
            }
            let negative = to_unicode(*c).starts_with('−');
            let magnitude = if negative { -*c } else { *c };
            let (mut cu, mut cl) = (to_unicode(magnitude), to_latex(magnitude));
            if top_level_terms(&cu).len() > 1 {
                cu = format!("({cu})");
                cl = format!(r"\left({cl}\right)");
            }
            push_sign(&mut unicode, &mut latex, negative);
            if cu != "1" {
                unicode.push_str(&cu);
                unicode.push(' ');
                latex.push_str(&cl);
                latex.push(' ');
            }
            unicode.push_str(u);
            latex.push_str(l);
        }
        if unicode.is_empty() {
            return Math::label("0", r"\vec{0}");
        }
        Math { unicode, latex }
    }
}

/// Appends the sign of the next term of a sum written out by hand: a leading `−` for a
/// negative first term, ` + ` or ` − ` between terms.
pub(crate) fn push_sign(unicode: &mut String, latex: &mut String, negative: bool) {
    match (unicode.is_empty(), negative) {
        (true, true) => {
            unicode.push('−');
            latex.push('-');
        }
        (true, false) => {}
        (false, true) => {
            unicode.push_str(" − ");
            latex.push_str(" - ");
        }
        (false, false) => {
            unicode.push_str(" + ");
            latex.push_str(" + ");
        }
    }
}

/// One line of an aligned display: `lhs = rhs`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Equation {
    /// The left-hand side.
    pub lhs: Math,
    /// The right-hand side.
    pub rhs: Math,
}

impl Equation {
    /// `lhs = rhs`.
    #[must_use]
    pub fn new(lhs: Math, rhs: Math) -> Equation {
        Equation { lhs, rhs }
    }
}

/// A table cell: prose or mathematics.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Cell {
    /// Plain text.
    Text(String),
    /// Mathematics.
    Math(Math),
}

/// The pieces a section is made of.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Block {
    /// A paragraph of prose.
    Paragraph(String),
    /// Aligned equations, one per line.
    Equations(Vec<Equation>),
    /// A table with a header row.
    Table {
        /// Column titles.
        header: Vec<String>,
        /// Rows of cells.
        rows: Vec<Vec<Cell>>,
    },
    /// A figure written beside the document.
    Figure {
        /// The file name, relative to the document.
        path: String,
        /// What it shows.
        caption: String,
    },
    /// A remark worth noticing, like the seed's *Obs.*
    Remark(String),
}

/// A titled section.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Section {
    /// Its title.
    pub title: String,
    /// 2 for a section, 3 for a subsection.
    pub level: u8,
    /// What it says, in order.
    pub blocks: Vec<Block>,
}

impl Section {
    /// An empty section.
    #[must_use]
    pub fn new(title: impl Into<String>, level: u8) -> Section {
        Section {
            title: title.into(),
            level,
            blocks: Vec::new(),
        }
    }

    /// Adds a paragraph.
    pub fn paragraph(&mut self, text: impl Into<String>) -> &mut Section {
        self.blocks.push(Block::Paragraph(text.into()));
        self
    }

    /// Adds a display of equations (nothing when `lines` is empty).
    pub fn equations(&mut self, lines: Vec<Equation>) -> &mut Section {
        if !lines.is_empty() {
            self.blocks.push(Block::Equations(lines));
        }
        self
    }

    /// Adds a remark.
    pub fn remark(&mut self, text: impl Into<String>) -> &mut Section {
        self.blocks.push(Block::Remark(text.into()));
        self
    }
}

/// A whole solution.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Document {
    /// The title.
    pub title: String,
    /// The sections, in order.
    pub sections: Vec<Section>,
}

/// Terminal width the text rendering wraps long equations to.
const COLUMNS: usize = 80;

impl Document {
    /// For the terminal: Unicode mathematics, long equations broken at top-level `+`/`−`.
    #[must_use]
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        let title = wrap_words(&self.title, COLUMNS, "");
        let width = title.lines().map(|l| l.chars().count()).max().unwrap_or(0);
        let _ = writeln!(out, "{title}");
        let _ = writeln!(out, "{}", "═".repeat(width));
        for s in &self.sections {
            out.push('\n');
            let rule = if s.level <= 2 { '─' } else { '·' };
            let _ = writeln!(out, "{}", s.title);
            let _ = writeln!(out, "{}", rule.to_string().repeat(s.title.chars().count()));
            for b in &s.blocks {
                match b {
                    Block::Paragraph(p) => {
                        let _ = writeln!(out, "{}", wrap_words(p, COLUMNS, ""));
                    }
                    Block::Remark(p) => {
                        let _ =
                            writeln!(out, "{}", wrap_words(&format!("Obs. {p}"), COLUMNS, "  "));
                    }
                    Block::Equations(lines) => {
                        for e in lines {
                            let _ =
                                writeln!(out, "{}", wrap_equation(&e.lhs.unicode, &e.rhs.unicode));
                        }
                    }
                    Block::Table { header, rows } => {
                        out.push_str(&text_table(header, rows));
                    }
                    Block::Figure { path, caption } => {
                        let _ = writeln!(out, "  [figure: {caption} — {path}]");
                    }
                }
                out.push('\n');
            }
        }
        out
    }

    /// MyST Markdown: headings, `$$` display math with `aligned`, pipe tables, `{note}`
    /// admonitions for remarks, figures as images beside the file.
    #[must_use]
    pub fn to_markdown(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "# {}\n", self.title);
        for s in &self.sections {
            let _ = writeln!(out, "{} {}\n", "#".repeat(usize::from(s.level)), s.title);
            for b in &s.blocks {
                match b {
                    Block::Paragraph(p) => {
                        let _ = writeln!(out, "{p}\n");
                    }
                    Block::Remark(p) => {
                        let _ = writeln!(out, "```{{note}}\n{p}\n```\n");
                    }
                    Block::Equations(lines) => {
                        let _ = writeln!(out, "$$\n\\begin{{aligned}}");
                        let _ = writeln!(out, "{}", aligned_lines(lines));
                        let _ = writeln!(out, "\\end{{aligned}}\n$$\n");
                    }
                    Block::Table { header, rows } => {
                        let _ = writeln!(out, "| {} |", header.join(" | "));
                        let _ = writeln!(out, "|{}", "---|".repeat(header.len()));
                        for r in rows {
                            let cells: Vec<String> = r.iter().map(markdown_cell).collect();
                            let _ = writeln!(out, "| {} |", cells.join(" | "));
                        }
                        out.push('\n');
                    }
                    Block::Figure { path, caption } => {
                        let _ = writeln!(out, "```{{figure}} {path}\n{caption}\n```\n");
                    }
                }
            }
        }
        out
    }

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

impl Document {
    /// The document as JSON: `{title, sections: [{title, level, blocks}]}`, each block tagged
    /// by `kind` with its mathematics in both notations.
    #[must_use]
    pub fn to_json(&self) -> serde_json::Value {
        use serde_json::json;
        let math = |m: &Math| json!({ "unicode": m.unicode, "latex": m.latex });
        let sections: Vec<serde_json::Value> = self
            .sections
            .iter()
            .map(|s| {
                let blocks: Vec<serde_json::Value> = s
                    .blocks
                    .iter()
                    .map(|b| match b {
                        Block::Paragraph(p) => json!({ "kind": "paragraph", "text": p }),
                        Block::Remark(p) => json!({ "kind": "remark", "text": p }),
                        Block::Equations(lines) => json!({
                            "kind": "equations",
                            "lines": lines.iter().map(|e| json!({ "lhs": math(&e.lhs), "rhs": math(&e.rhs) })).collect::<Vec<_>>(),
                        }),
                        Block::Table { header, rows } => json!({
                            "kind": "table",
                            "header": header,
                            "rows": rows.iter().map(|r| r.iter().map(|c| match c {
                                Cell::Text(t) => json!(t),
                                Cell::Math(m) => math(m),
                            }).collect::<Vec<_>>()).collect::<Vec<_>>(),
                        }),
                        Block::Figure { path, caption } => json!({ "kind": "figure", "path": path, "caption": caption }),
                    })
                    .collect();
                json!({ "title": s.title, "level": s.level, "blocks": blocks })
            })
            .collect();
        json!({ "title": self.title, "sections": sections })
    }
}

/// Glyphs per display line (see [`visible_width`]) before a long right-hand side is broken:
/// the text width of the LaTeX document (2 cm margins) in 10 pt mathematics, with room to spare.
const LATEX_LINE: usize = 75;

/// The body of an `aligned`/`align*` display: `lhs &= rhs`, a long `rhs` broken before a
/// `+`/`-` onto continuation lines `&\quad + …`. Top-level signs are tried first; a right-hand
/// side that still does not fit is rewritten so that it can break inside its brackets too
/// ([`breakable_latex`]).
fn aligned_lines(lines: &[Equation]) -> String {
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
fn visible_width(s: &str) -> usize {
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
fn breakable_latex(s: &str) -> String {
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

fn markdown_cell(c: &Cell) -> String {
    match c {
        Cell::Text(t) => t.replace('|', "\\|"),
        Cell::Math(m) => format!("${}$", m.latex.replace('|', "\\vert ")),
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

/// Words wrapped to `width` columns; continuation lines start with `indent`.
fn wrap_words(text: &str, width: usize, indent: &str) -> String {
    let mut out = String::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > width {
            out.push_str(&line);
            out.push('\n');
            line = indent.to_string();
        } else if !line.is_empty() && line != indent {
            line.push(' ');
        }
        line.push_str(word);
    }
    out.push_str(&line);
    out
}

/// `  lhs = rhs`, broken before the ` + ` / ` − ` nearest the top level when longer than the
/// terminal: outside parentheses first, then one level in, and so on.
fn wrap_equation(lhs: &str, rhs: &str) -> String {
    let head = format!("  {lhs} = ");
    let full = format!("{head}{rhs}");
    if full.chars().count() <= COLUMNS {
        return full;
    }
    // A long left-hand side (`… = 0`, `… = F`) is broken like the right-hand side.
    let (head, rhs, indent) = if head.chars().count() > 24 {
        ("  ".to_string(), format!("{lhs} = {rhs}"), " ".repeat(6))
    } else {
        let indent = " ".repeat(head.chars().count());
        (head, rhs.to_string(), indent)
    };
    let rhs = rhs.as_str();
    let mut best = full;
    for depth in 0..4 {
        let mut out = String::new();
        let mut line = head.clone();
        for (k, piece) in terms_to_depth(rhs, depth).into_iter().enumerate() {
            let fits = line.chars().count() + piece.chars().count() <= COLUMNS;
            if k > 0 && !fits && line.trim().len() > indent.trim().len() {
                out.push_str(line.trim_end());
                out.push('\n');
                line = indent.clone();
            }
            line.push_str(&piece);
        }
        out.push_str(line.trim_end());
        best = out;
        if best.lines().all(|l| l.chars().count() <= COLUMNS) {
            break;
        }
    }
    best
}

/// Splits before the ` + ` and ` − ` that are outside parentheses.
fn top_level_terms(s: &str) -> Vec<String> {
    terms_to_depth(s, 0)
}

/// Splits before the ` + ` and ` − ` inside at most `depth` levels of parentheses; the pieces
/// put together give `s` back.
fn terms_to_depth(s: &str, depth: i32) -> Vec<String> {
    let chars: Vec<char> = s.chars().collect();
    let mut pieces = Vec::new();
    let mut level = 0i32;
    let mut start = 0;
    for i in 0..chars.len() {
        match chars[i] {
            '(' | '[' => level += 1,
            ')' | ']' => level -= 1,
            ' ' if level <= depth
                && i + 2 < chars.len()
                && (chars[i + 1] == '+' || chars[i + 1] == '−')
                && chars[i + 2] == ' '
                && i > start =>
            {
                pieces.push(chars[start..i].iter().collect());
                start = i;
            }
            _ => {}
        }
    }
    pieces.push(chars[start..].iter().collect());
    pieces
}

fn text_table(header: &[String], rows: &[Vec<Cell>]) -> String {
    let cell = |c: &Cell| match c {
        Cell::Text(t) => t.clone(),
        Cell::Math(m) => m.unicode.clone(),
    };
    let mut widths: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for r in rows {
        for (k, c) in r.iter().enumerate() {
            if let Some(w) = widths.get_mut(k) {
                *w = (*w).max(cell(c).chars().count());
            }
        }
    }
    let line = |cells: Vec<String>| -> String {
        let padded: Vec<String> = cells
            .iter()
            .zip(&widths)
            .map(|(c, w)| format!("{c}{}", " ".repeat(w.saturating_sub(c.chars().count()))))
            .collect();
        format!("  {}\n", padded.join("  ").trim_end())
    };
    let mut out = line(header.to_vec());
    out.push_str(&line(widths.iter().map(|w| "─".repeat(*w)).collect()));
    for r in rows {
        out.push_str(&line(r.iter().map(cell).collect()));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Document {
        let th = Expr::coordinate("theta");
        let l = Expr::symbol("l");
        let mut s = Section::new("Kinematics", 2);
        s.paragraph("Position of the bob, 100% on the rod_1 & #2.");
        s.equations(vec![Equation::new(
            Math::label("r_P", r"\vec{r}_P"),
            Math::vector(&[l * th.sin(), -(l * th.cos()), Expr::zero()]),
        )]);
        s.remark("θ = 0 is stable.");
        s.blocks.push(Block::Table {
            header: vec!["θ".into(), "stable".into()],
            rows: vec![vec![
                Cell::Math(Math::expr(Expr::zero())),
                Cell::Text("yes".into()),
            ]],
        });
        Document {
            title: "Pendulum".into(),
            sections: vec![s],
        }
    }

    #[test]
    fn vectors_read_like_the_seed() {
        let th = Expr::coordinate("theta");
        let l = Expr::symbol("l");
        let v = Math::vector(&[l * th.sin(), -(l * th.cos()), Expr::zero()]);
        assert_eq!(v.unicode, "ℓ sin θ x̂ − ℓ cos θ ŷ");
        assert_eq!(
            v.latex,
            r"\ell \sin \theta \hat{x} - \ell \cos \theta \hat{y}"
        );
        let w = Math::vector(&[Expr::zero(), Expr::one(), th + l]);
        assert_eq!(w.unicode, "ŷ + (θ + ℓ) ẑ");
        assert_eq!(
            Math::vector(&[Expr::zero(), Expr::zero(), Expr::zero()]).unicode,
            "0"
        );
    }

    #[test]
    fn the_three_renderings_carry_the_same_content() {
        let d = sample();
        let text = d.to_text();
        assert!(text.contains("Kinematics\n──────────"));
        assert!(text.contains("  r_P = ℓ sin θ x̂ − ℓ cos θ ŷ"));
        assert!(text.contains("Obs. θ = 0 is stable."));
        let md = d.to_markdown();
        assert!(md.contains("## Kinematics"));
        assert!(md.contains("$$\n\\begin{aligned}\n\\vec{r}_P &= "));
        assert!(md.contains("```{note}\nθ = 0 is stable.\n```"));
        assert!(md.contains("| $0$ | yes |"));
        let tex = d.to_latex();
        assert!(tex.starts_with("\\documentclass"));
        assert!(tex.ends_with("\\end{document}\n"));
        assert!(tex.contains("100\\% on the rod\\_1 \\& \\#2."));
        assert!(tex.contains("\\textit{Obs.} $\\theta$ = 0 is stable."));
        assert_eq!(
            tex.matches("\\begin{align*}").count(),
            tex.matches("\\end{align*}").count()
        );
    }

    #[test]
    fn long_latex_breaks_at_top_level_signs_only() {
        let rhs = format!(
            "{} + \\left({} + c\\right) - {}",
            "x".repeat(60),
            "y".repeat(10),
            "z".repeat(50)
        );
        let body = aligned_lines(&[Equation::new(
            Math::label("f", "f"),
            Math::label("f", rhs.clone()),
        )]);
        assert_eq!(body.lines().count(), 2, "{body}");
        assert!(body.contains("\\left(yyyyyyyyyy + c\\right)"));
        assert!(
            body.lines()
                .nth(1)
                .is_some_and(|l| l.starts_with("&\\quad + \\left(")),
            "{body}"
        );
        assert!(
            body.lines().next().is_some_and(|l| l.ends_with("x \\\\")),
            "{body}"
        );
    }

    #[test]
    fn long_equations_wrap_at_top_level_signs() {
        let top = format!("{} + (a + b) − {}", "x".repeat(50), "y".repeat(40));
        let nested = format!("−({} + {} − c)/(d + e)", "x".repeat(50), "y".repeat(40));
        let long_lhs = wrap_equation(&format!("{} + {}", "a".repeat(50), "b".repeat(40)), "0");
        assert!(
            long_lhs.lines().all(|l| l.chars().count() <= COLUMNS),
            "{long_lhs}"
        );
        for rhs in [top, nested] {
            let out = wrap_equation("f", &rhs);
            assert!(out.lines().count() >= 2, "{out}");
            assert!(out.lines().all(|l| l.chars().count() <= COLUMNS), "{out}");
            // Nothing is lost: the pieces put together give the equation back.
            let joined: String = out.lines().map(str::trim).collect::<Vec<_>>().join(" ");
            assert_eq!(joined, format!("f = {rhs}"));
        }
    }

    #[test]
    fn latex_breaks_inside_long_fractions_and_brackets() {
        // A fraction whose numerator is too long for a line, as a long left-hand side.
        let sum = (0..12)
            .map(|i| format!(r"m_{i} \ddot{{x}}_{i} \left( a_{i} + b_{i} \right)"))
            .collect::<Vec<_>>()
            .join(" + ");
        let lhs = format!(r"\frac{{{sum}}}{{x_1 + x_2}}");
        let body = aligned_lines(&[Equation::new(
            Math::label("", lhs.clone()),
            Math::label("0", "0"),
        )]);
        let rows: Vec<&str> = body.split(" \\\\\n").collect();
        assert!(rows.len() > 2, "{body}");
        for row in &rows {
            assert!(visible_width(row) <= LATEX_LINE + 20, "{row}");
            // Every row is valid on its own: braces balance and no \left is left open.
            assert_eq!(row.matches('{').count(), row.matches('}').count(), "{row}");
            assert_eq!(
                row.matches("\\left").count(),
                row.matches("\\right").count(),
                "{row}"
            );
        }
        assert!(rows[0].starts_with("& \\bigl("), "{body}");
        assert!(
            body.ends_with(r"\bigr) / \bigl(x_1 + x_2\bigr) = 0"),
            "{body}"
        );
        // Short displays are untouched.
        assert_eq!(breakable_latex(r"\frac{a}{b}"), r"\frac{a}{b}");
        assert_eq!(
            breakable_latex(r"\left|x\right| \left( a + b \right)"),
            r"\bigl|x\bigr| \bigl( a + b \bigr)"
        );
    }
}
