//! The "Equilibria and their stability" and "Linearized dynamics" sections of a solution: the
//! rest equations, every equilibrium (exact where the equations allow) with the criterion that
//! decided its stability, then `M0 δq̈ + C0 δq̇ + K0 δq = B0 δu` about each one with its natural
//! frequencies and modes.

use cas::print::to_unicode;
use cas::Expr;
use mechanics::equilibria::{Equilibrium, EquilibriumSet, RestEquations};
use mechanics::linearize::Linearized;
use mechanics::stability_condition::StabilityCondition;

use crate::document::{push_sign, Block, Cell, Equation, Math, Notation, Section};
use crate::equilibria::{free_response_waves, stability_word, LinearizedResult, Wave};

/// Both sections.
#[must_use]
pub fn equilibria_sections(
    rest: &RestEquations,
    set: &EquilibriumSet,
    lin: &[LinearizedResult],
    notation: &Notation,
    initial: Option<&InitialState>,
) -> Vec<Section> {
    vec![
        equilibria_section(rest, set, lin, notation),
        linearized_section(rest, set, lin, notation, initial),
    ]
}

fn coordinate(q: &str) -> Math {
    Math::expr(Expr::coordinate(q))
}

fn equilibria_section(
    rest: &RestEquations,
    set: &EquilibriumSet,
    lin: &[LinearizedResult],
    notation: &Notation,
) -> Section {
    let mut s = Section::new("Equilibria and their stability", 2);
    s.paragraph(format!(
        "Rest states: q̇ = 0, q̈ = 0 with the inputs held at their values, so {} — {}.",
        if rest.constraints.is_some() {
            "f(q, 0) − A(q)ᵀλ = 0 and Φ(q) = 0, for q and the multipliers λ"
        } else {
            "f(q, 0) = 0"
        },
        if set.method.complete() {
            match set.method {
                mechanics::equilibria::Method::Exact => {
                    "solved exactly; the list is complete".to_string()
                }
                m => format!("solved by {}; the list is complete", m.name()),
            }
        } else {
            format!(
                "solved numerically ({}); completeness is not guaranteed",
                set.method.name()
            )
        }
    ));
    s.equations(
        rest.coordinates
            .iter()
            .zip(&rest.residuals)
            .map(|(q, r)| {
                Equation::new(
                    Math::label(
                        format!("0 (eq. of {})", coordinate(q).unicode),
                        "0".to_string(),
                    ),
                    notation.math(*r),
                )
            })
            .chain(rest.constraints.iter().flat_map(|kept| {
                kept.names
                    .iter()
                    .zip(&kept.multipliers)
                    .zip(&kept.functions)
                    .map(|((name, lambda), f)| {
                        let lambda = notation.math(*lambda).unicode;
                        Equation::new(
                            Math::label(
                                format!("0 (constraint {name}, {lambda})"),
                                "0".to_string(),
                            ),
                            notation.math(*f),
                        )
                    })
            }))
            .collect(),
    );
    if set.equilibria.is_empty() {
        s.paragraph("No equilibrium for these parameter values.");
        return s;
    }
    s.blocks.push(equilibria_table(rest, set, lin, notation));
    for (i, (e, l)) in set.equilibria.iter().zip(lin).enumerate() {
        if let Some(sentence) = stability_sentence(i, e, l, notation) {
            s.paragraph(sentence);
        }
    }
    s
}

