//! One test per diagnostic kind: the message, the line and the column, and (where it matters)
//! the help. Most sources start with the two-line prelude `coordinates x, y` / `frame N`, so
//! the line under test is line 3.

use model::{Diagnostic, RenderOptions};

const PRELUDE: &str = "coordinates x, y\nframe N\n";

/// All diagnostics of `source` (parse + check), sorted by position.
fn diagnostics(source: &str) -> Vec<Diagnostic> {
    match model::load(source) {
        Ok(_) => Vec::new(),
        Err(errors) => errors.0,
    }
}

/// Assert that `source` has a diagnostic with `code`, `message`, at `line`:`column`; return it.
#[track_caller]
fn expect(source: &str, code: &str, message: &str, line: usize, column: usize) -> Diagnostic {
    let found = diagnostics(source);
    let Some(diagnostic) = found.iter().find(|d| d.kind.code() == code) else {
        panic!("no {code} in {found:#?}");
    };
    assert_eq!(diagnostic.message(), message);
    let position = diagnostic.line_col(source);
    assert_eq!(
        (position.line, position.column),
        (line, column),
        "position of {message:?}"
    );
    diagnostic.clone()
}

#[track_caller]
fn expect_line(statement: &str, code: &str, message: &str, column: usize) -> Diagnostic {
    expect(&format!("{PRELUDE}{statement}\n"), code, message, 3, column)
}

#[track_caller]
fn assert_help(diagnostic: &Diagnostic, help: &str) {
    let actual = diagnostic.help.as_deref().unwrap_or("");
    assert!(actual.contains(help), "help {actual:?} lacks {help:?}");
}

// --- syntax -----------------------------------------------------------------------------

#[test]
fn e001_invalid_character() {
    expect_line("point P = x*N.x @", "E001", "unexpected character `@`", 17);
}

#[test]
fn e002_unexpected_token() {
    expect_line(
        "point P x*N.x",
        "E002",
        "expected `=` and the point's position, found `x`",
        9,
    );
    expect(
        "coordinates x,\n",
        "E002",
        "expected a coordinate name, found end of line",
        1,
        15,
    );
}

#[test]
fn e003_unknown_statement() {
    let d = expect_line("piont P = x*N.x", "E003", "unknown statement `piont`", 1);
    assert_help(&d, "Did you mean `point`?");
}

#[test]
fn e004_unclosed_parenthesis() {
    let d = expect_line("point P = sin(x*N.x", "E004", "unclosed parenthesis", 14);
    assert_help(&d, "Add the missing `)`");
}

#[test]
fn e005_too_deep() {
    let deep = format!("gravity {}N.x{}", "(".repeat(200), ")".repeat(200));
    expect_line(
        &deep,
        "E005",
        "expression is nested too deeply (more than 64 levels)",
        73,
    );
}

#[test]
fn e006_number_out_of_range() {
    expect_line(
        "parameters m = 1e999",
        "E006",
        "number `1e999` is out of range",
        16,
    );
}

#[test]
fn e007_duplicate_clause() {
    expect_line(
        "body b mass 1 at origin mass 2",
        "E007",
        "`mass` is given twice",
        25,
    );
}

#[test]
fn e008_unknown_option() {
    let d = expect_line("body b mas 1", "E008", "unknown option `mas` for `body`", 8);
    assert_help(&d, "Did you mean `mass`?");
    expect_line(
        "simulate until 10",
        "E008",
        "unknown option `until` for `simulate`",
        10,
    );
}

// --- names ------------------------------------------------------------------------------

#[test]
fn e101_unknown_name_with_suggestion() {
    let source = "coordinates theta\nframe N\npoint P = thta*N.x\n";
    let d = expect(source, "E101", "unknown name `thta`", 3, 11);
    assert_help(&d, "Did you mean `theta`?");
}

#[test]
fn e102_duplicate_name() {
    let d = expect(
        "coordinates x, theta\nparameters theta = 1\n",
        "E102",
        "`theta` is already defined",
        2,
        12,
    );
    assert_eq!(d.labels.len(), 1, "points at the first definition");
}

#[test]
fn e103_reserved_name() {
    expect_line("parameters t = 1", "E103", "`t` is a reserved name", 12);
    expect_line("point sin = x*N.x", "E103", "`sin` is a reserved name", 7);
}

