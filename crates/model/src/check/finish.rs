//! Whole-model checks made after the last statement: unused names, unusable values, no free
//! coordinate, more constraints than coordinates.

use super::{Checker, MAX_LISTED_NAMES};
use crate::diagnostic::{Diagnostic, DiagnosticKind};
use crate::model::*;
use crate::span::Span;

impl Checker {
    pub(super) fn finish(&mut self) {
        if !self.diagnostics.iter().any(Diagnostic::is_error) {
            self.unused();
            // Values the file gives that numeric work could not use (`1/0`, an overflowing
            // product) are errors at their place now, not NaNs far downstream. Masses were
            // checked where they were declared.
            let values = self.model.value_diagnostics();
            self.diagnostics.extend(
                values
                    .into_iter()
                    .filter(|d| matches!(d.kind, DiagnosticKind::UnusableValue { .. })),
            );
        }
        let free = self.model.free_coordinates().count();
        if free == 0 && !self.diagnostics.iter().any(Diagnostic::is_error) {
            let span = Span::new(0, 0);
            self.diagnostics.push(
                Diagnostic::new(DiagnosticKind::NoCoordinates, span)
                    .with_help("Declare the generalized coordinates, e.g. `coordinates x, theta`."),
            );
        }
        let constraints = self.model.constraints.len();
        if free > 0 && constraints > free {
            let span = self
                .model
                .constraints
                .get(free)
                .map_or(Span::new(self.end, self.end), |c| c.span);
            self.diagnostics.push(
                Diagnostic::new(DiagnosticKind::TooManyConstraints { constraints, coordinates: free }, span)
                    .with_label("one constraint too many from here on")
                    .with_help("Each constraint removes a degree of freedom: remove redundant constraints or add coordinates."),
            );
        }
    }

    /// Warn about coordinates and parameters nothing uses. Only on an otherwise valid model:
    /// after an error, a name may look unused because the line that used it was skipped.
    fn unused(&mut self) {
        for coordinate in &self.model.coordinates {
            if coordinate.driven.is_none() && !self.used.contains(&coordinate.name.name) {
                let name = coordinate.name.name.clone();
                self.diagnostics.push(
                    Diagnostic::warning(DiagnosticKind::UnusedCoordinate { name: name.clone() }, coordinate.name.span)
                        .with_help(format!(
                            "Use `{name}` in a point, a frame or a constraint, or remove it: a coordinate \
                             that nothing depends on has no equation of motion."
                        )),
                );
            }
        }
        let unused: Vec<&Name> = self
            .model
            .parameters
            .iter()
            .map(|p| &p.name)
            .filter(|n| !self.used.contains(&n.name))
            .collect();
        match unused.as_slice() {
            [] => {}
            [one] => self.diagnostics.push(
                Diagnostic::warning(
                    DiagnosticKind::UnusedParameter {
                        name: one.name.clone(),
                    },
                    one.span,
                )
                .with_help(format!(
                    "Remove `{}`, or use it where it was meant to be.",
                    one.name
                )),
            ),
            // One warning for all of them: 5,000 unused parameters were 5,000 warnings, each
            // re-printing the source line (issue 14).
            [first, rest @ ..] => {
                let shown: Vec<String> = unused
                    .iter()
                    .take(MAX_LISTED_NAMES)
                    .map(|n| n.name.clone())
                    .collect();
                let mut diagnostic = Diagnostic::warning(
                    DiagnosticKind::UnusedParameters {
                        more: unused.len() - shown.len(),
                        names: shown,
                    },
                    first.span,
                )
                .with_help("Remove them, or use them where they were meant to be.");
                for other in rest.iter().take(MAX_LISTED_NAMES - 1) {
                    diagnostic = diagnostic.with_related(other.span, "never used");
                }
                self.diagnostics.push(diagnostic);
            }
        }
    }
}
