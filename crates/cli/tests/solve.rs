//! `lagrange solve`: the report in each format, `--out`, and the committed solutions of the
//! seed's exercises (`examples/seed/*.md`), which must match what the code writes today.
//! Regenerate them with `LAGRANGE_BLESS=1 cargo test -p lagrange-cli --test solve`.

use std::path::{Path, PathBuf};

mod common;
use common::{lagrange, root, stdout};

#[test]
fn the_text_report_follows_the_course() {
    let o = lagrange(&["solve", "examples/seed/7.1-cart-pendulum.lag"]);
    assert!(o.status.success());
    let text = stdout(&o);
    let order = [
        "The system",
        "Kinematics",
        "Lagrangian function",
        "Lagrange equations (II type)",
        "First integrals",
    ];
    let positions: Vec<usize> = order
        .iter()
        .map(|t| {
            text.find(&format!("{t}\n"))
                .unwrap_or_else(|| panic!("no `{t}` in\n{text}"))
        })
        .collect();
    assert!(positions.windows(2).all(|w| w[0] < w[1]), "{text}");
    assert!(text.contains("  ∂ℒ/∂ẋ = (m_A + m_B) ẋ + m_B ℓ θ̇ cos θ"));
    assert!(text.contains("  (m_A + m_B) ẍ + m_B ℓ θ̈ cos θ − m_B ℓ θ̇² sin θ + k x = F"));
    assert!(text.contains("  m_B ℓ (ℓ θ̈ + ẍ cos θ + g sin θ) = C"));
    assert!(text.contains(
        "Inputs (given functions of time, held at these values unless set): F = 0, C = 0."
    ));
    // The reactions the model asks for, by both methods, after the equations of motion.
    let reactions = text
        .find("Constraint reactions\n")
        .expect("a reactions section");
    assert!(reactions > positions[4]);
    assert!(text.contains("hinge_A — hinge at A, on B:"));
    assert_eq!(
        text.matches("Methods: lagrange_1, newton_euler — agree exactly")
            .count(),
        2,
        "{text}"
    );
    assert!(
        text.lines().all(|l| l.chars().count() <= 80),
        "a line is wider than 80 columns:\n{text}"
    );
}

#[test]
fn the_seed_equations_print_in_the_seed_notation() {
    // 7.3: the gear ratio r = R1/R2 is a named constant; the seed writes (I1 + I2 r²) φ̈1.
    let o = lagrange(&["solve", "examples/seed/7.3-gears-pendulum.lag"]);
    assert!(o.status.success());
    let text = stdout(&o);
    assert!(text.contains("  (I1 + I2 r²) φ̈1 = C − F R1\n"), "{text}");
    assert!(text.contains("  φ̈1 = (C − F R1)/(I1 + I2 r²)\n"), "{text}");
    // 7.2: Ĩ θ̈ + m g b sin θ = 0, with b = d cos² α and Ĩ = m b² + I_x (b/R)² + I_z cos² α
    // (here with I_y ≠ I_z, so the spin-dependent term is there too).
    let o = lagrange(&["solve", "examples/seed/7.2-rolling-cone.lag"]);
    assert!(o.status.success());
    let text = stdout(&o);
    assert!(text.contains("  U = m b g cos θ\n"), "{text}");
    assert!(
        text.contains("(m b² + I_y cos² α + I_x cos⁴ α/sin² α) θ̈"),
        "{text}"
    );
    assert!(text.contains("+ m b g sin θ = 0\n"), "{text}");
    assert!(
        text.contains("  r_C = b cos θ x̂ + b sin θ ŷ − h ẑ\n"),
        "{text}"
    );
}

