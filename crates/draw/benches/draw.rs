//! How long drawing each example takes: `cargo bench -p lagrange-draw --bench draw`.
//! The model is loaded once; each sample builds the scene and writes the SVG.

use std::path::{Path, PathBuf};

fn main() {
    divan::main();
}

fn examples() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut files = Vec::new();
    let mut stack = vec![root];
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "lag") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

const NAMES: &[&str] = &[
    "seed/7.1-cart-pendulum",
    "seed/7.2-rolling-cone",
    "seed/7.3-gears-pendulum",
    "seed/7.4-inverted-pendulum",
    "double-pendulum",
    "four-bar",
    "heavy-symmetric-top",
    "spring-chain",
];

#[divan::bench(args = NAMES)]
fn draw(bencher: divan::Bencher, name: &str) {
    let path = examples()
        .into_iter()
        .find(|p| p.to_string_lossy().ends_with(&format!("{name}.lag")))
        .expect("the example exists");
    let text = std::fs::read_to_string(path).expect("readable");
    let model = model::load(&text).expect("a valid example");
    let at = draw::Configuration {
        time: 0.0,
        coordinates: model
            .coordinates()
            .iter()
            .enumerate()
            .map(|(k, _)| {
                model
                    .initial()
                    .iter()
                    .find(|i| i.coordinate.index() == k && !i.rate)
                    .and_then(|i| match i.value.kind {
                        model::ExprKind::Number { value, .. } => Some(value),
                        _ => None,
                    })
                    .unwrap_or(0.0)
            })
            .collect(),
    };
    bencher.bench(|| draw::figure(&model, at.clone()).expect("drawn"));
}
