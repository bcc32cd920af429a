//! Explicit accelerations that stay small: `q̈ = adj(M) f / Δ` with the determinant
//! `Δ = det M` and the adjugate's entries (the cofactors) written once, instead of the
//! expanded `M⁻¹ f`, whose normal form can swell far beyond `M` and `f` (a double pendulum of
//! two bodies with off-axis mass centres: M and f of about 150 characters, `M⁻¹ f` of hundreds
//! of thousands). Above [`ACCELERATION_BUDGET`] characters per expression nothing explicit is
//! written and a note says why: `M q̈ = f` is then the answer.

use cas::print::to_sympy;
use cas::Expr;
use mechanics::Equations;

/// The most characters (SymPy syntax) an explicit acceleration, a determinant or a cofactor
/// may have in the JSON; longer ones are left out with a note.
pub const ACCELERATION_BUDGET: usize = 2000;

/// At most this many coordinates get the adjugate form: its entries are `(n−1)×(n−1)`
/// determinants, which grow factorially.
const MAX_COORDINATES: usize = 3;

/// `q̈ = adj(M) f / Δ`.
#[derive(Clone, Debug)]
pub struct AdjugateForm {
    /// `Δ = det M`, in normal form.
    pub determinant: Expr,
    /// `adj(M)` (the transposed cofactors), in normal form, row by row.
    pub adjugate: Vec<Vec<Expr>>,
    /// `q̈_i = (Σ_j adj_ij f_j) / Δ`, kept factored (not expanded).
    pub accelerations: Vec<Expr>,
}

/// The explicit accelerations the JSON writes, and what else it says about them.
#[derive(Clone, Debug)]
pub struct Explicit {
    /// The accelerations, when every one fits the budget: the normal form `M⁻¹ f` when it is
    /// that small, the factored `adj(M) f / Δ` otherwise.
    pub accelerations: Option<Vec<Expr>>,
    /// The determinant and adjugate, when they fit the budget.
    pub form: Option<AdjugateForm>,
    /// Why explicit accelerations are missing, when they are.
    pub note: Option<String>,
}

/// The adjugate form of `M q̈ = f` for up to three coordinates without
/// multipliers; `None` otherwise.
#[must_use]
pub fn adjugate_form(equations: &Equations) -> Option<AdjugateForm> {
    let m = equations.mass_matrix();
    let n = m.len();
    if n == 0 || n > MAX_COORDINATES || !equations.constraint_names().is_empty() {
        return None;
    }
    let determinant = determinant(m).normal();
    let adjugate: Vec<Vec<Expr>> = (0..n)
        .map(|i| (0..n).map(|j| cofactor(m, j, i).normal()).collect())
        .collect();
    let accelerations = adjugate
        .iter()
        .map(|row| {
            let numerator: Expr = row
                .iter()
                .zip(equations.forcing())
                .filter(|(a, _)| !a.is_literal_zero())
                .map(|(a, f)| *a * *f)
                .sum();
            numerator / determinant
        })
        .collect();
    Some(AdjugateForm {
        determinant,
        adjugate,
        accelerations,
    })
}

/// Whether `e` is within [`ACCELERATION_BUDGET`] characters in SymPy syntax.
#[must_use]
pub fn fits(e: Expr) -> bool {
    to_sympy(e).len() <= ACCELERATION_BUDGET
}

/// The accelerations a report shows: the normal form `M⁻¹ f` when every one is within the
/// budget, else the factored `adj(M) f / Δ` when that is; `None` when neither is.
#[must_use]
pub fn for_report(equations: &Equations) -> Option<Vec<Expr>> {
    let expanded = equations
        .accelerations()
        .filter(|a| a.iter().all(|e| fits(*e)))
        .map(<[Expr]>::to_vec);
    expanded.or_else(|| explicit(equations).accelerations)
}

/// The explicit accelerations within the budget, with a note when they are left out.
#[must_use]
pub fn explicit(equations: &Equations) -> Explicit {
    let fits = |e: &Expr| fits(*e);
    let form = adjugate_form(equations)
        .filter(|f| fits(&f.determinant) && f.adjugate.iter().flatten().all(fits));
    let expanded = equations
        .accelerations()
        .filter(|a| a.iter().all(fits))
        .map(<[Expr]>::to_vec);
    let factored = || {
        form.as_ref()
            .map(|f| f.accelerations.clone())
            .filter(|a| a.iter().all(fits))
    };
    // The shorter of the two forms that fit: the normal form reads best when it is small.
    let size = |a: &[Expr]| a.iter().map(|e| to_sympy(*e).len()).sum::<usize>();
    let accelerations = match (expanded, factored()) {
        (Some(e), Some(f)) if size(&f) < size(&e) => Some(f),
        (Some(e), _) => Some(e),
        (None, f) => f,
    };
    let note = if accelerations.is_some() {
        None
    } else if !equations.constraint_names().is_empty() {
        Some(
            "constraints are kept with multipliers: solve [M Aᵀ; A 0] [q_dd; λ] = [forcing; b]"
                .to_string(),
        )
    } else {
        Some(format!(
            "explicit accelerations are longer than {ACCELERATION_BUDGET} characters (or the system has more than {MAX_COORDINATES} coordinates): solve mass_matrix * q_dd = forcing"
        ))
    };
    Explicit {
        accelerations,
        form,
        note,
    }
}

/// `det m` by expansion along the first row (small matrices only).
fn determinant(m: &[Vec<Expr>]) -> Expr {
    match m.len() {
        0 => Expr::one(),
        1 => m[0][0],
        n => (0..n)
            .filter(|j| !m[0][*j].is_literal_zero())
            .map(|j| m[0][j] * cofactor(m, 0, j))
            .sum(),
    }
}

/// The cofactor `(−1)^(i+j) det(m without row i and column j)`.
fn cofactor(m: &[Vec<Expr>], i: usize, j: usize) -> Expr {
    let minor: Vec<Vec<Expr>> = m
        .iter()
        .enumerate()
        .filter(|(r, _)| *r != i)
        .map(|(_, row)| {
            row.iter()
                .enumerate()
                .filter(|(c, _)| *c != j)
                .map(|(_, x)| *x)
                .collect()
        })
        .collect();
    let d = determinant(&minor);
    if (i + j) % 2 == 0 {
        d
    } else {
        -d
    }
}
