//! Numbers that carry exact derivatives: `f64`, and dual numbers `a + b ε` (`ε² = 0`) over any
//! of them, nested to take several derivatives at once (forward-mode differentiation).
//!
//! Kane's equations need accelerations, so positions are evaluated at a truncated Taylor
//! series in time (a dual of a dual: `q + q̇ ε₁ + q̇ ε₂ + q̈ ε₁ε₂`); the linearization needs
//! their derivatives with respect to the state, one more dual level. Every operation is exact
//! to rounding: no step sizes.

use std::ops::{Add, Div, Mul, Neg, Sub};

use cas::Expr;

/// What the evaluation of a program needs from its numbers.
pub trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + std::fmt::Debug
{
    /// A constant.
    fn constant(x: f64) -> Self;
    /// The value, without any derivative.
    fn value(self) -> f64;
    /// Sine.
    fn sin(self) -> Self;
    /// Cosine.
    fn cos(self) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Exponential.
    fn exp(self) -> Self;
    /// Natural logarithm.
    fn ln(self) -> Self;
    /// Arctangent.
    fn atan(self) -> Self;
    /// Arcsine.
    fn asin(self) -> Self;
    /// `self` to an integer power.
    fn powi(self, k: i32) -> Self;
    /// `self` to a constant real power.
    fn powf(self, p: f64) -> Self;
    /// Whether the scalar carries expressions (then the exact constants are built; numeric
    /// scalars never touch the expression arena in their loops).
    const SYMBOLIC: bool = false;
    /// A constant known exactly as `exact` (a number of the model): symbolic scalars keep
    /// it, numeric ones take its value `x`.
    fn exact(exact: Expr, x: f64) -> Self {
        let _ = exact;
        Self::constant(x)
    }
    /// `self` to the constant power `exact` (value `p`), kept exact by symbolic scalars.
    fn pow_exact(self, exact: Expr, p: f64) -> Self {
        let _ = exact;
        self.powf(p)
    }
    /// `self` to a power that is itself a scalar: `exp(e ln self)`.
    fn pow(self, e: Self) -> Self {
        (e * self.ln()).exp()
    }
    /// `atan2(self, x)`: the angle of the point `(x, self)`.
    fn atan2(self, x: Self) -> Self;
    /// Arccosine.
    fn acos(self) -> Self {
        Self::constant(std::f64::consts::FRAC_PI_2) - self.asin()
    }
    /// `|self|` (its derivative the sign, where defined).
    fn abs(self) -> Self {
        self * Self::constant(self.signum())
    }
    /// The sign as a scalar (derivative zero where defined).
    fn sign(self) -> Self {
        Self::constant(self.signum())
    }
    /// The sign of the value (its derivative is zero where it is defined).
    fn signum(self) -> f64 {
        let v = self.value();
        if v > 0.0 {
            1.0
        } else if v < 0.0 {
            -1.0
        } else {
            0.0
        }
    }
}

impl Scalar for f64 {
    fn constant(x: f64) -> f64 {
        x
    }
    fn value(self) -> f64 {
        self
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
    fn exp(self) -> f64 {
        f64::exp(self)
    }
    fn ln(self) -> f64 {
        f64::ln(self)
    }
    fn atan(self) -> f64 {
        f64::atan(self)
    }
    fn asin(self) -> f64 {
        f64::asin(self)
    }
    fn powi(self, k: i32) -> f64 {
        f64::powi(self, k)
    }
    fn powf(self, p: f64) -> f64 {
        f64::powf(self, p)
    }
    fn atan2(self, x: f64) -> f64 {
        f64::atan2(self, x)
    }
}

/// `re + eps ε` with `ε² = 0`: the value and one directional derivative.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual<T> {
    /// The value.
    pub re: T,
    /// The derivative.
    pub eps: T,
}

impl<T: Scalar> Dual<T> {
    /// `re + eps ε`.
    pub fn new(re: T, eps: T) -> Dual<T> {
        Dual { re, eps }
    }

    /// `x` with no derivative.
    pub fn constant_of(x: T) -> Dual<T> {
        Dual::new(x, T::constant(0.0))
    }

    /// The chain rule: `f(re) + f'(re) eps ε`.
    fn chain(self, f: T, df: T) -> Dual<T> {
        Dual::new(f, df * self.eps)
    }
}

impl<T: Scalar> Add for Dual<T> {
    type Output = Dual<T>;
    fn add(self, o: Dual<T>) -> Dual<T> {
        Dual::new(self.re + o.re, self.eps + o.eps)
    }
}

