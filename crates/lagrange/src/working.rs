//! The working of each reaction the model asks for, for the solution's reactions section
//! ([`report::reaction_working`]): the Lagrange equations that give it, with the
//! accelerations still in them, before the result.
//!
//! A reaction at a point: the released system (the bodies moved by displacement coordinates
//! `u_i`) is derived once more, and the equation of each `u_i` at `u = u̇ = ü = 0` is
//! `R · d_i`. A constraint kept with its multiplier: the constrained equations' own rows,
//! `E_j − Q_j = −Σ a_kj λ_k`. A constraint eliminated by integration (a gear): the equations of
//! the system without it, `E_j − Q_j = Q^R_j`. Nothing here changes a result: the reactions
//! themselves come from [`Analysis::reactions`].

use cas::Expr;
use mechanics::{Equations, ReactionRequest, Release};
use report::reaction_working::{multiplier_symbol, Working};

use crate::Analysis;

impl Analysis {
    /// The working of each reaction asked for, in the order of [`Analysis::reactions`];
    /// `None` for one whose working cannot be had (a driven coordinate's force, a released
    /// system that does not derive within the limits). Empty when the model asks for no
    /// reaction or has no equations of motion.
    #[must_use]
    pub fn reaction_working(&self) -> Vec<Option<Working>> {
        let (Ok(requests), Ok(equations)) = (self.requests(), self.equations()) else {
            return Vec::new();
        };
        requests
            .iter()
            .map(|request| match request {
                ReactionRequest::Release(release) => self.released_working(release, equations),
                ReactionRequest::Constraint { name, without } => {
                    if equations.constraint_names().iter().any(|n| n == name) {
                        multiplier_working(name, equations)
                    } else {
                        self.freed_working(without, equations)
                    }
                }
                _ => None,
            })
            .collect()
    }

    /// `E_u − Q_u` at `u = u̇ = ü = 0` for each displacement of the release, in the
    /// constrained system's coordinates.
    fn released_working(&self, release: &Release, equations: &Equations) -> Option<Working> {
        let at_rest = match self.derived_release(release) {
            Some(computed) => computed,
            None => self.released_at_rest(release)?,
        };
        let lines = release
            .displacements
            .iter()
            .filter_map(|(u, d)| {
                let (_, lhs) = at_rest.iter().find(|(q, _)| q == u)?;
                let lhs = on_constrained(*lhs, equations);
                let axis = u.rsplit("__").next().unwrap_or(u).to_string();
                (!lhs.is_zero()).then_some((axis, *d, lhs))
            })
            .collect();
        Some(Working::Released {
            point: release.point.0.clone(),
            equations: lines,
        })
    }

    /// The released equations at rest that the closed-form reactions already derived (see
    /// [`mechanics::Reaction::released_equations`]), when they were: deriving the released
    /// system a second time here was a third of the rolling cone's `solve` (issue 20).
    fn derived_release(&self, release: &Release) -> Option<Vec<(String, Expr)>> {
        let Some(Ok(Some(reactions))) = self.reactions.get() else {
            return None;
        };
        let reaction = reactions
            .reactions
            .iter()
            .find(|r| r.name == release.name)?;
        Some(reaction.released_equations.clone())
    }

    /// `E_u − Q_u` at `u = u̇ = ü = 0` of each coordinate of the released system, derived here
    /// (the reactions were evaluated numerically, or not derived).
    fn released_at_rest(&self, release: &Release) -> Option<Vec<(String, Expr)>> {
        let released = self.derived_quietly(&release.system)?;
        let zero: Vec<(Expr, Expr)> = release
            .displacements
            .iter()
            .chain(&release.rotations)
            .flat_map(|(u, _)| {
                [Expr::coordinate(u), Expr::rate(u, 1), Expr::rate(u, 2)].map(|x| (x, Expr::zero()))
            })
            .collect();
        let equations = released
            .lagrange_lhs()
            .iter()
            .zip(released.generalized_forces());
        let at_rest = released
            .coordinates()
            .iter()
            .zip(equations)
            .map(|(q, (e, f))| (q.clone(), (*e - *f).subs(&zero)))
            .collect();
        Some(at_rest)
    }

    /// The equations of the system without an integrable constraint, `E_j − Q_j = Q^R_j`, on
    /// the constrained system's coordinates.
    fn freed_working(&self, without: &mechanics::System, equations: &Equations) -> Option<Working> {
        let freed = self.derived_quietly(without)?;
        let lines = freed
            .coordinates()
            .iter()
            .zip(freed.lagrange_lhs().iter().zip(freed.generalized_forces()))
            .map(|(q, (e, f))| (q.clone(), on_constrained(*e - *f, equations)))
            .collect();
        Some(Working::Freed { equations: lines })
    }

    /// The equations of `system` without first integrals, within this analysis' limits;
    /// `None` when they cannot be had (then the working is left out, the result stands).
    fn derived_quietly(&self, system: &mechanics::System) -> Option<Equations> {
        self.within_limits(|| mechanics::derive_without_first_integrals(system))
            .ok()
    }
}

/// The constrained equations' rows for each coordinate, `E_j − Q_j = −Σ_k a_kj λ_k`, when the
/// constraint `name` is the only one kept with multipliers (else the multipliers of others
/// would stand beside its own).
fn multiplier_working(name: &str, equations: &Equations) -> Option<Working> {
    let names = equations.constraint_names();
    if names.iter().any(|n| n != name) {
        return None;
    }
    let rows = equations.constraint_matrix();
    let lines = equations
        .coordinates()
        .iter()
        .enumerate()
        .map(|(j, q)| {
            let lhs = (equations.lagrange_lhs()[j] - equations.generalized_forces()[j]).normal();
            let rhs = Expr::add_all(
                rows.iter()
                    .enumerate()
                    .map(|(k, row)| -(row[j] * multiplier_symbol(k, rows.len()))),
            )
            .normal();
            (q.clone(), lhs, rhs)
        })
        .filter(|(_, l, r)| !(l.is_zero() && r.is_zero()))
        .collect();
    Some(Working::Multiplier { equations: lines })
}

/// `e` in the constrained system's coordinates: its eliminated coordinates (and their rates
/// and accelerations) replaced by their values, in order.
fn on_constrained(e: Expr, equations: &Equations) -> Expr {
    let mut e = e;
    for elimination in equations.eliminated() {
        let value = elimination.value;
        let rate = value.dt();
        e = e.subs(&[
            (Expr::coordinate(&elimination.coordinate), value),
            (Expr::rate(&elimination.coordinate, 1), rate),
            (Expr::rate(&elimination.coordinate, 2), rate.dt()),
        ]);
    }
    e.normal()
}