#[test]
fn e104_used_before_definition() {
    let d = expect_line(
        "point P = l*x*N.x\nparameters l = 1",
        "E104",
        "`l` is used before it is defined",
        11,
    );
    assert_help(&d, "Move the declaration of `l` above its first use.");
}

#[test]
fn e105_wrong_kind() {
    expect_line(
        "particle N mass 1",
        "E105",
        "`N` is a frame, but a point is needed here",
        10,
    );
}

#[test]
fn e106_particle_at_undefined_point() {
    let source = format!("{PRELUDE}point Pb = x*N.x\nparticle Pa mass 1\n");
    let d = expect(&source, "E106", "particle at undefined point `Pa`", 4, 10);
    assert_help(&d, "Did you mean `Pb`?");
}

#[test]
fn e107_unknown_function() {
    let d = expect_line(
        "point P = sine(x)*N.x",
        "E107",
        "unknown function `sine`",
        11,
    );
    assert_help(&d, "Did you mean `sin`?");
}

#[test]
fn e108_wrong_arity() {
    expect_line(
        "point P = atan2(x)*N.x",
        "E108",
        "`atan2` takes 2 arguments, but 1 was given",
        11,
    );
}

#[test]
fn e109_unknown_axis() {
    let d = expect_line("point P = x*N.w", "E109", "frame `N` has no axis `w`", 15);
    assert_help(&d, "`N.x`, `N.y` and `N.z`");
}

#[test]
fn e110_rotation_about_a_missing_axis() {
    let d = expect_line(
        "frame B = N rotated x about w",
        "E110",
        "cannot rotate about `w`: there is no such axis",
        29,
    );
    assert_help(&d, "`x`, `y` or `z`");
    let d = expect_line(
        "frame B = N rotated x about xx",
        "E110",
        "cannot rotate about `xx`: there is no such axis",
        29,
    );
    assert_help(&d, "Write only the axis letter");
    let d = expect_line(
        "frame B = N rotated x about N.z",
        "E002",
        "expected end of line, found `.`",
        30,
    );
    assert_help(&d, "one statement per line");
}

#[test]
fn e111_second_inertial_frame() {
    let d = expect_line(
        "frame M",
        "E111",
        "there is already an inertial frame, `N`",
        7,
    );
    assert_help(&d, "frame M = N rotated");
}

#[test]
fn e112_not_a_value() {
    let d = expect_line("point P = x*N", "E112", "`N` is a frame, not a value", 13);
    assert_help(&d, "`N.x`");
}

// --- types ------------------------------------------------------------------------------

#[test]
fn e201_vector_where_a_scalar_is_needed() {
    let source = format!("{PRELUDE}point P = x*N.x\nparticle P mass N.y\n");
    expect(&source, "E201", "expected a scalar, found a vector", 4, 17);
}

#[test]
fn e201_scalar_where_a_vector_is_needed() {
    let d = expect_line(
        "point P = x + y",
        "E201",
        "expected a vector, found a scalar",
        11,
    );
    assert_help(&d, "unit vector such as `N.x`");
}

#[test]
fn e202_invalid_operands() {
    expect_line(
        "point P = x + N.x",
        "E202",
        "cannot add a scalar and a vector",
        11,
    );
    let d = expect_line(
        "point P = N.x*N.y",
        "E202",
        "cannot multiply a vector and a vector",
        11,
    );
    assert_help(&d, "dot(u, v)");
}

#[test]
fn e203_rate_of_a_non_coordinate() {
    let source = format!("{PRELUDE}parameters m = 1\ngeneralized force m' on x\n");
    expect(
        &source,
        "E203",
        "`m'`: only coordinates have rates, and `m` is a parameter",
        4,
        19,
    );
}

#[test]
fn e204_rate_not_allowed() {
    expect_line(
        "point P = x'*N.x",
        "E204",
        "rates such as `x'` cannot appear in a point's position",
        11,
    );
}

#[test]
fn e205_not_constant() {
    expect_line(
        "parameters m = x",
        "E205",
        "a parameter value can depend only on numbers, parameters and constants, not on `x`",
        16,
    );
}

#[test]
fn e206_wrong_degree_in_rates() {
    expect_line(
        "constraint x'^2 = 1",
        "E206",
        "a velocity constraint must be linear in the rates",
        12,
    );
}

// --- statements -------------------------------------------------------------------------