impl<T: Scalar> Sub for Dual<T> {
    type Output = Dual<T>;
    fn sub(self, o: Dual<T>) -> Dual<T> {
        Dual::new(self.re - o.re, self.eps - o.eps)
    }
}

impl<T: Scalar> Mul for Dual<T> {
    type Output = Dual<T>;
    fn mul(self, o: Dual<T>) -> Dual<T> {
        Dual::new(self.re * o.re, self.re * o.eps + self.eps * o.re)
    }
}

impl<T: Scalar> Div for Dual<T> {
    type Output = Dual<T>;
    fn div(self, o: Dual<T>) -> Dual<T> {
        let q = self.re / o.re;
        Dual::new(q, (self.eps - q * o.eps) / o.re)
    }
}

impl<T: Scalar> Neg for Dual<T> {
    type Output = Dual<T>;
    fn neg(self) -> Dual<T> {
        Dual::new(-self.re, -self.eps)
    }
}

impl<T: Scalar> Scalar for Dual<T> {
    fn constant(x: f64) -> Dual<T> {
        Dual::new(T::constant(x), T::constant(0.0))
    }
    fn value(self) -> f64 {
        self.re.value()
    }
    fn sin(self) -> Dual<T> {
        self.chain(self.re.sin(), self.re.cos())
    }
    fn cos(self) -> Dual<T> {
        self.chain(self.re.cos(), -self.re.sin())
    }
    fn sqrt(self) -> Dual<T> {
        let s = self.re.sqrt();
        self.chain(s, T::constant(0.5) / s)
    }
    fn exp(self) -> Dual<T> {
        let e = self.re.exp();
        self.chain(e, e)
    }
    fn ln(self) -> Dual<T> {
        self.chain(self.re.ln(), T::constant(1.0) / self.re)
    }
    fn atan(self) -> Dual<T> {
        let one = T::constant(1.0);
        self.chain(self.re.atan(), one / (one + self.re * self.re))
    }
    fn asin(self) -> Dual<T> {
        let one = T::constant(1.0);
        self.chain(self.re.asin(), one / (one - self.re * self.re).sqrt())
    }
    fn powi(self, k: i32) -> Dual<T> {
        if k == 0 {
            return Dual::constant(1.0);
        }
        let below = self.re.powi(k - 1);
        self.chain(below * self.re, T::constant(f64::from(k)) * below)
    }
    fn powf(self, p: f64) -> Dual<T> {
        let below = self.re.powf(p - 1.0);
        self.chain(below * self.re, T::constant(p) * below)
    }
    fn exact(exact: Expr, x: f64) -> Dual<T> {
        Dual::constant_of(T::exact(exact, x))
    }
    const SYMBOLIC: bool = T::SYMBOLIC;
    fn pow_exact(self, exact: Expr, p: f64) -> Dual<T> {
        // `exact − 1` interns an expression: only a symbolic scalar needs it.
        let lowered = if T::SYMBOLIC { exact - 1 } else { exact };
        let below = self.re.pow_exact(lowered, p - 1.0);
        self.chain(below * self.re, T::exact(exact, p) * below)
    }
    fn atan2(self, x: Dual<T>) -> Dual<T> {
        // d atan2(y, x) = (x dy − y dx) / (x² + y²), exact with no branch to choose.
        let r2 = x.re * x.re + self.re * self.re;
        Dual::new(
            self.re.atan2(x.re),
            (x.re * self.eps - self.re * x.eps) / r2,
        )
    }
    fn acos(self) -> Dual<T> {
        let one = T::constant(1.0);
        self.chain(self.re.acos(), -(one / (one - self.re * self.re).sqrt()))
    }
    fn abs(self) -> Dual<T> {
        let s = self.re.sign();
        Dual::new(self.re.abs(), s * self.eps)
    }
    fn sign(self) -> Dual<T> {
        Dual::constant_of(self.re.sign())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn second_derivative_by_nesting() {
        // f(x) = x³ sin x at x = 0.7: f'' = 6x sin x + 6x² cos x − x³ sin x.
        let x = 0.7_f64;
        let d = Dual::new(Dual::new(x, 1.0), Dual::new(1.0, 0.0));
        let f = d.powi(3) * d.sin();
        let exact = 6.0 * x * x.sin() + 6.0 * x * x * x.cos() - x.powi(3) * x.sin();
        assert!((f.eps.eps - exact).abs() < 1e-14);
        assert!((f.re.re - x.powi(3) * x.sin()).abs() < 1e-15);
    }
}
