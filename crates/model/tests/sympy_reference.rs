//! Mass matrix and forcing against independent SymPy `LagrangesMethod` data
//! (`tests/data/eom/*.json`, written by `tools/sympy_reference`), at every sample.

use cas::{Symbol, SymbolKind};
use serde_json::Value;

fn env_of(values: &serde_json::Map<String, Value>) -> impl Fn(Symbol) -> Option<f64> + '_ {
    move |s: Symbol| {
        let key = match s.kind() {
            SymbolKind::Time => "t".to_string(),
            SymbolKind::TimeFunction { order: 1 } => format!("{}_d", s.name()),
            SymbolKind::TimeFunction { order: 2 } => format!("{}_dd", s.name()),
            _ => s.name().to_string(),
        };
        values.get(&key).and_then(Value::as_f64)
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-8 * (1.0 + a.abs().max(b.abs()))
}

#[test]
fn equations_match_sympy_reference_data() {
    let root = format!("{}/../..", env!("CARGO_MANIFEST_DIR"));
    let Ok(entries) = std::fs::read_dir(format!("{root}/tests/data/eom")) else {
        return;
    };
    let mut checked = 0;
    for entry in entries.flatten() {
        let path = entry.path();
        if path.extension().and_then(|e| e.to_str()) != Some("json") {
            continue;
        }
        let data: Value =
            serde_json::from_str(&std::fs::read_to_string(&path).expect("read")).expect("json");
        let model_path = data["model"].as_str().expect("model path");
        let text = std::fs::read_to_string(format!("{root}/{model_path}")).expect("model file");
        let model = model::load(&text).expect("loads");
        let system = model::lower(&model).expect("lowers");
        let eq = mechanics::derive(&system).expect("derives");
        let coordinates: Vec<String> = data["coordinates"]
            .as_array()
            .expect("coordinates")
            .iter()
            .filter_map(|c| c.as_str().map(String::from))
            .collect();
        assert_eq!(eq.coordinates(), coordinates.as_slice(), "{model_path}");
        for sample in data["samples"].as_array().expect("samples") {
            let values = sample["values"].as_object().expect("values");
            let env = env_of(values);
            for (i, row) in eq.mass_matrix().iter().enumerate() {
                for (j, entry) in row.iter().enumerate() {
                    let want = sample["mass_matrix"][i][j].as_f64().expect("number");
                    let got = entry.eval(&env).expect("evaluates");
                    assert!(
                        close(got, want),
                        "{model_path}: M[{i}][{j}] = {got}, want {want}"
                    );
                }
            }
            for (i, f) in eq.forcing().iter().enumerate() {
                let want = sample["forcing"][i].as_f64().expect("number");
                let got = f.eval(&env).expect("evaluates");
                assert!(
                    close(got, want),
                    "{model_path}: f[{i}] = {got}, want {want}"
                );
            }
        }
        checked += 1;
    }
    assert!(checked > 0);
}
