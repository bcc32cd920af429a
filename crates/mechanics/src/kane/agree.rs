//! Whether Kane's reduced equations and Lagrange's equations say the same: Lagrange's
//! `M q̈ = f + Aᵀλ`, projected on the speeds, is `Tᵀ M T u̇ = Tᵀ (f − M bias)` (the
//! multipliers drop out, `A T = 0`), which must be Kane's `M_r u̇ = f_r` term by term.
//!
//! The differences are decided exactly (their normal form is zero) within the `cas` work
//! limits, and past them at sample states, where a difference above rounding is a
//! disagreement.

use cas::{Expr, Symbol, SymbolKind};

use super::symbolic::KaneEquations;

/// How Kane's equations compare with Lagrange's.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Agreement {
    /// Every difference is exactly zero.
    Exact,
    /// Every difference vanishes to rounding at `states` sample states (the normal form
    /// passed the work limits); `largest` is the largest relative difference.
    AtStates {
        /// How many states.
        states: usize,
        /// The largest difference relative to the entries' size.
        largest: f64,
    },
    /// A difference that does not vanish: in the mass matrix or the forcing, at this speed.
    Differs {
        /// `"mass matrix"` or `"forcing"`.
        part: &'static str,
        /// The row (the speed's index).
        row: usize,
    },
}

/// The relative difference above which two evaluations disagree.
const TOLERANCE: f64 = 1e-8;

impl KaneEquations {
    /// Compares with Lagrange's mass matrix `M` and forcing `f` over the same coordinates
    /// (rates of the dependent coordinates in `f` are replaced by their speeds' expressions).
    /// `values` gives the named values' numbers for the comparison at sample states.
    #[must_use]
    pub fn agreement(
        &self,
        mass: &[Vec<Expr>],
        forcing: &[Expr],
        values: &[(String, f64)],
    ) -> Agreement {
        let (dm, df) = self.differences(mass, forcing);
        let exact = cas::limited(|| {
            if let Some(row) = dm.iter().position(|r| r.iter().any(|x| !x.is_zero())) {
                return Some(("mass matrix", row));
            }
            df.iter()
                .position(|x| !x.is_zero())
                .map(|row| ("forcing", row))
        });
        match exact {
            Ok(None) => Agreement::Exact,
            Ok(Some((part, row))) => Agreement::Differs { part, row },
            Err(_) => self.at_states(&dm, &df, values),
        }
    }

    /// `Tᵀ M T − M_r` and `Tᵀ (f − M bias) − f_r`.
    fn differences(&self, mass: &[Vec<Expr>], forcing: &[Expr]) -> (Vec<Vec<Expr>>, Vec<Expr>) {
        let n = self.coordinates.len();
        let p = self.split.independent.len();
        let t = &self.speed_matrix;
        let pairs: Vec<(Expr, Expr)> = self
            .split
            .dependent
            .iter()
            .map(|d| (Expr::rate(&self.coordinates[*d], 1), self.rates[*d]))
            .collect();
        let forcing: Vec<Expr> = forcing.iter().map(|f| f.subs(&pairs)).collect();
        let mt: Vec<Vec<Expr>> = (0..p)
            .map(|i| {
                (0..n)
                    .map(|l| Expr::add_all((0..n).map(|j| t[j][i] * mass[j][l])))
                    .collect()
            })
            .collect();
        let dm = (0..p)
            .map(|i| {
                (0..p)
                    .map(|k| Expr::add_all((0..n).map(|l| mt[i][l] * t[l][k])) - self.mass[i][k])
                    .collect()
            })
            .collect();
        let df = (0..p)
            .map(|i| {
                let projected = Expr::add_all((0..n).map(|j| t[j][i] * forcing[j]));
                let inertia = Expr::add_all((0..n).map(|l| mt[i][l] * self.bias[l]));
                projected - inertia - self.forcing[i]
            })
            .collect();
        (dm, df)
    }

    /// The differences at three sample states, relative to the size of Kane's entries there.
    fn at_states(&self, dm: &[Vec<Expr>], df: &[Expr], values: &[(String, f64)]) -> Agreement {
        let mut largest = 0.0_f64;
        for state in 0..3 {
            let env = |s: Symbol| sample_value(s, state, values);
            let eval = |e: &Expr| e.eval(&env).unwrap_or(f64::NAN);
            let scale = self
                .mass
                .iter()
                .flatten()
                .chain(&self.forcing)
                .map(|e| eval(e).abs())
                .fold(1e-300_f64, f64::max);
            let rows = dm
                .iter()
                .enumerate()
                .flat_map(|(r, row)| row.iter().map(move |d| ("mass matrix", r, d)));
            let forcing = df.iter().enumerate().map(|(r, d)| ("forcing", r, d));
            for (part, row, d) in rows.chain(forcing) {
                let rel = eval(d).abs() / scale;
                if rel.is_nan() || rel > TOLERANCE {
                    return Agreement::Differs { part, row };
                }
                largest = largest.max(rel);
            }
        }
        Agreement::AtStates { states: 3, largest }
    }
}

/// A value for `s` at sample state `state`: the named value when there is one, otherwise a
/// number in `[0.3, 1.3)` drawn from the name, its order and the state.
fn sample_value(s: Symbol, state: usize, values: &[(String, f64)]) -> Option<f64> {
    if !matches!(s.kind(), SymbolKind::TimeFunction { .. } | SymbolKind::Time) {
        if let Some((_, v)) = values.iter().find(|(n, _)| n == s.name()) {
            return Some(*v);
        }
    }
    let mut h: u64 = 0x9e37_79b9_7f4a_7c15 ^ (state as u64).wrapping_mul(0x0100_0000_01b3);
    for b in s.name().bytes().chain([s.order()]) {
        h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
    }
    Some(0.3 + (h >> 11) as f64 / (1u64 << 53) as f64)
}
