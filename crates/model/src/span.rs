//! Source positions: the byte range [`Span`] that every syntax node carries, and [`LineIndex`],
//! which turns a byte offset into the 1-based line and column that diagnostics show.

use std::ops::Range;

/// A half-open byte range `start..end` into the model source.
///
/// Spans are byte offsets (not character offsets) because that is what the lexer produces and
/// what slicing a `&str` needs; [`LineIndex`] converts them to line and column for people.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Span {
    /// Offset of the first byte.
    pub start: usize,
    /// Offset one past the last byte.
    pub end: usize,
}

impl Span {
    /// The span `start..end`; the bounds are swapped if given in the wrong order.
    #[must_use]
    pub fn new(start: usize, end: usize) -> Span {
        if start <= end {
            Span { start, end }
        } else {
            Span {
                start: end,
                end: start,
            }
        }
    }

    /// The smallest span covering both `self` and `other`.
    #[must_use]
    pub fn to(self, other: Span) -> Span {
        Span {
            start: self.start.min(other.start),
            end: self.end.max(other.end),
        }
    }

    /// The span as a `Range<usize>`.
    #[must_use]
    pub fn range(self) -> Range<usize> {
        self.start..self.end
    }

    /// Number of bytes covered.
    #[must_use]
    pub fn len(self) -> usize {
        self.end - self.start
    }

    /// Whether the span covers no byte (for example the end of the file).
    #[must_use]
    pub fn is_empty(self) -> bool {
        self.start == self.end
    }
}

impl From<Range<usize>> for Span {
    fn from(range: Range<usize>) -> Span {
        Span::new(range.start, range.end)
    }
}

/// A 1-based line and column, as editors show them. The column counts characters, not bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LineCol {
    /// Line number, starting at 1.
    pub line: usize,
    /// Column number in characters, starting at 1.
    pub column: usize,
}

impl std::fmt::Display for LineCol {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}", self.line, self.column)
    }
}

/// The start offsets of the lines of one source text, for offset → line/column conversion.
#[derive(Clone, Debug)]
pub struct LineIndex<'a> {
    source: &'a str,
    // Invariant: non-empty, starts with 0, strictly increasing; entry i is the byte offset just
    // after the i-th '\n'.
    line_starts: Vec<usize>,
}

impl<'a> LineIndex<'a> {
    /// Index the lines of `source`.
    #[must_use]
    pub fn new(source: &'a str) -> LineIndex<'a> {
        let mut line_starts = vec![0];
        line_starts.extend(source.match_indices('\n').map(|(i, _)| i + 1));
        LineIndex {
            source,
            line_starts,
        }
    }

    /// Line and column of byte `offset`. Offsets past the end clamp to the end of the text, and
    /// an offset inside a multi-byte character is placed just after that character.
    #[must_use]
    pub fn line_col(&self, offset: usize) -> LineCol {
        let offset = offset.min(self.source.len());
        // `partition_point` gives the number of line starts <= offset, which is at least 1.
        let line = self
            .line_starts
            .partition_point(|&start| start <= offset)
            .max(1);
        let line_start = self.line_starts.get(line - 1).copied().unwrap_or(0);
        let prefix = self.source.get(line_start..offset).map_or_else(
            // Not a char boundary: count the characters that start before `offset`.
            || {
                self.source
                    .char_indices()
                    .filter(|&(i, _)| i >= line_start && i < offset)
                    .count()
            },
            |text| text.chars().count(),
        );
        LineCol {
            line,
            column: prefix + 1,
        }
    }

    /// The text of line `line` (1-based) without its line break, or `None` past the end.
    #[must_use]
    pub fn line_text(&self, line: usize) -> Option<&'a str> {
        let start = *self.line_starts.get(line.checked_sub(1)?)?;
        let end = self
            .line_starts
            .get(line)
            .map_or(self.source.len(), |&next| next - 1);
        self.source
            .get(start..end)
            .map(|text| text.trim_end_matches('\r'))
    }
}

/// Line and column of byte `offset` in `source`; see [`LineIndex::line_col`]. Build a
/// [`LineIndex`] instead when converting many offsets of the same text.
#[must_use]
pub fn line_col(source: &str, offset: usize) -> LineCol {
    LineIndex::new(source).line_col(offset)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_are_one_based_and_count_characters() {
        let text = "ab\nθx\n";
        let index = LineIndex::new(text);
        assert_eq!(index.line_col(0), LineCol { line: 1, column: 1 });
        assert_eq!(index.line_col(3), LineCol { line: 2, column: 1 });
        // 'x' sits after the two-byte θ.
        assert_eq!(index.line_col(5), LineCol { line: 2, column: 2 });
        assert_eq!(index.line_col(4), LineCol { line: 2, column: 2 });
        assert_eq!(index.line_col(100), LineCol { line: 3, column: 1 });
        assert_eq!(index.line_text(2), Some("θx"));
        assert_eq!(index.line_text(9), None);
    }
}