/// The table of equilibria: values (exact ones with their numbers) and a stability word.
fn equilibria_table(
    rest: &RestEquations,
    set: &EquilibriumSet,
    lin: &[LinearizedResult],
    notation: &Notation,
) -> Block {
    let mut header = vec!["#".to_string()];
    header.extend(rest.coordinates.iter().map(|q| coordinate(q).unicode));
    if let Some(kept) = &rest.constraints {
        header.extend(
            kept.names
                .iter()
                .zip(&kept.multipliers)
                .map(|(name, l)| format!("{} ({name})", notation.math(*l).unicode)),
        );
    }
    header.push("stability".to_string());
    let rows: Vec<Vec<Cell>> = set
        .equilibria
        .iter()
        .zip(lin)
        .enumerate()
        .map(|(i, (e, l))| {
            let mut row = vec![Cell::Text(i.to_string())];
            for (k, v) in e.values.iter().enumerate() {
                let free = rest.free.get(k).copied().unwrap_or(false);
                let exact = e.exact.as_ref().and_then(|x| x.get(k)).copied();
                row.push(match (free, exact) {
                    (true, _) => Cell::Text("any".into()),
                    (false, Some(x)) if x.as_number().is_none() => {
                        let m = notation.math(x);
                        Cell::Math(Math::label(
                            format!("{} ≈ {v:.4}", m.unicode),
                            format!(r"{} \approx {v:.4}", m.latex),
                        ))
                    }
                    _ => Cell::Math(Math::label(format!("{v:.4}"), format!("{v:.4}"))),
                });
            }
            for v in &e.multipliers {
                row.push(Cell::Math(Math::label(
                    format!("{v:.4}"),
                    format!("{v:.4}"),
                )));
            }
            match l {
                // The criterion and its reasoning follow the table.
                Ok(l) => row.push(Cell::Text(stability_word(l.stable).into())),
                Err(_) => row.push(Cell::Text("not decided".into())),
            }
            row
        })
        .collect();
    Block::Table { header, rows }
}

/// The criterion that decided equilibrium `i`'s stability, and when it exists.
fn stability_sentence(
    i: usize,
    e: &Equilibrium,
    l: &LinearizedResult,
    notation: &Notation,
) -> Option<String> {
    let mut sentence = String::new();
    match l {
        Ok(l) => sentence.push_str(&format!("Equilibrium {i}: {}.", l.criterion)),
        Err(err) => sentence.push_str(&format!("Equilibrium {i}: stability not decided: {err}.")),
    }
    // Conditions that hold for positive parameters are left out (docs/solve.md).
    let conditions = notation.conditions(&e.conditions);
    if !conditions.is_empty() {
        sentence.push_str(&format!(
            " It exists only when {}.",
            conditions.join(" and ")
        ));
    }
    (!sentence.is_empty()).then(|| sentence.trim_start().to_string())
}

