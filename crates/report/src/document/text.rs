//! The terminal rendering: Unicode mathematics, prose and long equations wrapped to 80
//! columns, tables aligned in columns.

use std::fmt::Write as _;

use super::{Block, Cell, Document};

/// Terminal width the text rendering wraps long equations to.
pub(super) const COLUMNS: usize = 80;

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
                    Block::List(items) => {
                        for item in items {
                            let _ = writeln!(
                                out,
                                "{}",
                                wrap_words(&format!("• {item}"), COLUMNS, "  ")
                            );
                        }
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
                    Block::Figure { path, caption, .. } => {
                        let _ = writeln!(out, "  [figure: {caption} — {path}]");
                    }
                    Block::Link { path, text } => {
                        let _ = writeln!(out, "{text}: {path}");
                    }
                }
                out.push('\n');
            }
        }
        out
    }
}

/// Words wrapped to `width` columns; continuation lines start with `indent`.
pub(super) fn wrap_words(text: &str, width: usize, indent: &str) -> String {
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
pub(super) fn wrap_equation(lhs: &str, rhs: &str) -> String {
    // A matrix, one row a line: set beside its name, not wrapped.
    if rhs.contains('\n') {
        return super::side_by_side(&[&format!("  {lhs}"), rhs], " = ");
    }
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
pub(super) fn top_level_terms(s: &str) -> Vec<String> {
    terms_to_depth(s, 0)
}

/// Splits before the ` + ` and ` − ` inside at most `depth` levels of parentheses; the pieces
/// put together give `s` back.
pub(super) fn terms_to_depth(s: &str, depth: i32) -> Vec<String> {
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

pub(super) fn text_table(header: &[String], rows: &[Vec<Cell>]) -> String {
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
