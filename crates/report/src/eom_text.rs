//! The equations of motion for the terminal, as `lagrange eom` prints them: eliminated
//! coordinates, `K`, `V`, Lagrange's equations `d/dt ∂L/∂q̇ − ∂L/∂q = Q − Σ λ A`, the
//! constraints kept with multipliers, the explicit accelerations and the first integrals.

use cas::print::to_unicode;
use mechanics::{Equations, System};

use crate::document::Notation;

/// The text of `lagrange eom`.
#[must_use]
pub fn eom_text(system: &System, equations: &Equations) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    // Each line of the text.
    macro_rules! say {
        ($($arg:tt)*) => {{
            let _ = writeln!(out, $($arg)*);
        }};
    }
    // The model's constants by name, denominators spread, as in `solve`; Unicode only (the
    // LaTeX of `Notation::math` would double the printing of a large result for nothing).
    let notation = Notation::of(system);
    let shown = |e: cas::Expr| to_unicode(notation.shape(e));
    for e in equations.eliminated() {
        say!(
            "{} eliminated by constraint `{}`: {} = {}",
            e.coordinate,
            e.constraint,
            e.coordinate,
            to_unicode(e.value)
        );
    }
    say!("K = {}", shown(equations.kinetic_energy()));
    say!("V = {}", shown(equations.potential_energy()));
    say!("");
    // M q̈ + Aᵀλ = f is printed as d/dt ∂L/∂q̇ − ∂L/∂q = Q − Σ λ_i A_ij.
    let multipliers: Vec<cas::Expr> = (1..=equations.constraint_names().len())
        .map(|i| cas::Expr::symbol(&format!("lambda{i}")))
        .collect();
    for (j, (lhs, q)) in equations
        .lagrange_lhs()
        .iter()
        .zip(equations.generalized_forces())
        .enumerate()
    {
        let reactions = equations
            .constraint_matrix()
            .iter()
            .zip(&multipliers)
            .filter_map(|(row, lambda)| row.get(j).map(|a| *lambda * *a))
            .sum::<cas::Expr>();
        say!("{} = {}", shown(*lhs), shown(*q - reactions));
    }
    for (name, ((row, b), lambda)) in equations.constraint_names().iter().zip(
        equations
            .constraint_matrix()
            .iter()
            .zip(equations.constraint_rhs())
            .zip(&multipliers),
    ) {
        let lhs = row
            .iter()
            .zip(equations.coordinates())
            .map(|(a, q)| *a * cas::Expr::rate(q, 2))
            .sum::<cas::Expr>();
        say!(
            "constraint `{name}` ({}): {} = {}",
            to_unicode(*lambda),
            to_unicode(lhs),
            to_unicode(*b)
        );
    }
    if let Some(accelerations) = equations.accelerations() {
        say!("");
        say!("solved for the accelerations:");
        for (j, (q, a)) in equations
            .coordinates()
            .iter()
            .zip(accelerations)
            .enumerate()
        {
            say!(
                "  {} = {}",
                to_unicode(cas::Expr::rate(q, 2)),
                crate::solution::acceleration(equations, &notation, j, *a).unicode
            );
        }
    }
    if !equations.first_integrals().is_empty() {
        say!("");
    }
    for f in equations.first_integrals() {
        let condition = crate::solution::conditions_text(f)
            .map(|c| format!(" while {c}"))
            .unwrap_or_default();
        match &f.coordinate {
            Some(q) => say!("conserved{condition}: p_{q} = {}", shown(f.value)),
            None => say!("conserved ({}){condition}: h = {}", f.kind, shown(f.value)),
        }
    }
    out
}