#[test]
fn e301_body_without_mass_or_inertia() {
    let d = expect_line(
        "body b at origin frame N inertia 1, 1, 1",
        "E301",
        "body `b` has no mass",
        6,
    );
    assert_help(&d, "Add `mass m`");
    expect_line(
        "body b mass 1 at origin frame N",
        "E301",
        "body `b` has no inertia",
        6,
    );
}

#[test]
fn e302_constraint_not_an_equation() {
    let d = expect_line(
        "constraint x^2 + y^2",
        "E302",
        "a constraint must be an equation",
        12,
    );
    assert_help(&d, "`x^2 + y^2 = 0`");
}

#[test]
fn e303_initial_for_a_non_coordinate() {
    let source = format!("{PRELUDE}parameters m = 1\ninitial m = 2\n");
    expect(
        &source,
        "E303",
        "initial condition for `m`, which is a parameter and not a coordinate",
        4,
        9,
    );
}

#[test]
fn e304_duplicate_initial() {
    expect_line(
        "initial x = 1, x = 2",
        "E304",
        "initial value of `x` is given twice",
        16,
    );
}

#[test]
fn e305_more_constraints_than_coordinates() {
    let source = "coordinates x\nconstraint x = 1\nconstraint x = 2\n";
    expect(
        source,
        "E305",
        "2 constraints on 1 coordinate: the system cannot move",
        3,
        1,
    );
}

#[test]
fn e306_no_coordinates() {
    expect(
        "frame N\n",
        "E306",
        "the model declares no coordinates",
        1,
        1,
    );
}

#[test]
fn e307_reaction_not_a_constraint() {
    expect_line(
        "reactions x",
        "E307",
        "no reaction for `x`: it is a coordinate, not a constraint or a driven coordinate",
        11,
    );
}

#[test]
fn e308_invalid_simulation() {
    expect_line(
        "simulate from 1 to 0",
        "E308",
        "invalid simulation setting: the end time must be after the start time",
        20,
    );
    expect_line(
        "simulate to 1 rtol -1",
        "E308",
        "invalid simulation setting: steps and tolerances must be positive",
        20,
    );
}

#[test]
fn e309_duplicate_simulate() {
    let source = format!("{PRELUDE}simulate to 1\nsimulate to 2\n");
    expect(&source, "E309", "`simulate` is given twice", 4, 1);
}

#[test]
fn e310_constraint_without_coordinates() {
    let source = format!("{PRELUDE}parameters l = 1\nconstraint l = 2\n");
    expect(
        &source,
        "E310",
        "this constraint does not involve any coordinate",
        4,
        12,
    );
}

#[test]
fn e311_non_positive_mass() {
    let source = format!("{PRELUDE}point P = x*N.x\nparticle P mass 0\n");
    expect(
        &source,
        "E311",
        "a mass must be positive, but this one is 0",
        4,
        17,
    );
    let source = format!("{PRELUDE}parameters m = 2\npoint P = x*N.x\nparticle P mass 1 - m\n");
    expect(
        &source,
        "E311",
        "a mass must be positive, but this one is -1",
        5,
        17,
    );
}

#[test]
fn e312_negative_moment() {
    let source = format!("{PRELUDE}point G = x*N.x\nbody b mass 1 at G frame N inertia xx = 1, yy = -2, zz = 1, xy = -5\n");
    expect(
        &source,
        "E312",
        "a moment of inertia cannot be negative, but this one is -2",
        4,
        49,
    );
}

// --- values -----------------------------------------------------------------------------

fn require_values(source: &str) -> Vec<Diagnostic> {
    model::load(source).expect("a valid model").require_values()
}

#[test]
fn e401_missing_parameter_value() {
    let source = format!("{PRELUDE}parameters m, l = 1\ninputs F\n");
    let found = require_values(&source);
    assert_eq!(found.len(), 2);
    assert_eq!(found[0].message(), "parameter `m` has no value");
    assert_eq!(found[0].line_col(&source).line, 3);
    assert_eq!(found[0].line_col(&source).column, 12);
    assert_eq!(found[1].message(), "input `F` has no value");
    assert_eq!(found[1].kind.code(), "E401");
}

