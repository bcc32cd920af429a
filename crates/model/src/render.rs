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
    for diagnostic in sorted {
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
        if report
            .finish()
            .write((file_name, Source::from(source)), &mut out)
            .is_err()
        {
            out.extend_from_slice(
                render_short(std::slice::from_ref(diagnostic), file_name, source).as_bytes(),
            );
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Render one line per diagnostic: `file:line:column: error[E101]: message (help: …)`.
#[must_use]
pub fn render_short(diagnostics: &[Diagnostic], file_name: &str, source: &str) -> String {
    let index = LineIndex::new(source);
    let mut out = String::new();
    for diagnostic in diagnostics {
        let position = index.line_col(diagnostic.span.start);
        let severity = match diagnostic.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        out.push_str(&format!(
            "{file_name}:{position}: {severity}[{}]: {}",
            diagnostic.kind.code(),
            diagnostic.message()
        ));
        if let Some(help) = &diagnostic.help {
            out.push_str(&format!(" (help: {help})"));
        }
        out.push('\n');
    }
    out
}
