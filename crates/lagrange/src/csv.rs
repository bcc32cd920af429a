//! The tables a simulation writes, as CSV text: rows of numbers (each the shortest text that
//! reads back to the same `f64`), the recorded crossings, and one row per run of a sweep.

use crate::simulate::{direction, Crossing, SweepRun};
use crate::Error;

/// One row: numbers separated by commas, with a line break.
#[must_use]
pub fn row(values: &[f64]) -> String {
    let mut line = values
        .iter()
        .map(|v| format!("{v:?}"))
        .collect::<Vec<_>>()
        .join(",");
    line.push('\n');
    line
}

/// A text field: quoted (with quotes doubled) when it holds a comma, a quote or a line break.
#[must_use]
pub fn text(field: &str) -> String {
    if field.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_owned()
    }
}

/// The crossings: `event,direction,` and the state columns (`t`, coordinates, rates).
#[must_use]
pub fn events(columns: &[String], expressions: &[String], crossings: &[Crossing]) -> String {
    let mut out = format!("event,direction,{}\n", columns.join(","));
    for c in crossings {
        let name = expressions.get(c.event).map_or("", String::as_str);
        out.push_str(&format!("{},{},", text(name), direction(c.rising)));
        out.push_str(&row(&c.state));
    }
    out
}

/// One line about recorded crossings: how many, and the first few.
#[must_use]
pub fn crossings_line(expressions: &[String], crossings: &[Crossing]) -> String {
    const SHOWN: usize = 4;
    let mut line = format!(
        "recorded {} crossing{}",
        crossings.len(),
        if crossings.len() == 1 { "" } else { "s" }
    );
    for (k, c) in crossings.iter().take(SHOWN).enumerate() {
        line.push_str(if k == 0 { ": " } else { ", " });
        line.push_str(&format!(
            "`{}` {} at t = {:.6}",
            expressions.get(c.event).map_or("", String::as_str),
            direction(c.rising),
            c.state[0]
        ));
    }
    if crossings.len() > SHOWN {
        line.push_str(&format!(", … ({} more)", crossings.len() - SHOWN));
    }
    line
}

/// A sweep's table: `run`, the varied names, `final_` and each column, `steps`, `outcome`;
/// also how many runs failed.
#[must_use]
pub fn sweep(
    names: &[String],
    columns: &[String],
    values: &[Vec<f64>],
    results: &[Result<SweepRun, Error>],
) -> (String, usize) {
    let mut header: Vec<String> = vec!["run".into()];
    header.extend(names.iter().cloned());
    header.extend(columns.iter().map(|c| format!("final_{c}")));
    header.extend(["steps".into(), "outcome".into()]);
    let mut out = header.join(",") + "\n";
    let mut failed = 0;
    for (k, (values, result)) in values.iter().zip(results).enumerate() {
        let mut fields: Vec<String> = vec![k.to_string()];
        fields.extend(values.iter().map(|v| format!("{v:?}")));
        match result {
            Ok(r) => {
                failed += usize::from(r.ending.stopped_short());
                fields.extend(r.last.iter().map(|v| format!("{v:?}")));
                let missing = columns.len().saturating_sub(r.last.len());
                fields.extend(std::iter::repeat_n(String::new(), missing));
                fields.push(r.steps.to_string());
                fields.push(format!("\"{}\"", r.ending.word().replace('"', "'")));
            }
            Err(e) => {
                failed += 1;
                fields.extend(std::iter::repeat_n(String::new(), columns.len() + 1));
                fields.push(format!("\"error: {}\"", e.to_string().replace('"', "'")));
            }
        }
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    (out, failed)
}
