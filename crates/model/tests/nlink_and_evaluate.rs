//! The n-link pendulum, written as a model file for n = 1…10, against the closed form
//! `M_ij = μ_ij l_i l_j cos(θ_i − θ_j)`,
//! `f_i = −Σ_j μ_ij l_i l_j sin(θ_i − θ_j) θ̇_j² − μ_ii g l_i sin θ_i`, `μ_ij = Σ_{k ≥ max(i,j)} m_k`;
//! and the lowering of every example's particle positions against `Model::evaluate` at
//! random states.

use cas::{Expr, Symbol, SymbolKind};

fn nlink_model(n: usize) -> String {
    let mut text = String::from("coordinates ");
    let names: Vec<String> = (1..=n).map(|i| format!("th{i}")).collect();
    text += &names.join(", ");
    text += "\nparameters g";
    for i in 1..=n {
        text += &format!(", m{i}, l{i}");
    }
    text += "\nframe N\n";
    for i in 1..=n {
        let previous = if i == 1 {
            String::new()
        } else {
            format!("P{} + ", i - 1)
        };
        text += &format!("point P{i} = {previous}l{i}*sin(th{i})*N.x - l{i}*cos(th{i})*N.y\n");
        text += &format!("particle P{i} mass m{i}\n");
    }
    text += "gravity -g*N.y\n";
    text
}

#[test]
fn nlink_matches_the_closed_form() {
    for n in 1..=10 {
        let model = model::load(&nlink_model(n)).expect("generated model loads");
        let system = model::lower(&model).expect("lowers");
        let eq = mechanics::derive(&system).expect("derives");
        let th: Vec<Expr> = (1..=n)
            .map(|i| Expr::coordinate(&format!("th{i}")))
            .collect();
        let thd: Vec<Expr> = (1..=n).map(|i| Expr::rate(&format!("th{i}"), 1)).collect();
        let m: Vec<Expr> = (1..=n).map(|i| Expr::symbol(&format!("m{i}"))).collect();
        let l: Vec<Expr> = (1..=n).map(|i| Expr::symbol(&format!("l{i}"))).collect();
        let g = Expr::symbol("g");
        let mu = |i: usize, j: usize| (i.max(j)..n).map(|k| m[k]).sum::<Expr>();
        for i in 0..n {
            for j in 0..n {
                let want = mu(i, j) * l[i] * l[j] * (th[i] - th[j]).cos();
                assert!(eq.mass_matrix()[i][j].equals(want), "n = {n}: M[{i}][{j}]");
            }
            let want = -(0..n)
                .map(|j| mu(i, j) * l[i] * l[j] * (th[i] - th[j]).sin() * thd[j].powi(2))
                .sum::<Expr>()
                - mu(i, i) * g * l[i] * th[i].sin();
            assert!(eq.forcing()[i].equals(want), "n = {n}: f[{i}]");
        }
        // Conservative and time-free: the energy K + V is a first integral for every n.
        let energy = eq
            .first_integrals()
            .iter()
            .find(|f| f.coordinate.is_none())
            .expect("an energy integral");
        assert_eq!(energy.kind, "energy");
        assert!(energy
            .value
            .equals(eq.kinetic_energy() + eq.potential_energy()));
    }
}

/// A small deterministic generator (xorshift), so the test needs no dependency.
fn uniform(seed: &mut u64) -> f64 {
    *seed ^= *seed << 13;
    *seed ^= *seed >> 7;
    *seed ^= *seed << 17;
    (*seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

#[test]
fn lowered_positions_agree_with_model_evaluate() {
    let root = format!("{}/../..", env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["examples", "examples/seed"] {
        for entry in std::fs::read_dir(format!("{root}/{dir}"))
            .expect("examples")
            .flatten()
        {
            if entry.path().extension().and_then(|e| e.to_str()) == Some("lag") {
                files.push(entry.path());
            }
        }
    }
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    for path in files {
        let model = model::load(&std::fs::read_to_string(&path).expect("read")).expect("loads");
        let system = model::lower(&model).expect("lowers");
        let names: Vec<String> = model
            .coordinates()
            .iter()
            .map(|c| c.name.name.clone())
            .collect();
        for _ in 0..3 {
            let q: Vec<f64> = names.iter().map(|_| uniform(&mut seed)).collect();
            let qd: Vec<f64> = names.iter().map(|_| uniform(&mut seed)).collect();
            let time = uniform(&mut seed).abs();
            let state = model::State {
                time,
                coordinates: &q,
                rates: &qd,
            };
            let env = |s: Symbol| -> Option<f64> {
                match s.kind() {
                    SymbolKind::Time => Some(time),
                    SymbolKind::TimeFunction { order } => {
                        let k = names.iter().position(|n| n == s.name())?;
                        match order {
                            0 => Some(q[k]),
                            1 => Some(qd[k]),
                            _ => None,
                        }
                    }
                    _ => model
                        .parameters()
                        .iter()
                        .find(|p| p.name.name == s.name())
                        .and_then(|p| p.value.as_ref())
                        .and_then(|v| model.evaluate(v, &state).ok())
                        .and_then(model::Value::scalar)
                        .or_else(|| {
                            let input = model.inputs().iter().find(|i| i.name.name == s.name())?;
                            model.evaluate(input.value.as_ref()?, &state).ok()?.scalar()
                        }),
                }
            };
            for (particle, lowered) in model.particles().iter().zip(system.particles()) {
                let point = model::Expr {
                    kind: model::ExprKind::Point(particle.point),
                    span: particle.span,
                    ty: model::Type::Vector,
                };
                let Ok(model::Value::Vector(want)) = model.evaluate(&point, &state) else {
                    panic!("{}: the point does not evaluate", path.display());
                };
                #[allow(clippy::needless_range_loop)]
                // k indexes both the lowered and the evaluated vector.
                for k in 0..3 {
                    let got = lowered.position[k].eval(&env).expect("evaluates");
                    assert!(
                        (got - want[k]).abs() <= 1e-9 * (1.0 + want[k].abs()),
                        "{}: {} component {k}: {got} vs {}",
                        path.display(),
                        lowered.name,
                        want[k]
                    );
                }
            }
        }
    }
}
