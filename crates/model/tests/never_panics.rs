//! Property tests: no input makes parsing, checking, summarizing or rendering panic (or hang).
//! Inputs are random token soups and the example files mutated by deleting, inserting and
//! swapping characters. The case count is bounded so the suite runs in seconds; the fuzz
//! target in `fuzz/` runs the same pipeline without a bound.

use std::path::Path;

use proptest::prelude::*;

/// Run the whole front end on `source`, exercising every output.
fn pipeline(source: &str) {
    match model::load(source) {
        Ok(model) => {
            let _ = model.summary().to_string();
            let _ = model::render(
                model.warnings(),
                "m.lag",
                source,
                model::RenderOptions::default(),
            );
            // Evaluate points and outputs at an arbitrary state (the first few: each evaluation
            // walks the whole model, and the long-chain test has 20 000 points).
            let n = model.coordinates().len();
            let (q, rates) = (vec![0.3; n], vec![-0.7; n]);
            let state = model::State {
                time: 1.5,
                coordinates: &q,
                rates: &rates,
            };
            for point in model.points().iter().take(20) {
                if let Some(position) = &point.position {
                    let _ = model.evaluate(position, &state);
                }
            }
            for output in model.outputs().iter().take(20) {
                if let model::Quantity::Expr(value) = &output.quantity {
                    let _ = model.evaluate(value, &state);
                }
            }
            let values = model.require_values();
            let _ = model::render(&values, "m.lag", source, model::RenderOptions::default());
        }
        Err(errors) => {
            assert!(!errors.0.is_empty());
            for diagnostic in &errors.0 {
                assert!(diagnostic.span.start <= diagnostic.span.end);
                assert!(
                    diagnostic.span.end <= source.len(),
                    "{diagnostic:?} outside the source"
                );
            }
            let _ = model::render(&errors.0, "m.lag", source, model::RenderOptions::default());
            let _ = model::render_short(&errors.0, "m.lag", source);
        }
    }
}

fn examples() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut sources = Vec::new();
    for sub in [dir.clone(), dir.join("seed")] {
        for entry in std::fs::read_dir(&sub)
            .expect("examples directory")
            .flatten()
        {
            if entry.path().extension().is_some_and(|e| e == "lag") {
                sources.push(std::fs::read_to_string(entry.path()).expect("readable example"));
            }
        }
    }
    sources.sort();
    sources
}

const FRAGMENTS: &[&str] = &[
    "coordinates",
    "parameters",
    "inputs",
    "constants",
    "driven",
    "frame",
    "point",
    "particle",
    "body",
    "gravity",
    "spring",
    "damper",
    "dissipation",
    "potential",
    "force",
    "couple",
    "generalized",
    "constraint",
    "reactions",
    "initial",
    "simulate",
    "output",
    "rotated",
    "about",
    "then",
    "mass",
    "at",
    "inertia",
    "from",
    "to",
    "on",
    "length",
    "rest",
    "rolling",
    "gear",
    "ratio",
    "x",
    "y",
    "z",
    "theta",
    "N",
    "B",
    "A",
    "origin",
    "t",
    "pi",
    "sin",
    "atan2",
    "dot",
    "cross",
    "norm",
    "m",
    "l",
    "g",
    "0",
    "1.5",
    "2e3",
    ".5",
    "1e999",
    "+",
    "-",
    "*",
    "/",
    "^",
    "**",
    "(",
    ")",
    ",",
    "=",
    ":",
    ".",
    "'",
    "\\",
    "\n",
    " ",
    "#",
    "θ",
    "é",
    "$",
    "\t",
    "xx",
];

#[derive(Clone, Debug)]
enum Mutation {
    Delete(usize),
    Insert(usize, char),
    Swap(usize, usize),
    Duplicate(usize, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        any::<usize>().prop_map(Mutation::Delete),
        (
            any::<usize>(),
            prop_oneof![
                Just('('),
                Just(')'),
                Just('\n'),
                Just('\''),
                Just('.'),
                Just('='),
                Just('-'),
                Just('\\'),
                Just('#'),
                Just('x'),
                Just('é'),
                any::<char>()
            ]
        )
            .prop_map(|(at, c)| Mutation::Insert(at, c)),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::Swap(a, b)),
        (any::<usize>(), 0usize..40).prop_map(|(at, len)| Mutation::Duplicate(at, len)),
    ]
}

fn apply(source: &str, mutations: &[Mutation]) -> String {
    let mut chars: Vec<char> = source.chars().collect();
    for mutation in mutations {
        let n = chars.len().max(1);
        match *mutation {
            Mutation::Delete(at) => {
                if !chars.is_empty() {
                    chars.remove(at % n);
                }
            }
            Mutation::Insert(at, c) => chars.insert(at % (chars.len() + 1), c),
            Mutation::Swap(a, b) => {
                if !chars.is_empty() {
                    chars.swap(a % n, b % n);
                }
            }
            Mutation::Duplicate(at, len) => {
                let start = at % n;
                let end = (start + len).min(chars.len());
                let copy: Vec<char> = chars.get(start..end).unwrap_or(&[]).to_vec();
                chars.splice(start..start, copy);
            }
        }
    }
    chars.into_iter().collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn token_soup_never_panics(parts in prop::collection::vec(prop::sample::select(FRAGMENTS), 0..120)) {
        pipeline(&parts.join(" "));
        pipeline(&parts.concat());
    }

    #[test]
    fn arbitrary_text_never_panics(text in ".{0,300}") {
        pipeline(&text);
    }

    #[test]
    fn mutated_examples_never_panic(
        index in any::<prop::sample::Index>(),
        mutations in prop::collection::vec(mutation(), 1..12),
    ) {
        let sources = examples();
        let source = index.get(&sources);
        pipeline(&apply(source, &mutations));
    }
}

#[test]
fn pathological_inputs() {
    pipeline("");
    pipeline("\n\n\n");
    pipeline(&"(".repeat(100_000));
    pipeline(&")".repeat(100_000));
    pipeline(&format!("gravity {}", "-".repeat(100_000)));
    pipeline(&format!("gravity x{}", "^x".repeat(100_000)));
    pipeline(&format!("gravity {}", "sin(".repeat(100_000)));
    pipeline(&"\\\n".repeat(1000));
    pipeline(
        "coordinates x\nframe N\npoint P = x*N.x\nparticle P mass 1\nsimulate to 1e308 from -1e308",
    );
}

#[test]
fn long_chains_of_definitions_do_not_overflow_or_explode() {
    let n = 20_000;
    let mut source = String::from("coordinates x\nframe N\nparameters a0 = 1\npoint P0 = x*N.x\n");
    for i in 1..n {
        source.push_str(&format!("parameters a{i} = a{} + a{}\n", i - 1, i - 1));
        source.push_str(&format!("point P{i} = P{} + a{i}*N.y\n", i - 1));
        source.push_str(&format!(
            "frame F{i} = {} rotated x about z\n",
            if i == 1 {
                "N".to_string()
            } else {
                format!("F{}", i - 1)
            }
        ));
    }
    source.push_str(&format!("simulate to a{}\n", n - 1));
    pipeline(&source);
}