#[test]
fn the_free_response_starts_from_the_initial_state_and_follows_the_modes() {
    // 7.1 starts at x = 0.1, θ = 0.3 at rest; about the stable equilibrium (0, 0) the free
    // response is a sum of the two modes' cosines, whose coefficients add up to the start.
    let o = lagrange(&["solve", "examples/seed/7.1-cart-pendulum.lag"]);
    assert!(o.status.success());
    let text = stdout(&o);
    let start = text.find("Free response").expect("a free response");
    let line = |name: &str| -> Vec<(f64, f64)> {
        let line = text[start..]
            .lines()
            .find(|l| l.trim_start().starts_with(&format!("δ{name}(t) = ")))
            .unwrap_or_else(|| panic!("no δ{name}(t) in\n{text}"));
        // Terms `± c cos(ω t)`.
        let rhs = line.split(" = ").nth(1).expect("a right-hand side");
        rhs.replace(" − ", " + -")
            .split(" + ")
            .map(|term| {
                let term = term.trim().replace('−', "-");
                let (c, wave) = term.split_once(" cos(").expect("a cosine term");
                let w = wave.trim_end_matches(" t)");
                (
                    c.parse().expect("a number"),
                    w.parse().expect("a frequency"),
                )
            })
            .collect()
    };
    let (x, theta) = (line("x"), line("θ"));
    let sum = |terms: &[(f64, f64)]| terms.iter().map(|(c, _)| c).sum::<f64>();
    assert!((sum(&x) - 0.1).abs() < 1e-3, "{x:?}");
    assert!((sum(&theta) - 0.3).abs() < 1e-3, "{theta:?}");
    // The frequencies are the natural frequencies the section states.
    for (_, w) in x.iter().chain(&theta) {
        assert!(text.contains(&format!("ω = {w}")), "ω = {w} not in\n{text}");
    }
    // 7.4 starts 0.05 rad from the upright position, which is unstable: cosh grows.
    let o = lagrange(&["solve", "examples/seed/7.4-inverted-pendulum.lag"]);
    let text = stdout(&o);
    assert!(text.contains("  δθ(t) = 0.05000 cosh("), "{text}");
}

