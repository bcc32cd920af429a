//! The sections of a solution by Kane's method (issue 18): for a nonholonomic system whose
//! equations with multipliers are over the symbolic work limits (the Whipple bicycle), the
//! generalized speeds, the reduced equations `M_r u̇ = f_r` (symbolic, or their values at the
//! initial state), and the linearization about the steady motion with its canonical form.
//! Everything is computed by the caller; these functions only lay it out.

use cas::Expr;

use crate::document::{Block, Cell, Equation, Math, Notation, Section};

/// The generalized speeds: which rates are speeds, which follow.
#[derive(Clone, Debug)]
pub struct Speeds<'a> {
    /// The coordinates whose rates are the speeds, in order.
    pub independent: &'a [String],
    /// The coordinates whose rates the constraints fix.
    pub dependent: &'a [String],
    /// The coordinates a holonomic constraint fixes (found by Newton's method in a run).
    pub holonomic: &'a [String],
}

/// The reduced equations at one state, as numbers.
#[derive(Clone, Debug)]
pub struct ReducedAt<'a> {
    /// Why they are not printed symbolically.
    pub why: String,
    /// The coordinates and their values at the state.
    pub configuration: &'a [(String, f64)],
    /// The rates there (the speeds given, the others from the constraints).
    pub rates: &'a [(String, f64)],
    /// `M_r` (speeds × speeds).
    pub mass: &'a [Vec<f64>],
    /// `f_r`.
    pub forcing: &'a [f64],
}

/// A linearization about a steady motion, with its canonical form when there is one.
#[derive(Clone, Debug)]
pub struct SteadyPart<'a> {
    /// The steady rates that are not zero.
    pub rates: &'a [(String, f64)],
    /// The states of the linearization.
    pub states: &'a [String],
    /// The eigenvalues `(re, im)`.
    pub eigenvalues: &'a [(f64, f64)],
    /// Whether every eigenvalue has a negative real part.
    pub stable: bool,
    /// `M q̈ + v C₁ q̇ + (g K₀ + v² K₂) q = 0`: the speed's name, the coordinates and
    /// `M`, `C₁`, `K₀`, `K₂`.
    pub canonical: Option<Canonical<'a>>,
}

/// The canonical second-order form of a steady linearization.
#[derive(Clone, Debug)]
pub struct Canonical<'a> {
    /// The speed parameter.
    pub speed: &'a str,
    /// The coordinates, in the matrices' order.
    pub coordinates: &'a [String],
    /// `M`, `C₁`, `K₀`, `K₂`, in that order.
    pub matrices: [&'a [Vec<f64>]; 4],
}

/// "Generalized speeds": `u_k = q̇_j`, the dependent rates and the fixed coordinates.
#[must_use]
pub fn speeds_section(speeds: &Speeds<'_>, notation: &Notation) -> Section {
    let mut s = Section::new("Generalized speeds", 2);
    let rate = |q: &String| notation.math(Expr::rate(q, 1));
    s.paragraph(format!(
        "Kane's method takes {} of the rates as generalized speeds; the constraints give the \
         others at every state, so the equations of motion are one per speed and carry no \
         multipliers.",
        speeds.independent.len()
    ));
    let lines = speeds
        .independent
        .iter()
        .enumerate()
        .map(|(k, q)| {
            let name = format!("u{}", k + 1);
            Equation::new(Math::label(&name, format!("u_{{{}}}", k + 1)), rate(q))
        })
        .collect();
    s.equations(lines);
    if !speeds.dependent.is_empty() {
        let names: Vec<String> = speeds.dependent.iter().map(|q| rate(q).unicode).collect();
        s.paragraph(format!(
            "Dependent rates, solved from the constraints at each state: {}.",
            names.join(", ")
        ));
    }
    if !speeds.holonomic.is_empty() {
        let names: Vec<String> = (speeds.holonomic.iter())
            .map(|q| notation.math(Expr::coordinate(q)).unicode)
            .collect();
        s.paragraph(format!(
            "Fixed by the holonomic constraints (found by Newton's method at each state): {}.",
            names.join(", ")
        ));
    }
    s
}

/// "Reduced equations of motion" printed symbolically: `Σ_k M_r,ik u̇_k = f_r,i` per speed.
#[must_use]
pub fn reduced_symbolic_section(lines: Vec<Equation>) -> Section {
    let mut s = Section::new("Reduced equations of motion", 2);
    s.paragraph("Kane's equations Fr + Fr* = 0, one per speed (M_r u̇ = f_r):");
    s.equations(lines);
    s
}

