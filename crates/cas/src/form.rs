//! [`NormalForm`]: a normal form kept in its working (polynomial fraction) form, without its
//! expression tree.
//!
//! Every `Expr` operation returns a canonical tree, and building that tree (interning every
//! term and sorting them in the structural order) is most of the cost of a large result. A
//! derivation chains many operations whose intermediate results nobody reads — `d/dt ∂L/∂q̇`,
//! `∂L/∂q`, their difference, the forcing before its sign flip — so those steps work on
//! `NormalForm` and only the results that are kept become trees with [`NormalForm::to_expr`].
//! Both routes give the same canonical expression.

use std::sync::Arc;

use crate::calculus::{gradient_rf, partial_derivative_rf, time_derivative_rf};
use crate::expr::{Expr, Symbol};
use crate::normal::{cached_rf, from_shared_rf, to_rf, tree_unremembered, Rf};
use crate::ops::affine_split;

/// The normal form of an expression as a polynomial fraction (see the module documentation).
/// Cheap to clone (shared).
#[derive(Clone, Debug)]
pub struct NormalForm(Arc<Rf>);

impl NormalForm {
    fn from_rf(r: Rf) -> NormalForm {
        NormalForm(Arc::new(r))
    }

    /// Zero.
    #[must_use]
    pub fn zero() -> NormalForm {
        NormalForm::from_rf(Rf::zero())
    }

    /// The canonical tree, the same `Expr` that `Expr::normal` gives for an equal input.
    /// A large form is remembered with its tree, so later `Expr` operations on the tree do not
    /// convert it back.
    #[must_use]
    pub fn to_expr(&self) -> Expr {
        from_shared_rf(&self.0)
    }

    /// [`NormalForm::to_expr`] for a result whose working form is not wanted again: the tree
    /// is the same, but the form is not remembered with it, so it is freed with the last
    /// `NormalForm` that holds it. A later operation on the tree converts it back (in time
    /// linear in its size). The mass matrix and forcing of a large system are kept as trees
    /// by every later stage; remembering their working forms as well doubled the memory of a
    /// derivation (the n-link pendulum at n = 100: O(n³) terms of 96 bytes each).
    #[must_use]
    pub fn to_expr_unremembered(&self) -> Expr {
        tree_unremembered(&self.0)
    }

    /// Whether the form is identically zero (exact for the mechanics class).
    #[must_use]
    pub fn is_zero(&self) -> bool {
        self.0.is_zero()
    }

    /// `self + other`.
    #[must_use]
    pub fn add(&self, other: &NormalForm) -> NormalForm {
        NormalForm::from_rf(self.0.add(&other.0))
    }

    /// `Σ forms`, equal to adding them one by one, in time linear in the terms (up to the
    /// sort): adding a long list one at a time copies the growing sum for every part.
    #[must_use]
    pub fn sum<'a>(forms: impl IntoIterator<Item = &'a NormalForm>) -> NormalForm {
        NormalForm::from_rf(Rf::sum(forms.into_iter().map(|f| &*f.0)))
    }

    /// `self − other`.
    #[must_use]
    pub fn sub(&self, other: &NormalForm) -> NormalForm {
        NormalForm::from_rf(self.0.sub(&other.0))
    }

    /// `self · other`.
    #[must_use]
    pub fn mul(&self, other: &NormalForm) -> NormalForm {
        NormalForm::from_rf(self.0.mul(&other.0))
    }

    /// `−self`.
    #[must_use]
    pub fn neg(&self) -> NormalForm {
        NormalForm::from_rf(self.0.neg())
    }

    /// The partial derivative `∂self/∂var` (coordinates and rates independent), as
    /// [`Expr::diff`].
    #[must_use]
    pub fn diff(&self, var: Symbol) -> NormalForm {
        NormalForm::from_rf(partial_derivative_rf(&self.0, var))
    }

    /// `∂self/∂v` for every `v` of `vars`, each equal to [`NormalForm::diff`]; the terms are
    /// read once for all the variables.
    #[must_use]
    pub fn gradient(&self, vars: &[Symbol]) -> Vec<NormalForm> {
        let parts = gradient_rf(&self.0, vars);
        parts.into_iter().map(NormalForm::from_rf).collect()
    }

    /// The total time derivative, as [`Expr::dt`].
    #[must_use]
    pub fn dt(&self) -> NormalForm {
        NormalForm::from_rf(time_derivative_rf(&self.0))
    }

    /// The coefficients `c_j` and the remainder `r` of `Σ_j c_j x_j + r`, as
    /// [`Expr::affine_coefficients`]; `None` under the same conditions.
    #[must_use]
    pub fn affine_coefficients(&self, atoms: &[Expr]) -> Option<(Vec<NormalForm>, NormalForm)> {
        let (coefficients, rest) = affine_split(&self.0, atoms)?;
        Some((
            coefficients.into_iter().map(NormalForm::from_rf).collect(),
            NormalForm::from_rf(rest),
        ))
    }
}