#[test]
fn the_simulation_section_stops_where_a_contact_is_lost() {
    // A particle sliding off a sphere from θ0 = 0.01 leaves it where cos θ = ⅔ cos θ0; past
    // that the model's equations no longer hold, and `solve` stops there as `simulate` does.
    let source = std::fs::read_to_string(root().join("examples/particle-on-sphere.lag"))
        .expect("the example exists");
    let path = std::env::temp_dir().join(format!("lagrange-sphere-{}.lag", std::process::id()));
    std::fs::write(&path, format!("{source}\nsimulate to 10\n")).expect("writes");
    let o = lagrange(&["solve", path.to_str().expect("utf-8")]);
    let _ = std::fs::remove_file(&path);
    assert!(o.status.success());
    let text = stdout(&o);
    assert!(
        text.contains("the one-sided constraint `normal` is lost"),
        "{text}"
    );
    let theta: f64 = text
        .split(": θ = ")
        .nth(1)
        .and_then(|rest| rest.split(',').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no final θ in\n{text}"));
    assert!(
        (theta.cos() - 2.0 / 3.0 * 0.01_f64.cos()).abs() < 1e-5,
        "θ = {theta}"
    );
}

#[test]
fn markdown_latex_and_json_carry_the_equations() {
    let md = stdout(&lagrange(&[
        "solve",
        "examples/seed/7.1-cart-pendulum.lag",
        "--format",
        "md",
    ]));
    assert!(md.starts_with("# Exercise 7.1 — a cart on a spring"));
    assert!(md.contains("## Lagrange equations (II type)"));
    assert_eq!(
        md.matches("$$\n\\begin{aligned}").count(),
        md.matches("\\end{aligned}\n$$").count()
    );
    let tex = stdout(&lagrange(&[
        "solve",
        "examples/seed/7.1-cart-pendulum.lag",
        "--format",
        "tex",
    ]));
    assert!(tex.starts_with("\\documentclass"));
    assert!(tex.trim_end().ends_with("\\end{document}"));
    assert_eq!(
        tex.matches("\\begin{").count(),
        tex.matches("\\end{").count()
    );
    let json = stdout(&lagrange(&[
        "solve",
        "examples/seed/7.1-cart-pendulum.lag",
        "--format",
        "json",
    ]));
    let value: serde_json::Value = serde_json::from_str(&json).expect("valid JSON");
    assert_eq!(value["coordinates"], serde_json::json!(["x", "theta"]));
    // After the model's problem statement and notes, and the system.
    assert_eq!(value["report"]["sections"][3]["title"], "Kinematics");
}

#[test]
fn out_writes_the_report_into_a_directory() {
    let dir = std::env::temp_dir().join(format!("lagrange-solve-{}", std::process::id()));
    let o = lagrange(&[
        "solve",
        "examples/seed/7.4-inverted-pendulum.lag",
        "--format",
        "md",
        "--out",
        dir.to_str().expect("utf-8 temp dir"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let written = std::fs::read_to_string(dir.join("7.4-inverted-pendulum.md")).expect("written");
    assert!(written.contains("## Kinematics"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_singular_model_is_an_error_with_a_non_zero_exit() {
    let path = std::env::temp_dir().join(format!("lagrange-singular-{}.lag", std::process::id()));
    std::fs::write(
        &path,
        "coordinates x, y\nparameters m = 1\nframe N\npoint P = (x + y)*N.x\nparticle P mass m\n",
    )
    .expect("written");
    let o = lagrange(&["solve", path.to_str().expect("utf-8")]);
    let _ = std::fs::remove_file(&path);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("mass matrix is singular"), "{err}");
}

#[test]
fn the_committed_seed_solutions_are_up_to_date() {
    let bless = std::env::var_os("LAGRANGE_BLESS").is_some();
    let seed = root().join("examples/seed");
    let mut models: Vec<PathBuf> = std::fs::read_dir(&seed)
        .expect("examples/seed")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().and_then(|e| e.to_str()) == Some("lag"))
        .collect();
    models.sort();
    assert_eq!(models.len(), 4);
    let mut stale = Vec::new();
    let scratch = std::env::temp_dir().join(format!("lagrange-seed-{}", std::process::id()));
    for model in models {
        let relative = Path::new("examples/seed").join(model.file_name().expect("a file name"));
        let out = if bless { seed.clone() } else { scratch.clone() };
        let o = lagrange(&[
            "solve",
            relative.to_str().expect("utf-8"),
            "--format",
            "md",
            "--out",
            out.to_str().expect("utf-8"),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let name = model.with_extension("md");
        let name = name.file_name().expect("a file name");
        let written = std::fs::read(out.join(name)).expect("the solution is written");
        // Every seed model simulates, so its plot is written beside the solution.
        let stem = model.file_stem().and_then(|s| s.to_str()).expect("a stem");
        assert!(
            out.join(format!("{stem}-motion.svg")).exists(),
            "{stem}: no plot"
        );
        if !bless && std::fs::read(seed.join(name)).ok() != Some(written) {
            stale.push(seed.join(name).display().to_string());
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    assert!(
        stale.is_empty(),
        "stale solutions (regenerate with LAGRANGE_BLESS=1 cargo test -p lagrange-cli --test solve): {stale:?}"
    );
}

#[test]
fn the_inverted_pendulum_is_unstable_upright_and_controllable() {
    let text = stdout(&lagrange(&[
        "solve",
        "examples/seed/7.4-inverted-pendulum.lag",
    ]));
    let equilibria = text
        .find("Equilibria and their stability\n")
        .expect("an equilibria section");
    let linearized = text
        .find("Linearized dynamics\n")
        .expect("a linearized section");
    assert!(equilibria < linearized);
    assert!(text.contains("  0  any  0.0000      unstable"), "{text}");
    assert!(text.contains("  1  any  π ≈ 3.1416  stable"), "{text}");
    // Upright: λ = ±√(K/M) of the reduced pendulum, 5.2942 for the example's values.
    assert!(text.contains("Eigenvalues of the state matrix A: -5.2942, 0.0000, 0.0000, 5.2942."));
    assert!(text.contains("of rank 4 of 4: controllable from the inputs"));
}

#[test]
fn set_overrides_a_value_for_one_run_in_every_command() {
    // F = 3 moves the cart's equilibrium to x = F/k = 0.1.
    let o = lagrange(&[
        "solve",
        "examples/seed/7.1-cart-pendulum.lag",
        "--set",
        "F=3",
    ]);
    assert!(o.status.success());
    assert!(stdout(&o).contains("  0  F/k ≈ 0.1000"), "{}", stdout(&o));
    // From θ₀ = 0.5 at rest the particle leaves the sphere where cos θ = ⅔ cos 0.5.
    let o = lagrange(&[
        "reactions",
        "examples/particle-on-sphere.lag",
        "--set",
        "theta=0.5",
    ]);
    assert!(o.status.success());
    let want = format!("(cos = {:.6}", 2.0 / 3.0 * 0.5f64.cos());
    assert!(stdout(&o).contains(&want), "{}", stdout(&o));
    // An unknown name is an error that lists what can be set, with exit code 1 (a mistake in the input).
    for command in ["eom", "solve", "reactions"] {
        let o = lagrange(&[
            command,
            "examples/seed/7.1-cart-pendulum.lag",
            "--set",
            "nope=1",
        ]);
        assert_eq!(o.status.code(), Some(1), "{command}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("`nope` is not a parameter"),
            "{command}: {err}"
        );
    }
}