/// "Reduced equations of motion" as numbers at a state.
#[must_use]
pub fn reduced_numeric_section(reduced: &ReducedAt<'_>, notation: &Notation) -> Section {
    let mut s = Section::new("Reduced equations of motion", 2);
    s.paragraph(format!(
        "Kane's equations Fr + Fr* = 0, one per speed, M_r u̇ = f_r. Not printed \
         symbolically: {}. They are evaluated exactly (to rounding) at any state from the \
         geometry's shared sub-expressions; at the initial state:",
        reduced.why
    ));
    let state_rows: Vec<Vec<Cell>> = reduced
        .configuration
        .iter()
        .zip(reduced.rates)
        .map(|((q, value), (_, rate))| {
            vec![
                Cell::Math(notation.math(Expr::coordinate(q))),
                number(*value),
                number(*rate),
            ]
        })
        .collect();
    s.blocks.push(Block::Table {
        header: vec!["coordinate".into(), "value".into(), "rate".into()],
        rows: state_rows,
    });
    let p = reduced.forcing.len();
    let mut header: Vec<String> = vec!["row".into()];
    header.extend((1..=p).map(|k| format!("M_r (u{k})")));
    header.push("f_r".into());
    let rows = (0..p)
        .map(|i| {
            let mut row = vec![Cell::Text(format!("u{}", i + 1))];
            row.extend(reduced.mass[i].iter().map(|x| number(*x)));
            row.push(number(reduced.forcing[i]));
            row
        })
        .collect();
    s.blocks.push(Block::Table { header, rows });
    s
}

/// "Steady motion and its stability": the eigenvalues, the verdict and the canonical form.
#[must_use]
pub fn steady_section(steady: &SteadyPart<'_>, notation: &Notation) -> Section {
    let mut s = Section::new("Steady motion and its stability", 2);
    let rates: Vec<String> = (steady.rates.iter())
        .map(|(q, v)| {
            format!(
                "{} = {}",
                notation.math(Expr::rate(q, 1)).unicode,
                short(*v)
            )
        })
        .collect();
    s.paragraph(format!(
        "The initial statement describes a steady motion ({}). Linearized about it in the \
         states {} (Kane's reduced equations differentiated exactly), its eigenvalues are:",
        rates.join(", "),
        steady.states.join(", ")
    ));
    let rows = (steady.eigenvalues.iter())
        .map(|(re, im)| vec![number(*re), number(*im)])
        .collect();
    s.blocks.push(Block::Table {
        header: vec!["real part".into(), "imaginary part".into()],
        rows,
    });
    s.paragraph(if steady.stable {
        "Every eigenvalue has a negative real part: the steady motion is asymptotically stable."
    } else {
        "An eigenvalue has a real part that is not negative: the steady motion is not \
         asymptotically stable."
    });
    if let Some(c) = &steady.canonical {
        canonical_blocks(&mut s, c, notation);
    }
    s
}

/// The canonical form's matrices, one table each.
fn canonical_blocks(s: &mut Section, c: &Canonical<'_>, notation: &Notation) {
    s.paragraph(format!(
        "In the canonical form of the bicycle literature, M q̈ + {v} C1 q̇ + (g K0 + {v}² K2) q \
         = 0, with q = ({}):",
        c.coordinates.join(", "),
        v = c.speed
    ));
    for (name, m) in ["M", "C1", "K0", "K2"].iter().zip(c.matrices) {
        let mut header = vec![(*name).to_string()];
        header.extend(c.coordinates.iter().cloned());
        let rows = c
            .coordinates
            .iter()
            .zip(m)
            .map(|(q, row)| {
                let mut cells = vec![Cell::Math(notation.math(Expr::coordinate(q)))];
                cells.extend(row.iter().map(|x| number(*x)));
                cells
            })
            .collect();
        s.blocks.push(Block::Table { header, rows });
    }
}

/// A number to ten significant digits, in both notations.
fn number(x: f64) -> Cell {
    let text = short(x);
    Cell::Math(Math::label(text.replace('-', "−"), text))
}

/// Ten significant digits, in powers of ten when very large or small, never `-0`.
fn short(x: f64) -> String {
    let x = x + 0.0;
    if x == 0.0 {
        return "0".into();
    }
    if x.abs() >= 1e6 || x.abs() < 1e-4 {
        format!("{x:.9e}")
    } else {
        let digits = 9 - (x.abs().max(1e-300).log10().floor() as i32).clamp(-5, 9);
        let text = format!("{x:.*}", digits.max(0) as usize);
        match text.strip_prefix('-') {
            Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_owned(),
            _ => text,
        }
    }
}

/// "The system" of a solution by Kane's method: why by Kane's method (one sentence), the
/// degrees of freedom as `lagrange check` counts them, the coordinates, the parameters and
/// the constraints.
#[must_use]
pub fn system_section(
    why: &str,
    degrees_of_freedom: &str,
    system: &mechanics::System,
    constraints: &[String],
    notation: &Notation,
) -> Section {
    let mut s = Section::new("The system", 2);
    s.paragraph(why.to_string());
    let coordinates: Vec<String> = (system.coordinates().iter())
        .map(|q| notation.math(Expr::coordinate(q)).unicode)
        .collect();
    s.paragraph(format!(
        "Coordinates: {}. Degrees of freedom: {degrees_of_freedom}.",
        coordinates.join(", ")
    ));
    s.blocks
        .extend(crate::solution::parameter_table(system, notation));
    if !constraints.is_empty() {
        s.paragraph("Constraints:");
        s.blocks.push(Block::List(constraints.to_vec()));
    }
    s
}