impl Expr {
    /// The normal form in working form (see [`NormalForm`]); `e.normal_form().to_expr()` is
    /// `e.normal()`.
    #[must_use]
    pub fn normal_form(self) -> NormalForm {
        match cached_rf(self) {
            Some(r) => NormalForm(r),
            None => NormalForm::from_rf(to_rf(self)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn working_forms_give_the_trees_of_the_expression_operations() {
        let th = Expr::coordinate("form_theta");
        let ph = Expr::coordinate("form_phi");
        let thd = Expr::rate("form_theta", 1);
        let phd = Expr::rate("form_phi", 1);
        let l = Expr::symbol("form_l");
        // A Lagrangian large enough (> 8 terms) to be remembered with its working form, and a
        // small one that is not.
        let big = (l * thd.powi(2) * (th - ph).cos()
            + phd.powi(2) * (2 * th).sin()
            + thd * phd * (th + ph).cos()
            + l * th.cos() * ph.sin())
        .normal();
        let small = (l * thd * th.cos()).normal();
        for e in [big, small] {
            let f = e.normal_form();
            assert_eq!(f.to_expr(), e);
            for s in [th, thd, l].map(|x| x.as_symbol().unwrap()) {
                assert_eq!(f.diff(s).to_expr(), e.diff(s));
            }
            assert_eq!(f.dt().to_expr(), e.dt());
            assert_eq!(f.neg().to_expr(), (-e).normal());
            assert_eq!(f.sub(&small.normal_form()).to_expr(), (e - small).normal());
            assert_eq!(f.add(&big.normal_form()).to_expr(), (e + big).normal());
            assert_eq!(f.mul(&thd.normal_form()).to_expr(), (e * thd).normal());
            assert!(f.sub(&f).is_zero());
            assert!(!f.is_zero());
        }
        // A sum in one merge is the sum added term by term, fractions and all.
        let parts = [
            big.normal_form(),
            small.normal_form(),
            (Expr::one() / (l + th.cos())).normal_form(),
            big.normal_form().neg(),
            (thd / l).normal_form(),
        ];
        let folded = parts
            .iter()
            .fold(NormalForm::zero(), |s, p| s.add(p))
            .to_expr();
        assert_eq!(NormalForm::sum(&parts).to_expr(), folded);
        assert!(NormalForm::sum(&[]).is_zero());
        let dd = [Expr::rate("form_theta", 2), Expr::rate("form_phi", 2)];
        let eq = big.dt();
        let (row, rest) = eq.normal_form().affine_coefficients(&dd).unwrap();
        let (row_e, rest_e) = eq.affine_coefficients(&dd).unwrap();
        assert_eq!(
            row.iter().map(NormalForm::to_expr).collect::<Vec<_>>(),
            row_e
        );
        assert_eq!(rest.to_expr(), rest_e);
        assert!(big
            .normal_form()
            .affine_coefficients(&[thd.powi(2)])
            .is_none());
    }
}
