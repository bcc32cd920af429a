//! Rendering diagnostics as text: the annotated source excerpt (via `ariadne`), or one short
//! line per diagnostic. Everything is written into a `String`; this crate never prints.

use ariadne::{CharSet, Color, Config, IndexType, Label, Report, ReportKind, Source};

use crate::diagnostic::{Diagnostic, Severity};
use crate::span::{LineIndex, Span};

/// How to render diagnostics.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct RenderOptions {
    /// Use ANSI colours (default: `false`; the CLI turns them on for a terminal).
    pub color: bool,
    /// Draw boxes with Unicode characters rather than ASCII (default: `true`).
    pub unicode: bool,
}

impl Default for RenderOptions {
    fn default() -> RenderOptions {
        RenderOptions {
            color: false,
            unicode: true,
        }
    }
}

impl RenderOptions {
    /// Set [`RenderOptions::color`].
    #[must_use]
    pub fn with_color(mut self, color: bool) -> RenderOptions {
        self.color = color;
        self
    }

    /// Set [`RenderOptions::unicode`].
    #[must_use]
    pub fn with_unicode(mut self, unicode: bool) -> RenderOptions {
        self.unicode = unicode;
        self
    }
}

/// Render `diagnostics` about `source` (read from `file_name`) with the offending text
/// underlined, the message, related places and the help. Diagnostics are sorted by position.
#[must_use]
pub fn render(
    diagnostics: &[Diagnostic],
    file_name: &str,
    source: &str,
    options: RenderOptions,
) -> String {
    let mut sorted: Vec<&Diagnostic> = diagnostics.iter().collect();
    sorted.sort_by_key(|d| (d.span.start, d.span.end));
    let mut out = Vec::new();
    let config = Config::new()
        .with_color(options.color)
        .with_char_set(if options.unicode {
            CharSet::Unicode
        } else {
            CharSet::Ascii
        })
        .with_index_type(IndexType::Byte);
    let clamp = |span: Span| {
        // Spans come from this source, but clamp anyway so that a diagnostic paired with the
        // wrong text cannot make the renderer misbehave.
        let end = span.end.min(source.len());
        span.start.min(end)..end
    };
    // One source index for all diagnostics: building it per diagnostic made rendering
    // quadratic in the file (issue 14).
    let mut cache = (file_name, Source::from(source));
    let index = LineIndex::new(source);
    let total = sorted.len();
    for (shown, diagnostic) in sorted.into_iter().enumerate() {
        if shown == MAX_RENDERED {
            out.extend_from_slice(
                format!(
                    "… and {} more diagnostic{} (fix these first)\n",
                    total - shown,
                    if total - shown == 1 { "" } else { "s" }
                )
                .as_bytes(),
            );
            break;
        }
        if let Some(excerpt) = long_line_excerpt(diagnostic, file_name, source, &index) {
            out.extend_from_slice(excerpt.as_bytes());
            continue;
        }
        let kind = match diagnostic.severity {
            Severity::Error => ReportKind::Error,
            Severity::Warning => ReportKind::Warning,
        };
        let primary = clamp(diagnostic.span);
        let mut label = Label::new((file_name, primary.clone())).with_order(0);
        // The header carries the message; the underline gets a short note, so that the two
        // do not say the same thing twice.
        let note = diagnostic
            .label
            .clone()
            .or_else(|| diagnostic.kind.underline_note());
        label = label.with_message(note.unwrap_or_else(|| diagnostic.message()));
        if options.color {
            label = label.with_color(Color::Red);
        }
        let mut report = Report::build(kind, (file_name, primary))
            .with_config(config)
            .with_code(diagnostic.kind.code())
            .with_message(diagnostic.message())
            .with_label(label);
        for (order, related) in diagnostic.labels.iter().enumerate() {
            let mut label = Label::new((file_name, clamp(related.span)))
                .with_message(&related.message)
                .with_order(i32::try_from(order).unwrap_or(i32::MAX).saturating_add(1));
            if options.color {
                label = label.with_color(Color::Blue);
            }
            report = report.with_label(label);
        }
        if let Some(help) = &diagnostic.help {
            report = report.with_help(help);
        }
        // Writing into a Vec<u8> cannot fail; if ariadne ever reports an error, fall back to
        // the short form so that the diagnostic is not lost.
        if report.finish().write(&mut cache, &mut out).is_err() {
            out.extend_from_slice(
                render_short(std::slice::from_ref(diagnostic), file_name, source).as_bytes(),
            );
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// At most this many diagnostics are drawn in full; the rest are counted.
const MAX_RENDERED: usize = 50;

/// Source lines longer than this are not drawn whole: only an excerpt around the span.
const MAX_LINE: usize = 200;

/// Characters of context shown on each side of the span in an excerpt.
const EXCERPT_CONTEXT: usize = 40;

/// For a diagnostic on a line longer than [`MAX_LINE`], the short header and an excerpt of the
/// line around the span, underlined (`None` for ordinary lines, which ariadne draws).
fn long_line_excerpt(
    diagnostic: &Diagnostic,
    file_name: &str,
    source: &str,
    index: &LineIndex,
) -> Option<String> {
    let start = floor_boundary(source, diagnostic.span.start.min(source.len()));
    let line_start = source[..start].rfind('\n').map_or(0, |i| i + 1);
    let line_end = source[start..]
        .find('\n')
        .map_or(source.len(), |i| start + i);
    if line_end - line_start <= MAX_LINE {
        return None;
    }
    let end = floor_boundary(source, diagnostic.span.end.clamp(start, line_end));
    let from = floor_boundary(
        source,
        start.saturating_sub(EXCERPT_CONTEXT).max(line_start),
    );
    let to = floor_boundary(source, (end + EXCERPT_CONTEXT).min(line_end).max(end));
    let before = if from > line_start { "…" } else { "" };
    let after = if to < line_end { "…" } else { "" };
    let pad = before.chars().count() + source[from..start].chars().count();
    let width = source[start..end]
        .chars()
        .count()
        .clamp(1, 2 * EXCERPT_CONTEXT);
    let mut out = short_line(diagnostic, file_name, index);
    out.push_str(&format!("  | {before}{}{after}\n", &source[from..to]));
    out.push_str(&format!("  | {}{}\n", " ".repeat(pad), "^".repeat(width)));
    Some(out)
}

fn floor_boundary(s: &str, mut i: usize) -> usize {
    i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// Render one line per diagnostic: `file:line:column: error[E101]: message (help: …)`.
#[must_use]
pub fn render_short(diagnostics: &[Diagnostic], file_name: &str, source: &str) -> String {
    let index = LineIndex::new(source);
    diagnostics
        .iter()
        .map(|d| short_line(d, file_name, &index))
        .collect()
}

/// `file:line:column: error[E101]: message (help: …)` and a line break.
fn short_line(diagnostic: &Diagnostic, file_name: &str, index: &LineIndex) -> String {
    let position = index.line_col(diagnostic.span.start);
    let severity = match diagnostic.severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
    };
    let mut out = format!(
        "{file_name}:{position}: {severity}[{}]: {}",
        diagnostic.kind.code(),
        diagnostic.message()
    );
    if let Some(help) = &diagnostic.help {
        out.push_str(&format!(" (help: {help})"));
    }
    out.push('\n');
    out
}
