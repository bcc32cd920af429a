//! The MyST Markdown rendering: headings, `$$` display math, pipe tables, admonitions.

use std::fmt::Write as _;

use super::latex::aligned_lines_to;
use super::prose::{pieces, Piece};

/// Glyphs per display line of the Markdown rendering (see `latex::visible_width`): a Jupyter
/// Book's text column (about 790 px in a 1000 px window) in MathJax's type, with room to spare;
/// `tools/browser/book.py` checks that no display is wider than the column.
pub(super) const MARKDOWN_LINE: usize = 58;
use super::{Block, Cell, Document};

impl Document {
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
                        let _ = writeln!(out, "{}\n", markdown_prose(p));
                    }
                    Block::Remark(p) => {
                        let _ = writeln!(out, "```{{note}}\n{}\n```\n", markdown_prose(p));
                    }
                    Block::List(items) => {
                        for item in items {
                            let _ = writeln!(out, "- {}", markdown_prose(item));
                        }
                        out.push('\n');
                    }
                    Block::Equations(lines) => {
                        let _ = writeln!(out, "$$\n\\begin{{aligned}}");
                        let _ = writeln!(out, "{}", aligned_lines_to(lines, MARKDOWN_LINE));
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
                    Block::Figure { path, caption, .. } => {
                        let _ = writeln!(out, "```{{figure}} {path}\n{caption}\n```\n");
                    }
                    Block::Link { path, text } => {
                        let _ = writeln!(out, "[{text}]({path})\n");
                    }
                }
            }
        }
        out
    }
}

/// Prose with its mathematics as inline `$…$` (the prose layer shared with the LaTeX writer)
/// and its names in backticks as code.
pub(super) fn markdown_prose(s: &str) -> String {
    pieces(s)
        .into_iter()
        .map(|p| match p {
            Piece::Text(t) => t,
            Piece::Math(m) => format!("${m}$"),
            Piece::Code(c) => format!("`{c}`"),
        })
        .collect()
}

fn markdown_cell(c: &Cell) -> String {
    match c {
        Cell::Text(t) => markdown_prose(t).replace('|', "\\|"),
        Cell::Math(m) => format!("${}$", m.latex.replace('|', "\\vert ")),
    }
}
