//! Results written in the formats the command line and the Python package offer
//! (`lagrange::formats`): each result renders as text or JSON from the library, the JSON
//! parses back with its schema, and a lone expression is written in each dialect.

use std::path::Path;

use lagrange::{cas, Analysis, Dialect, ReportFormat, ResultFormat, Written};

fn pendulum() -> Analysis {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/simple-pendulum.lag");
    Analysis::from_file(&path).expect("the example reads")
}

fn parsed(text: &str) -> serde_json::Value {
    assert!(text.ends_with('\n'), "JSON text ends its line");
    serde_json::from_str(text).expect("valid JSON")
}

#[test]
fn equations_are_written_as_text_or_as_json_with_the_schema() {
    let analysis = pendulum();
    let text = analysis.equations_written(ResultFormat::Text).unwrap();
    assert!(text.contains("θ̈"), "{text}");
    let json = parsed(&analysis.equations_written(ResultFormat::Json).unwrap());
    assert_eq!(json["schema"], 1);
    assert_eq!(json["coordinates"][0], "theta");
}

#[test]
fn equilibria_are_written_the_same_way_the_types_give_them() {
    let analysis = pendulum();
    let found = analysis.equilibria().unwrap();
    assert_eq!(
        found.written(ResultFormat::Text),
        format!("{}\n", found.to_text().trim_end())
    );
    let json = parsed(&found.written(ResultFormat::Json));
    assert_eq!(json, found.to_json());
    let linearized = lagrange::Linearized {
        equilibria: found,
        only: Some(0),
        deviations: None,
    };
    assert_eq!(
        parsed(&linearized.written(ResultFormat::Json)),
        found.linearized_json(Some(0), None)
    );
}

#[test]
fn a_solution_is_written_in_each_report_format() {
    let analysis = pendulum();
    let solution = analysis.solution(None).unwrap();
    let written = |format| analysis.solution_written(&solution, format).unwrap();
    assert_eq!(written(ReportFormat::Text), solution.document.to_text());
    assert!(written(ReportFormat::Tex).starts_with("\\documentclass"));
    assert!(written(ReportFormat::Md).contains("$$"));
    let json = parsed(&written(ReportFormat::Json));
    assert!(json["report"].is_object(), "the report is inside: {json}");
    let extensions: Vec<_> = [
        ReportFormat::Text,
        ReportFormat::Md,
        ReportFormat::Tex,
        ReportFormat::Json,
    ]
    .map(ReportFormat::extension)
    .into();
    assert_eq!(extensions, ["txt", "md", "tex", "json"]);
}

#[test]
fn an_expression_is_written_in_each_dialect() {
    let expr = cas::Expr::symbol("theta").powi(2) / 2;
    assert_eq!(Dialect::Sympy.write(expr), "theta**2/2");
    assert_eq!(Dialect::Unicode.write(expr), "θ²/2");
    assert_eq!(Dialect::Latex.write(expr), "\\frac{1}{2} \\theta^2");
}
