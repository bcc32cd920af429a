//! Every example's solution as LaTeX spells each character of its prose in a way `pdflatex`
//! knows: no character falls back to `?` (a precomposed `ẋ`, `ŷ`, `Ṙ`, a superscript `⁵`
//! once did). Compiling with `pdflatex` itself is `tools/latex/check.sh`, run in CI.

use std::path::{Path, PathBuf};

use lagrange::Analysis;

fn examples() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut files = Vec::new();
    for dir in [root.clone(), root.join("seed")] {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "lag") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

#[test]
fn no_character_of_any_example_falls_back_to_a_question_mark() {
    // The slow models (many reactions) are covered by the seed and the small ones.
    for path in examples() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if name == "four-bar.lag" {
            continue;
        }
        let analysis = Analysis::from_file(&path).unwrap();
        let Ok(solution) = analysis.solution(None) else {
            continue;
        };
        let tex = solution.document.to_latex();
        for (n, line) in tex.lines().enumerate() {
            assert!(!line.contains('?'), "{name}, line {}: {line}", n + 1);
            assert!(
                line.chars()
                    .all(|c| c.is_ascii()
                        || (('\u{c0}'..='\u{17f}').contains(&c) && c.is_alphabetic())),
                "{name}, line {}: a character outside what T1 and inputenc read: {line}",
                n + 1
            );
        }
    }
}
