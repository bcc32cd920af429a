//! Issue 14: 5,000 unused parameters on one line took 13.8 s, 1.3 GB and printed 670 MB: one
//! warning per parameter, each re-printing the whole (long) source line, and the renderer
//! rebuilt its index of the file for every diagnostic (quadratic: `check` took 1.3 s for 1,000
//! parameters, 5.3 s for 2,000). The fix: unused parameters are one grouped warning listing
//! the first few names and "and N more"; the renderer indexes the file once, draws at most 50
//! diagnostics, and shows an excerpt of a line longer than 200 characters instead of the line.

use model::{render, DiagnosticKind, RenderOptions};

fn one_line_of_parameters(n: usize) -> String {
    let parameters: Vec<String> = (0..n).map(|i| format!("p{i} = 1")).collect();
    format!(
        "coordinates x\nparameters m = 1, {}\nframe N\npoint P = x*N.x\nparticle P mass m\n",
        parameters.join(", ")
    )
}

#[test]
fn unused_parameters_are_one_warning_with_a_bounded_rendering() {
    let source = one_line_of_parameters(5000);
    let model = model::load(&source).expect("loads, with a warning");
    let warnings = model.warnings();
    assert_eq!(warnings.len(), 1);
    match &warnings[0].kind {
        DiagnosticKind::UnusedParameters { names, more } => {
            assert_eq!(names.first().map(String::as_str), Some("p0"));
            assert_eq!(names.len() + more, 5000);
        }
        other => panic!("{other:?}"),
    }
    assert!(warnings[0]
        .message()
        .ends_with(&format!("and {} more", 5000 - 8)));
    let text = render(warnings, "m.lag", &source, RenderOptions::default());
    // The 60,000-character line is shown as an excerpt around the first name.
    assert!(text.len() < 1000, "{} bytes", text.len());
    assert!(text.contains("m.lag:2:19: warning[W002]: 5000 parameters are never used"));
    assert!(text.contains("parameters m = 1, p0 = 1"));
    assert!(text.contains('…'));
}

#[test]
fn one_unused_parameter_keeps_its_own_warning() {
    let model = model::load(
        "coordinates x\nparameters m = 1, k = 2\nframe N\npoint P = x*N.x\nparticle P mass m\n",
    )
    .unwrap();
    assert!(matches!(
        &model.warnings()[0].kind,
        DiagnosticKind::UnusedParameter { name } if name == "k"
    ));
}

#[test]
fn many_errors_are_rendered_up_to_a_cap() {
    // 120 unknown names: 120 errors, 50 drawn, the rest counted.
    let mut source = String::from("coordinates x\nframe N\n");
    for i in 0..120 {
        source.push_str(&format!("point P{i} = q{i}*N.x\n"));
    }
    let diagnostics = model::load(&source).expect_err("errors").0;
    assert_eq!(diagnostics.len(), 120);
    let text = render(&diagnostics, "m.lag", &source, RenderOptions::default());
    assert_eq!(text.matches("[E101] Error").count(), 50, "{text}");
    assert!(text.contains("… and 70 more diagnostics"));
}

#[test]
fn many_parameters_on_their_own_lines_check_without_a_warning_each() {
    let mut source = String::from("coordinates x\n");
    for i in 0..2000 {
        source.push_str(&format!("parameters p{i} = {}\n", i + 1));
    }
    source.push_str("frame N\npoint P = x*N.x\nparticle P mass p0\n");
    let model = model::load(&source).unwrap();
    assert_eq!(model.warnings().len(), 1);
    let text = render(model.warnings(), "m.lag", &source, RenderOptions::default());
    assert!(
        text.contains("1999 parameters are never used: `p1`"),
        "{text}"
    );
}

/// Issue 14: a missing inertial frame suggested `frame N = N rotated …`, which refers to
/// itself; the help now gives a definition that works.
#[test]
fn a_missing_frame_gets_a_definition_that_works() {
    let help = |source: &str| {
        model::load(source).expect_err("an error").0[0]
            .help
            .clone()
            .unwrap_or_default()
    };
    let none = help("coordinates th\nparameters m = 1\nframe B = N rotated th about z\npoint P = B.x\nparticle P mass m\n");
    assert!(none.contains("`frame N` (the first frame"), "{none}");
    let one = help("coordinates th\nparameters m = 1\nframe A\nframe B = N rotated th about z\npoint P = B.x\nparticle P mass m\n");
    assert!(one.contains("`frame N = A rotated … about z`"), "{one}");
}
