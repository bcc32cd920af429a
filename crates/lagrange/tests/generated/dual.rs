//! Forward-mode automatic differentiation for the independent numeric route: a dual number
//! `a + b ε` (ε² = 0) generic over its components, so that `Dual<Dual<f64>>` is a hyper-dual
//! number (exact first and mixed second derivatives, no step size) and one more level gives
//! velocities as directional derivatives of positions.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// What the numeric route computes with: `f64` or nested duals of it.
pub trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// A constant.
    fn c(x: f64) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn sqrt(self) -> Self;
}

impl Scalar for f64 {
    fn c(x: f64) -> f64 {
        x
    }
    fn sin(self) -> f64 {
        f64::sin(self)
    }
    fn cos(self) -> f64 {
        f64::cos(self)
    }
    fn sqrt(self) -> f64 {
        f64::sqrt(self)
    }
}

/// `v + d ε` with ε² = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual<T> {
    pub v: T,
    pub d: T,
}

impl<T: Scalar> Dual<T> {
    pub fn new(v: T, d: T) -> Self {
        Dual { v, d }
    }
}

impl<T: Scalar> Add for Dual<T> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Dual::new(self.v + o.v, self.d + o.d)
    }
}

impl<T: Scalar> Sub for Dual<T> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Dual::new(self.v - o.v, self.d - o.d)
    }
}

impl<T: Scalar> Mul for Dual<T> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Dual::new(self.v * o.v, self.v * o.d + self.d * o.v)
    }
}

impl<T: Scalar> Div for Dual<T> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        let v = self.v / o.v;
        Dual::new(v, (self.d - v * o.d) / o.v)
    }
}

impl<T: Scalar> Neg for Dual<T> {
    type Output = Self;
    fn neg(self) -> Self {
        Dual::new(-self.v, -self.d)
    }
}

impl<T: Scalar> Scalar for Dual<T> {
    fn c(x: f64) -> Self {
        Dual::new(T::c(x), T::c(0.0))
    }
    fn sin(self) -> Self {
        Dual::new(self.v.sin(), self.d * self.v.cos())
    }
    fn cos(self) -> Self {
        Dual::new(self.v.cos(), -(self.d * self.v.sin()))
    }
    fn sqrt(self) -> Self {
        let r = self.v.sqrt();
        Dual::new(r, self.d / (r + r))
    }
}

/// A hyper-dual number: `∂/∂a` in the outer ε, `∂/∂b` in the inner one, `∂²/∂a∂b` in both.
pub type Hyper = Dual<Dual<f64>>;

/// `x` seeded along the directions `a` (outer) and `b` (inner) with weights `da`, `db`.
pub fn hyper(x: f64, da: f64, db: f64) -> Hyper {
    Dual::new(Dual::new(x, db), Dual::new(da, 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hyper_dual_gives_exact_mixed_second_derivatives() {
        // f(x, y) = sin(x y)/√x: f_y = √x cos(xy), f_xy = cos(xy)/(2√x) − √x y sin(xy).
        let (x, y) = (0.7, 1.3);
        let f = |x: Hyper, y: Hyper| (x * y).sin() / x.sqrt();
        let got = f(hyper(x, 1.0, 0.0), hyper(y, 0.0, 1.0));
        let s = x.sqrt();
        let fxy = 0.5 * (x * y).cos() / s - s * y * (x * y).sin();
        assert!((got.d.d - fxy).abs() < 1e-14, "{} vs {fxy}", got.d.d);
        let fx = y * (x * y).cos() / s - 0.5 * (x * y).sin() / (x * s);
        assert!((got.d.v - fx).abs() < 1e-14);
        assert!((got.v.d - x * (x * y).cos() / s).abs() < 1e-14);
    }
}