/// A matrix for the terminal: one row a line, the columns aligned, in tall brackets
/// (`⎡3    0.5 ⎤` over `⎣0.5  0.25⎦`); a single row in `[ ]`.
fn matrix_rows(cells: &[Vec<String>]) -> String {
    let columns = cells.iter().map(Vec::len).max().unwrap_or(0);
    let widths: Vec<usize> = (0..columns)
        .map(|j| {
            cells
                .iter()
                .filter_map(|r| r.get(j))
                .map(|c| c.chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let n = cells.len();
    cells
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let (open, close) = match (n, i) {
                (1, _) => ('[', ']'),
                (_, 0) => ('⎡', '⎤'),
                (_, i) if i + 1 == n => ('⎣', '⎦'),
                _ => ('⎢', '⎥'),
            };
            let row: Vec<String> = r
                .iter()
                .zip(&widths)
                .map(|(c, w)| format!("{c}{}", " ".repeat(w - c.chars().count())))
                .collect();
            format!("{open}{}{close}", row.join("  "))
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// A numeric matrix in both notations.
fn matrix(m: &[Vec<f64>]) -> Math {
    let cell = |v: f64| {
        let v = if v.abs() < 1e-12 { 0.0 } else { v };
        // Four decimals, without trailing zeros: `0.5`, `30`, `-4.905`.
        let text = format!("{v:.4}");
        let text = text.trim_end_matches('0').trim_end_matches('.');
        if text == "-0" {
            "0".to_string()
        } else {
            text.to_string()
        }
    };
    let cells: Vec<Vec<String>> = m
        .iter()
        .map(|r| r.iter().map(|v| cell(*v)).collect())
        .collect();
    let unicode = matrix_rows(&cells);
    let latex = format!(
        r"\begin{{pmatrix}} {} \end{{pmatrix}}",
        m.iter()
            .map(|r| r.iter().map(|v| cell(*v)).collect::<Vec<_>>().join(" & "))
            .collect::<Vec<_>>()
            .join(r" \\ ")
    );
    Math::label(unicode, latex)
}

/// A symbolic matrix in both notations.
fn exact_matrix(m: &[Vec<Expr>], notation: &Notation) -> Math {
    let cells: Vec<Vec<String>> = m
        .iter()
        .map(|r| r.iter().map(|e| notation.math(*e).unicode).collect())
        .collect();
    let unicode = matrix_rows(&cells);
    let latex = format!(
        r"\begin{{pmatrix}} {} \end{{pmatrix}}",
        m.iter()
            .map(|r| r
                .iter()
                .map(|e| notation.math(*e).latex)
                .collect::<Vec<_>>()
                .join(" & "))
            .collect::<Vec<_>>()
            .join(r" \\ ")
    );
    Math::label(unicode, latex)
}

fn linearized_section(
    rest: &RestEquations,
    set: &EquilibriumSet,
    lin: &[LinearizedResult],
    notation: &Notation,
    initial: Option<&InitialState>,
) -> Section {
    let mut s = Section::new("Linearized dynamics", 2);
    s.paragraph(
        "About each equilibrium q0: M0 δq̈ + C0 δq̇ + K0 δq = B0 δu, with M0 = M(q0), \
         C0 = −∂f/∂q̇ and K0 = −∂f/∂q at rest; natural frequencies from K0 x = ω² M0 x.",
    );
    for (i, l) in lin.iter().enumerate() {
        let Ok(l) = l else { continue };
        s.paragraph(format!(
            "About equilibrium {i} ({}):",
            stability_word(l.stable)
        ));
        s.equations(linear_lines(l, notation));
        s.paragraph(frequencies_sentence(rest, l));
    }
    if let Some(initial) = initial {
        free_response(&mut s, rest, set, lin, initial);
    }
    s
}

/// The model's initial state by the rest equations' coordinates: positions and rates.
#[derive(Clone, Debug, PartialEq)]
pub struct InitialState {
    /// `q(0)`.
    pub positions: Vec<f64>,
    /// `q̇(0)`.
    pub rates: Vec<f64>,
}

/// The free response from the model's initial state, in closed form (a sum of modes), about
/// the nearest equilibrium whose linearization is known.
fn free_response(
    s: &mut Section,
    rest: &RestEquations,
    set: &EquilibriumSet,
    lin: &[LinearizedResult],
    initial: &InitialState,
) {
    let n = rest.coordinates.len();
    if initial.positions.len() != n || initial.rates.len() != n {
        return;
    }
    let distance = |values: &[f64]| -> f64 {
        values
            .iter()
            .zip(&initial.positions)
            .enumerate()
            .filter(|(k, _)| !rest.free.get(*k).copied().unwrap_or(false))
            .map(|(_, (e, q))| (q - e).powi(2))
            .sum()
    };
    let nearest = set
        .equilibria
        .iter()
        .zip(lin)
        .enumerate()
        .filter_map(|(i, (e, l))| l.as_ref().ok().map(|l| (i, e, l)))
        .min_by(|a, b| distance(&a.1.values).total_cmp(&distance(&b.1.values)));
    let Some((i, e, l)) = nearest else { return };
    let dq0: Vec<f64> = initial
        .positions
        .iter()
        .zip(&e.values)
        .map(|(q, e)| q - e)
        .collect();
    match free_response_waves(l, &dq0, &initial.rates) {
        Some(waves) => {
            s.paragraph(format!(
                "Free response from the model's initial state, linearized about equilibrium {i} \
                 (the nearest; δq = q − q0, valid while the deviations stay small):"
            ));
            s.equations(
                rest.coordinates
                    .iter()
                    .zip(waves)
                    .map(|(q, parts)| {
                        let q = coordinate(q);
                        Equation::new(
                            Math::label(
                                format!("δ{}(t)", q.unicode),
                                format!(r"\delta {}(t)", q.latex),
                            ),
                            wave_sum(&parts),
                        )
                    })
                    .collect(),
            );
        }
        None => {
            s.paragraph(format!(
                "Free response about equilibrium {i}: no closed form as a sum of undamped modes \
                 (the linearization is damped); the simulation shows the motion."
            ));
        }
    }
}

/// `Σ c · wave(t)` in both notations, coefficients to four significant digits.
fn wave_sum(parts: &[(f64, Wave)]) -> Math {
    if parts.is_empty() {
        return Math::label("0", "0");
    }
    let mut unicode = String::new();
    let mut latex = String::new();
    for (c, wave) in parts {
        let magnitude = significant(c.abs());
        push_sign(&mut unicode, &mut latex, *c < 0.0);
        let function = match wave {
            Wave::Cos(w) => Some(("cos", w)),
            Wave::Sin(w) => Some(("sin", w)),
            Wave::Cosh(g) => Some(("cosh", g)),
            Wave::Sinh(g) => Some(("sinh", g)),
            Wave::One | Wave::Time => None,
        };
        let (u, l) = match (function, wave) {
            (Some((name, rate)), _) => (
                format!("{name}({} t)", significant(*rate)),
                format!(r"\{name}({}\, t)", significant(*rate)),
            ),
            (None, Wave::Time) => ("t".to_string(), "t".to_string()),
            (None, _) => (String::new(), String::new()),
        };
        unicode.push_str(&magnitude);
        latex.push_str(&latex_number(&magnitude));
        if !u.is_empty() {
            unicode.push(' ');
            unicode.push_str(&u);
            latex.push(' ');
            latex.push_str(&l);
        }
    }
    Math::label(unicode, latex)
}

/// `1.234e-5` as `1.234 \\cdot 10^{-5}`; plain numbers as they are.
fn latex_number(x: &str) -> String {
    match x.split_once('e') {
        Some((mantissa, exponent)) => format!(r"{mantissa} \cdot 10^{{{exponent}}}"),
        None => x.to_string(),
    }
}

/// A positive number to four significant digits, in plain notation where that is short.
fn significant(x: f64) -> String {
    if x == 0.0 || (1e-3..1e4).contains(&x) {
        let digits = (3 - x.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.3e}")
    }
}

fn linear_lines(l: &Linearized, notation: &Notation) -> Vec<Equation> {
    let names = [("M0", "M_0"), ("C0", "C_0"), ("K0", "K_0"), ("B0", "B_0")];
    let numeric = [&l.m0, &l.c0, &l.k0, &l.b0];
    let has_inputs = l.b0.iter().any(|row| !row.is_empty());
    names
        .iter()
        .enumerate()
        .filter(|(k, _)| *k != 1 || l.c0.iter().flatten().any(|v| v.abs() > 1e-12))
        .filter(|(k, _)| *k != 3 || has_inputs)
        .map(|(k, (u, t))| {
            let numbers = matrix(numeric[k]);
            let rhs = match &l.exact {
                Some(exact) => {
                    let symbolic = exact_matrix(&exact[k], notation);
                    // In a terminal a long symbolic matrix does not fit: the numbers only.
                    let both = crate::document::side_by_side(
                        &[&symbolic.unicode, &numbers.unicode],
                        " = ",
                    );
                    let unicode = if both.lines().any(|l| l.chars().count() > 72) {
                        numbers.unicode.clone()
                    } else {
                        both
                    };
                    Math::label(unicode, format!("{} = {}", symbolic.latex, numbers.latex))
                }
                None => numbers,
            };
            Equation::new(Math::label(*u, *t), rhs)
        })
        .collect()
}

fn frequencies_sentence(rest: &RestEquations, l: &Linearized) -> String {
    let Some(omega_squared) = &l.omega_squared else {
        return "M0 is not positive definite here: no natural frequencies.".to_string();
    };
    let parts: Vec<String> = omega_squared
        .iter()
        .enumerate()
        .map(|(k, w2)| {
            // Gyroscopic coupling: complex modes, not shown.
            let shape = l.modes.get(k).map(|mode| {
                rest.coordinates
                    .iter()
                    .zip(mode)
                    .map(|(q, x)| format!("{} {x:+.4}", coordinate(q).unicode))
                    .collect::<Vec<_>>()
                    .join(", ")
            });
            match (*w2 > 0.0, shape) {
                (true, Some(shape)) => format!("ω = {:.4} rad/s (mode {shape})", w2.sqrt()),
                (true, None) => format!("ω = {:.4} rad/s", w2.sqrt()),
                (false, Some(shape)) => {
                    format!("ω² = {w2:.4} ≤ 0, a divergent or neutral mode ({shape})")
                }
                (false, None) => format!("ω² = {w2:.4} ≤ 0, a divergent or neutral mode"),
            }
        })
        .collect();
    let mut sentence = format!("Natural frequencies: {}.", parts.join("; "));
    if l.modes.is_empty() && !omega_squared.is_empty() {
        sentence.push_str(
            " They are those of the whole linearization: C0 couples the coordinates \
             gyroscopically, so the modes are complex and K0, M0 alone do not give them.",
        );
    }
    let eigenvalues: Vec<String> = l
        .eigenvalues
        .iter()
        .map(|(re, im)| {
            let re = if re.abs() < 1e-9 { 0.0 } else { *re };
            if im.abs() < 1e-9 {
                format!("{re:.4}")
            } else {
                format!(
                    "{re:.4} {} {:.4}i",
                    if *im < 0.0 { "−" } else { "+" },
                    im.abs()
                )
            }
        })
        .collect();
    sentence.push_str(&format!(
        " Eigenvalues of the state matrix A: {}.",
        eigenvalues.join(", ")
    ));
    if let Some(rank) = l.controllability_rank {
        let n = l.a.len();
        sentence.push_str(&format!(
            " Controllability matrix [B, AB, …] of rank {rank} of {n}: {}.",
            if rank == n {
                "controllable from the inputs"
            } else {
                "not controllable from the inputs alone"
            }
        ));
    }
    if l.damping_ratios.iter().any(|z| z.abs() > 1e-9) {
        let z: Vec<String> = l.damping_ratios.iter().map(|z| format!("{z:.4}")).collect();
        sentence.push_str(&format!(" Damping ratios: {}.", z.join(", ")));
    }
    sentence
}

/// The stability conditions in the parameters, one paragraph per equilibrium that has one
/// (`mechanics::stability_condition`): the condition, its criterion, what happens on its
/// boundaries (a family of equilibria there is said to be one), and whether the model's
/// values sit on a boundary. `on_boundary` gives, per equilibrium, that boundary's index.
#[must_use]
pub fn stability_condition_paragraphs(
    conditions: &[Option<StabilityCondition>],
    on_boundary: &[Option<usize>],
) -> Vec<String> {
    conditions
        .iter()
        .enumerate()
        .filter_map(|(i, c)| {
            let c = c.as_ref()?;
            let mut text = format!(
                "Equilibrium {i} in the parameters: {} ({}).",
                c.sentence(to_unicode),
                c.criterion.sentence()
            );
            let boundaries = c.boundary_sentences(to_unicode);
            for b in &boundaries {
                let mut letters = b.chars();
                let first: String = letters
                    .next()
                    .into_iter()
                    .flat_map(char::to_uppercase)
                    .collect();
                text.push_str(&format!(" {first}{}.", letters.as_str()));
            }
            if let Some(b) = on_boundary
                .get(i)
                .copied()
                .flatten()
                .and_then(|k| boundaries.get(k))
            {
                text.push_str(&format!(" The model's values sit on that boundary: {b}."));
            }
            Some(text)
        })
        .collect()
}
