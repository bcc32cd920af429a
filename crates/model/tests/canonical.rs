//! The canonical model files under `examples/canonical/` and the systems built in code by
//! `mechanics::canonical` are the same systems: the lowered file and the code give the same
//! coordinates, energies, equations, constraints and eliminations (exact equality), and the
//! same parameter values (by number).

use cas::Expr;
use mechanics::{canonical, derive, Equations};

fn lowered(name: &str) -> mechanics::System {
    let path = format!(
        "{}/../../examples/canonical/{name}.lag",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let model = model::load(&text).unwrap_or_else(|e| panic!("{path}: {e:?}"));
    model::lower(&model).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn same(what: &str, name: &str, a: Expr, b: Expr) {
    assert!(a.equals(b), "{name}: {what}: file {a}, code {b}");
}

fn same_rows(what: &str, name: &str, a: &[Vec<Expr>], b: &[Vec<Expr>]) {
    assert_eq!(a.len(), b.len(), "{name}: {what} rows");
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert_eq!(x.len(), y.len(), "{name}: {what} row {i}");
        for (j, (p, q)) in x.iter().zip(y).enumerate() {
            same(&format!("{what}[{i}][{j}]"), name, *p, *q);
        }
    }
}

fn same_equations(name: &str, file: &Equations, code: &Equations) {
    assert_eq!(
        file.coordinates(),
        code.coordinates(),
        "{name}: coordinates"
    );
    same("K", name, file.kinetic_energy(), code.kinetic_energy());
    same("V", name, file.potential_energy(), code.potential_energy());
    same_rows("M", name, file.mass_matrix(), code.mass_matrix());
    for (i, (a, b)) in file.forcing().iter().zip(code.forcing()).enumerate() {
        same(&format!("f[{i}]"), name, *a, *b);
    }
    let (qf, qc) = (file.generalized_forces(), code.generalized_forces());
    assert_eq!(qf.len(), qc.len(), "{name}: generalized forces");
    for (i, (a, b)) in qf.iter().zip(qc).enumerate() {
        same(&format!("Q[{i}]"), name, *a, *b);
    }
    same_rows(
        "A",
        name,
        file.constraint_matrix(),
        code.constraint_matrix(),
    );
    for (i, (a, b)) in file
        .constraint_rhs()
        .iter()
        .zip(code.constraint_rhs())
        .enumerate()
    {
        same(&format!("b[{i}]"), name, *a, *b);
    }
    assert_eq!(file.constraint_names(), code.constraint_names(), "{name}");
    assert_eq!(file.eliminated().len(), code.eliminated().len(), "{name}");
    for (a, b) in file.eliminated().iter().zip(code.eliminated()) {
        assert_eq!(a.coordinate, b.coordinate, "{name}");
        same("elimination", name, a.value, b.value);
    }
    let kinds =
        |e: &Equations| -> Vec<&str> { e.first_integrals().iter().map(|f| f.kind).collect() };
    assert_eq!(kinds(file), kinds(code), "{name}: first integrals");
}

#[test]
fn model_files_give_the_code_built_equations() {
    for c in canonical::all() {
        let file_system = lowered(c.name);
        let file = derive(&file_system).unwrap_or_else(|e| panic!("{}: {e}", c.name));
        let code = derive(&c.system).unwrap_or_else(|e| panic!("{}: {e}", c.name));
        same_equations(c.name, &file, &code);
        // The same parameters with the same values.
        let values = |s: &mechanics::System| -> Vec<(String, f64)> {
            s.parameters()
                .iter()
                .map(|(n, v)| {
                    let v = v.expect("a value").eval(&|_| None).expect("a constant");
                    (n.clone(), v)
                })
                .collect()
        };
        let (a, b) = (values(&file_system), values(&c.system));
        assert_eq!(a.len(), b.len(), "{}: parameters", c.name);
        for ((na, va), (nb, vb)) in a.iter().zip(&b) {
            assert_eq!(na, nb, "{}", c.name);
            assert!((va - vb).abs() <= 1e-15 * va.abs(), "{}: {na}", c.name);
        }
        let inputs = |s: &mechanics::System| -> Vec<String> {
            s.inputs().iter().map(|(n, _)| n.clone()).collect()
        };
        assert_eq!(inputs(&file_system), inputs(&c.system), "{}", c.name);
    }
}

/// The model files' initial states are the code's (so a simulation of either starts alike).
#[test]
fn model_files_start_where_the_code_does() {
    for c in canonical::all() {
        let path = format!(
            "{}/../../examples/canonical/{}.lag",
            env!("CARGO_MANIFEST_DIR"),
            c.name
        );
        let text = std::fs::read_to_string(&path).expect("readable");
        let model = model::load(&text).expect("loads");
        for (name, x, v) in &c.initial {
            let given = |rate: bool| -> f64 {
                model
                    .initial()
                    .iter()
                    .find(|i| i.rate == rate && model.coordinate(i.coordinate).name.name == *name)
                    .map_or(0.0, |i| {
                        model.evaluate_constant(&i.value).expect("a constant value")
                    })
            };
            assert!((given(false) - x).abs() < 1e-12, "{}: {name}", c.name);
            assert!((given(true) - v).abs() < 1e-12, "{}: {name}'", c.name);
        }
    }
}
