//! Output files named by a user (`lagrange::output`): a format read from the file name or a
//! typed error naming the formats; a solution's directory made and every file it will hold
//! checked before any work, the model never among them; a drawing's state with its time read
//! from `NAME=VALUE` items; an equilibrium asked for by an index that is not there.

use std::path::{Path, PathBuf};

use lagrange::{Analysis, Error, ErrorKind, Figures, FileFormat, Output};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// A fresh directory of its own under the target directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("output-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

#[test]
fn a_file_format_comes_from_the_extension_in_any_case() {
    let of = |name: &str, output| FileFormat::of(Path::new(name), output);
    assert_eq!(of("a.svg", Output::Figure).unwrap(), FileFormat::Svg);
    assert_eq!(of("a.PNG", Output::Figure).unwrap(), FileFormat::Png);
    assert_eq!(of("b.Html", Output::Animation).unwrap(), FileFormat::Html);
    let error = of("a.pdf", Output::Figure).unwrap_err();
    assert_eq!(error.kind(), ErrorKind::Input);
    assert_eq!(
        error.to_string(),
        "`a.pdf`: a figure is written as SVG or PNG; give a file name ending in .svg or .png"
    );
    let error = of("movie.svg", Output::Animation).unwrap_err();
    assert!(matches!(error, Error::FileFormat { .. }), "{error:?}");
    assert!(error.to_string().contains("ending in .html"), "{error}");
}

#[test]
fn a_solution_directory_is_made_and_its_files_checked_before_any_work() {
    let dir = scratch("solution").join("nested");
    let model = example("simple-pendulum.lag");
    let (figures, replaced) = Figures::prepare(&dir, &model, "tex").unwrap();
    assert!(dir.is_dir());
    assert!(replaced.is_empty());
    // pdflatex cannot include SVG: a LaTeX solution's figures are PNG.
    assert_eq!(figures.extension, "png");
    assert_eq!(figures.stem, "simple-pendulum");
    assert_eq!(figures.report_file("tex"), dir.join("simple-pendulum.tex"));
    std::fs::write(dir.join("simple-pendulum.md"), "old").unwrap();
    let (figures, replaced) = Figures::prepare(&dir, &model, "md").unwrap();
    assert_eq!(figures.extension, "svg");
    assert_eq!(replaced, vec![dir.join("simple-pendulum.md")]);
}

#[test]
fn a_solution_is_never_written_over_its_model() {
    let dir = scratch("over-model");
    std::fs::create_dir_all(&dir).unwrap();
    let model = dir.join("m.md");
    std::fs::write(&model, "coordinates x\n").unwrap();
    let error = Figures::prepare(&dir, &model, "md").unwrap_err();
    assert!(matches!(error, Error::OverwritesInput { .. }), "{error:?}");
    assert_eq!(std::fs::read_to_string(&model).unwrap(), "coordinates x\n");
}

#[test]
fn a_state_sets_values_and_reads_the_time_as_a_constant_expression() {
    let mut analysis = Analysis::from_file(&example("simple-pendulum.lag")).unwrap();
    let items = ["theta=pi/6".to_owned(), "t=pi/4".to_owned()];
    let time = analysis.set_state(&items).unwrap();
    assert!((time - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
    assert_eq!(analysis.set_state(&[]).unwrap(), 0.0);
    let error = analysis.set_state(&["nope=1".to_owned()]).unwrap_err();
    assert!(
        matches!(&error, Error::Refused { item, .. } if item == "nope=1"),
        "{error:?}"
    );
    assert_eq!(error.kind(), ErrorKind::Input);
    assert!(
        error
            .to_string()
            .starts_with("nope=1: `nope` is not a parameter"),
        "{error}"
    );
    // `t` is a time for a drawing, never a value of the model.
    let error = analysis.set_texts(&["t=1".to_owned()]).unwrap_err();
    assert!(
        matches!(&error, Error::Refused { item, .. } if item == "t=1"),
        "{error:?}"
    );
}

#[test]
fn an_equilibrium_index_beyond_the_list_is_a_typed_input_error() {
    let analysis = Analysis::from_file(&example("simple-pendulum.lag")).unwrap();
    let found = analysis.equilibria().unwrap();
    let count = found.set.equilibria.len();
    assert!(count >= 2, "a pendulum rests hanging and upright");
    assert!(found.check_index(count - 1).is_ok());
    let error = found.check_index(count).unwrap_err();
    assert_eq!(error.kind(), ErrorKind::Input);
    assert!(
        matches!(error, Error::NoSuchEquilibrium { index, count: c } if index == count && c == count),
        "{error:?}"
    );
}