#[test]
fn e402_missing_end_time() {
    let source = format!("{PRELUDE}simulate from 0\n");
    let found = require_values(&source);
    assert_eq!(found[0].message(), "the simulation has no end time");
    assert_eq!(found[0].kind.code(), "E402");
    assert_eq!(
        (
            found[0].line_col(&source).line,
            found[0].line_col(&source).column
        ),
        (3, 1)
    );
}

// --- several at once, and rendering ----------------------------------------------------

#[test]
fn several_errors_are_reported_in_one_run() {
    let source = "coordinates theta\nframe N\npoint P = thta*N.x\npiont Q = theta*N.x\nparticle P mass N.x\n\
                  frame B = N rotated theta about w\nconstraint theta\n";
    let found = diagnostics(source);
    let codes: Vec<&str> = found.iter().map(|d| d.kind.code()).collect();
    // `P` failed to define, so its particle's only new error is the vector mass.
    assert_eq!(
        codes,
        ["E101", "E003", "E201", "E110", "E302"],
        "{found:#?}"
    );
}

#[test]
fn a_broken_declaration_does_not_cascade() {
    let source =
        "coordinates x, y,\nframe N\npoint P = x*N.x + y*N.y\nparticle P mass 1\npoint Q = z*N.x\n";
    let found = diagnostics(source);
    let codes: Vec<&str> = found.iter().map(|d| d.kind.code()).collect();
    // The syntax error, and the genuinely unknown `z`; not `x` and `y`, nor "no coordinates".
    assert_eq!(codes, ["E002", "E101"], "{found:#?}");
    assert_eq!(found[1].message(), "unknown name `z`");
}

#[test]
fn rendering_shows_file_line_column_underline_and_help() {
    let source = "coordinates theta\nframe N\npoint P = thta*N.x\n";
    let errors = model::load(source).unwrap_err();
    let text = model::render(
        &errors.0,
        "pendulum.lag",
        source,
        RenderOptions::default().with_unicode(false),
    );
    let expected = "[E101] Error: unknown name `thta`
   ,-[ pendulum.lag:3:11 ]
   |
 3 | point P = thta*N.x
   |           ^^|^
   |             `--- not declared
   |
   | Help: Did you mean `theta`?
---'
";
    let trimmed: String = text
        .lines()
        .map(str::trim_end)
        .collect::<Vec<_>>()
        .join("\n")
        + "\n";
    assert_eq!(trimmed, expected);
    let short = model::render_short(&errors.0, "pendulum.lag", source);
    assert_eq!(
        short,
        "pendulum.lag:3:11: error[E101]: unknown name `thta` (help: Did you mean `theta`?)\n"
    );
}

// --- warnings ---------------------------------------------------------------------------

#[test]
fn w001_w002_unused_coordinate_and_parameter() {
    let source =
        "coordinates x, q\nparameters m = 1, k = 2\nframe N\npoint P = x*N.x\nparticle P mass m\n";
    let model = model::load(source).expect("warnings do not make a model invalid");
    let warnings = model.warnings();
    assert_eq!(warnings.len(), 2);
    assert_eq!(warnings[0].kind.code(), "W001");
    assert_eq!(warnings[0].message(), "coordinate `q` is never used");
    assert_eq!(
        (
            warnings[0].line_col(source).line,
            warnings[0].line_col(source).column
        ),
        (1, 16)
    );
    assert!(!warnings[0].is_error());
    assert_eq!(warnings[1].message(), "parameter `k` is never used");
    assert_eq!(
        (
            warnings[1].line_col(source).line,
            warnings[1].line_col(source).column
        ),
        (2, 19)
    );
}

#[test]
fn outputs_name_energies_and_reactions() {
    let source =
        "coordinates x, y\nparameters l = 1\nframe N\npoint P = x*N.x + y*N.y\nparticle P mass 1\n\
                  constraint rod: x^2 + y^2 = l^2\noutput energy, rod, speed = norm(P), x'\n";
    let model = model::load(source).expect("valid");
    let quantities: Vec<&model::Quantity> = model.outputs().iter().map(|o| &o.quantity).collect();
    assert!(matches!(quantities[0], model::Quantity::Energy));
    assert!(matches!(quantities[1], model::Quantity::Reaction(_)));
    assert!(matches!(quantities[2], model::Quantity::Expr(_)));
    let labels: Vec<&str> = model.outputs().iter().map(|o| o.label.as_str()).collect();
    assert_eq!(labels, ["energy", "rod", "speed", "x'"]);
}
