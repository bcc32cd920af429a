//! Numbers of the symbolic core: exact rationals of any size, and floats where a user wrote a
//! decimal.
//!
//! [`Number`] keeps a fast path for rationals whose numerator and denominator fit in an `i64`
//! and moves to big integers on overflow, so arithmetic is exact and never wraps silently.
//! Floats are contagious (a float plus a rational is a float), as in every CAS; they only enter
//! an expression when a user writes a decimal literal or asks for one.

use std::cmp::Ordering;
use std::fmt;
use std::hash::{Hash, Hasher};

use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

/// An exact rational (small or big) or a float.
///
/// Invariant: a `Small` rational has `den > 0` and `gcd(num, den) = 1`; a `Big` rational does
/// not fit the `Small` form (so equal values have equal representations).
#[derive(Clone, Debug)]
pub enum Number {
    /// A rational whose parts fit in `i64`.
    Small {
        /// Numerator.
        num: i64,
        /// Denominator, positive.
        den: i64,
    },
    /// A rational that needs big integers.
    Big(Box<BigRational>),
    /// A floating-point value (only from decimals a user wrote, or from numeric evaluation).
    Float(f64),
}

impl Number {
    /// The integer `n`.
    pub const fn int(n: i64) -> Number {
        Number::Small { num: n, den: 1 }
    }

    /// Zero.
    pub const ZERO: Number = Number::int(0);
    /// One.
    pub const ONE: Number = Number::int(1);

    /// The rational `num / den`; `None` when `den` is zero.
    pub fn rational(num: i64, den: i64) -> Option<Number> {
        if den == 0 {
            return None;
        }
        Some(Self::from_i128(num as i128, den as i128))
    }

    /// The rational `num / den` from big integers; `None` when `den` is zero.
    pub fn big_rational(num: BigInt, den: BigInt) -> Option<Number> {
        if den.is_zero() {
            return None;
        }
        Some(Self::from_big(BigRational::new(num, den)))
    }

    /// A float.
    pub fn float(x: f64) -> Number {
        Number::Float(x)
    }

    /// Parses a decimal literal as written (`12`, `0.5`, `1e-3`, `2.5E+4`): an integer literal is
    /// exact, a literal with a point or an exponent is a float, as the user wrote it.
    pub fn parse_literal(text: &str) -> Option<Number> {
        if text.bytes().all(|b| b.is_ascii_digit()) && !text.is_empty() {
            let n: BigInt = text.parse().ok()?;
            return Some(Self::from_big(BigRational::from_integer(n)));
        }
        let x: f64 = text.parse().ok()?;
        x.is_finite().then_some(Number::Float(x))
    }

    fn from_i128(num: i128, den: i128) -> Number {
        let g = num.gcd(&den);
        let (mut n, mut d) = if g == 0 { (0, 1) } else { (num / g, den / g) };
        if d < 0 {
            n = -n;
            d = -d;
        }
        match (i64::try_from(n), i64::try_from(d)) {
            (Ok(num), Ok(den)) => Number::Small { num, den },
            _ => Number::Big(Box::new(BigRational::new(BigInt::from(n), BigInt::from(d)))),
        }
    }

    fn from_big(r: BigRational) -> Number {
        match (r.numer().to_i64(), r.denom().to_i64()) {
            (Some(num), Some(den)) => Number::Small { num, den },
            _ => Number::Big(Box::new(r)),
        }
    }

    fn to_big(&self) -> Option<BigRational> {
        match self {
            Number::Small { num, den } => {
                Some(BigRational::new_raw(BigInt::from(*num), BigInt::from(*den)))
            }
            Number::Big(r) => Some((**r).clone()),
            Number::Float(_) => None,
        }
    }

    /// Whether this is exactly zero (a float `0.0` counts).
    pub fn is_zero(&self) -> bool {
        match self {
            Number::Small { num, .. } => *num == 0,
            Number::Big(_) => false,
            Number::Float(x) => *x == 0.0,
        }
    }

    /// Whether this is an exact (not float) zero: the terms that may be dropped.
    pub fn is_exact_zero(&self) -> bool {
        matches!(self, Number::Small { num: 0, .. })
    }

    /// Whether this is an exact (not float) one: the factors that may be dropped.
    pub fn is_exact_one(&self) -> bool {
        matches!(self, Number::Small { num: 1, den: 1 })
    }

    /// A measure of the cost of arithmetic with this number: 1 for small ones, the number of
    /// 64-bit words for big ones.
    pub fn size_hint(&self) -> usize {
        match self {
            Number::Big(r) => ((r.numer().bits() + r.denom().bits()) / 64) as usize + 1,
            _ => 1,
        }
    }

    /// Whether this is exactly one.
    pub fn is_one(&self) -> bool {
        matches!(self, Number::Small { num: 1, den: 1 })
            || matches!(self, Number::Float(x) if *x == 1.0)
    }

    /// Whether this is exactly minus one.
    pub fn is_minus_one(&self) -> bool {
        matches!(self, Number::Small { num: -1, den: 1 })
            || matches!(self, Number::Float(x) if *x == -1.0)
    }

    /// Whether this is a float.
    pub fn is_float(&self) -> bool {
        matches!(self, Number::Float(_))
    }

    /// Whether this is an exact integer.
    pub fn is_integer(&self) -> bool {
        match self {
            Number::Small { den, .. } => *den == 1,
            Number::Big(r) => r.is_integer(),
            Number::Float(_) => false,
        }
    }

    /// The value as an `i64` when it is an exact integer that fits.
    pub fn to_i64(&self) -> Option<i64> {
        match self {
            Number::Small { num, den: 1 } => Some(*num),
            _ => None,
        }
    }

    /// Numerator and denominator of an exact rational that fits in `i64`.
    pub fn to_small_ratio(&self) -> Option<(i64, i64)> {
        match self {
            Number::Small { num, den } => Some((*num, *den)),
            _ => None,
        }
    }

    /// Numerator and denominator as big integers (`None` for floats).
    pub fn to_big_ratio(&self) -> Option<(BigInt, BigInt)> {
        self.to_big()
            .map(|r| (r.numer().clone(), r.denom().clone()))
    }

    /// The nearest `f64`.
    pub fn to_f64(&self) -> f64 {
        match self {
            Number::Small { num, den } => *num as f64 / *den as f64,
            Number::Big(r) => {
                // Scale both parts down together so that huge numerators and denominators
                // still give a finite quotient.
                let (n, d) = (r.numer(), r.denom());
                let shift = n.bits().max(d.bits()).saturating_sub(1000);
                let n = n >> shift as usize;
                let d = d >> shift as usize;
                n.to_f64().unwrap_or(f64::NAN) / d.to_f64().unwrap_or(f64::NAN)
            }
            Number::Float(x) => *x,
        }
    }

    /// The sign: -1, 0 or 1.
    pub fn signum(&self) -> i32 {
        match self {
            Number::Small { num, .. } => num.signum() as i32,
            Number::Big(r) => {
                if r.is_positive() {
                    1
                } else if r.is_negative() {
                    -1
                } else {
                    0
                }
            }
            Number::Float(x) => {
                if *x > 0.0 {
                    1
                } else if *x < 0.0 {
                    -1
                } else {
                    0
                }
            }
        }
    }

    /// Whether this is negative.
    pub fn is_negative(&self) -> bool {
        self.signum() < 0
    }

    /// The numerator of an exact rational, as a number (floats are their own numerator).
    pub fn numer(&self) -> Number {
        match self {
            Number::Small { num, .. } => Number::int(*num),
            Number::Big(r) => Self::from_big(BigRational::from_integer(r.numer().clone())),
            Number::Float(_) => self.clone(),
        }
    }

    /// The denominator of an exact rational (1 for floats).
    pub fn denom(&self) -> Number {
        match self {
            Number::Small { den, .. } => Number::int(*den),
            Number::Big(r) => Self::from_big(BigRational::from_integer(r.denom().clone())),
            Number::Float(_) => Number::ONE,
        }
    }

    /// The sum.
    pub fn add(&self, other: &Number) -> Number {
        match (self, other) {
            (Number::Small { num: a, den: b }, Number::Small { num: c, den: d }) => {
                if *b == 1 && *d == 1 {
                    if let Some(s) = a.checked_add(*c) {
                        return Number::int(s);
                    }
                }
                let (a, b, c, d) = (*a as i128, *b as i128, *c as i128, *d as i128);
                match (a.checked_mul(d), c.checked_mul(b), b.checked_mul(d)) {
                    (Some(x), Some(y), Some(z)) => match x.checked_add(y) {
                        Some(s) => Self::from_i128(s, z),
                        None => self.big_op(other, |x, y| x + y),
                    },
                    _ => self.big_op(other, |x, y| x + y),
                }
            }
            (Number::Float(x), o) | (o, Number::Float(x)) => Number::Float(x + o.to_f64()),
            _ => self.big_op(other, |x, y| x + y),
        }
    }

    /// The difference.
    pub fn sub(&self, other: &Number) -> Number {
        self.add(&other.neg())
    }

    /// The product.
    pub fn mul(&self, other: &Number) -> Number {
        match (self, other) {
            (Number::Small { num: a, den: b }, Number::Small { num: c, den: d }) => {
                if *b == 1 && *d == 1 {
                    if let Some(p) = a.checked_mul(*c) {
                        return Number::int(p);
                    }
                }
                let (a, b, c, d) = (*a as i128, *b as i128, *c as i128, *d as i128);
                match (a.checked_mul(c), b.checked_mul(d)) {
                    (Some(x), Some(y)) => Self::from_i128(x, y),
                    _ => self.big_op(other, |x, y| x * y),
                }
            }
            (Number::Float(x), o) | (o, Number::Float(x)) => Number::Float(x * o.to_f64()),
            _ => self.big_op(other, |x, y| x * y),
        }
    }

    /// The quotient; `None` when dividing by an exact zero.
    pub fn div(&self, other: &Number) -> Option<Number> {
        match other {
            Number::Float(y) => Some(Number::Float(self.to_f64() / y)),
            _ if other.is_zero() => None,
            _ => Some(self.mul(&other.recip()?)),
        }
    }

    /// The reciprocal; `None` for an exact zero.
    pub fn recip(&self) -> Option<Number> {
        match self {
            Number::Small { num, den } => {
                if *num == 0 {
                    None
                } else {
                    Some(Self::from_i128(*den as i128, *num as i128))
                }
            }
            Number::Big(r) => Some(Self::from_big(r.recip())),
            Number::Float(x) => Some(Number::Float(1.0 / x)),
        }
    }

    /// The negation.
    pub fn neg(&self) -> Number {
        match self {
            Number::Small { num, den } => match num.checked_neg() {
                Some(n) => Number::Small { num: n, den: *den },
                None => Self::from_i128(-(*num as i128), *den as i128),
            },
            Number::Big(r) => Self::from_big(-(**r).clone()),
            Number::Float(x) => Number::Float(-x),
        }
    }

    /// The absolute value.
    pub fn abs(&self) -> Number {
        if self.is_negative() {
            self.neg()
        } else {
            self.clone()
        }
    }

    /// `self` raised to an integer power; `None` for `0` to a negative power.
    pub fn powi(&self, exp: i64) -> Option<Number> {
        if let Number::Float(x) = self {
            return Some(Number::Float(
                x.powi(exp.clamp(i32::MIN as i64, i32::MAX as i64) as i32),
            ));
        }
        if exp < 0 {
            return self.recip()?.powi(exp.checked_neg()?);
        }
        let mut result = Number::ONE;
        let mut base = self.clone();
        let mut e = exp as u64;
        while e > 0 {
            if e & 1 == 1 {
                result = result.mul(&base);
            }
            e >>= 1;
            if e > 0 {
                base = base.mul(&base);
            }
        }
        Some(result)
    }

    /// Greatest common divisor of two exact rationals (`gcd(a/b, c/d) = gcd(a,c)/lcm(b,d)`),
    /// always non-negative; for floats it is 1.
    pub fn gcd(&self, other: &Number) -> Number {
        match (self.to_big(), other.to_big()) {
            (Some(x), Some(y)) => {
                let n = x.numer().gcd(y.numer());
                let d = x.denom().lcm(y.denom());
                Self::from_big(BigRational::new(n, d))
            }
            _ => Number::ONE,
        }
    }

    /// The exact `q`-th root of a non-negative rational when it is rational.
    pub fn exact_root(&self, q: u32) -> Option<Number> {
        let (n, d) = self.to_big_ratio()?;
        if n.is_negative() {
            return None;
        }
        let rn = n.nth_root(q);
        let rd = d.nth_root(q);
        if num_traits::pow(rn.clone(), q as usize) == n
            && num_traits::pow(rd.clone(), q as usize) == d
        {
            Some(Self::from_big(BigRational::new(rn, rd)))
        } else {
            None
        }
    }

    fn big_op(
        &self,
        other: &Number,
        op: impl Fn(BigRational, BigRational) -> BigRational,
    ) -> Number {
        match (self.to_big(), other.to_big()) {
            (Some(x), Some(y)) => Self::from_big(op(x, y)),
            _ => Number::Float(f64::NAN),
        }
    }

    /// A total order: exact numbers by value, floats by value after them when equal; used to
    /// sort terms deterministically.
    pub fn total_cmp(&self, other: &Number) -> Ordering {
        match (self, other) {
            (Number::Small { num: a, den: b }, Number::Small { num: c, den: d }) => {
                ((*a as i128) * (*d as i128)).cmp(&((*c as i128) * (*b as i128)))
            }
            (Number::Float(x), Number::Float(y)) => x.total_cmp(y),
            (Number::Float(_), _) => Ordering::Greater,
            (_, Number::Float(_)) => Ordering::Less,
            _ => match (self.to_big(), other.to_big()) {
                (Some(x), Some(y)) => x.cmp(&y),
                _ => Ordering::Equal,
            },
        }
    }
}

impl PartialEq for Number {
    fn eq(&self, other: &Number) -> bool {
        match (self, other) {
            (Number::Small { num: a, den: b }, Number::Small { num: c, den: d }) => {
                a == c && b == d
            }
            (Number::Big(x), Number::Big(y)) => x == y,
            (Number::Float(x), Number::Float(y)) => x.to_bits() == y.to_bits(),
            _ => false,
        }
    }
}

impl Eq for Number {}

impl Hash for Number {
    fn hash<H: Hasher>(&self, state: &mut H) {
        match self {
            Number::Small { num, den } => {
                0u8.hash(state);
                num.hash(state);
                den.hash(state);
            }
            Number::Big(r) => {
                1u8.hash(state);
                r.hash(state);
            }
            Number::Float(x) => {
                2u8.hash(state);
                x.to_bits().hash(state);
            }
        }
    }
}

impl From<i64> for Number {
    fn from(n: i64) -> Number {
        Number::int(n)
    }
}

impl From<BigInt> for Number {
    fn from(n: BigInt) -> Number {
        Number::from_big(BigRational::from_integer(n))
    }
}

impl fmt::Display for Number {
    /// Exact rationals print as `p/q`; floats print in the shortest form that reads back to
    /// the same value, always with a point or an exponent so that they read back as floats.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Number::Small { num, den: 1 } => write!(f, "{num}"),
            Number::Small { num, den } => write!(f, "{num}/{den}"),
            Number::Big(r) if r.is_integer() => write!(f, "{}", r.numer()),
            Number::Big(r) => write!(f, "{}/{}", r.numer(), r.denom()),
            Number::Float(x) => {
                let s = format!("{x:?}");
                f.write_str(&s)
            }
        }
    }
}

impl Zero for Number {
    fn zero() -> Number {
        Number::ZERO
    }
    fn is_zero(&self) -> bool {
        Number::is_zero(self)
    }
}

impl One for Number {
    fn one() -> Number {
        Number::ONE
    }
}

impl std::ops::Add for Number {
    type Output = Number;
    fn add(self, rhs: Number) -> Number {
        Number::add(&self, &rhs)
    }
}

impl std::ops::Mul for Number {
    type Output = Number;
    fn mul(self, rhs: Number) -> Number {
        Number::mul(&self, &rhs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_arithmetic_is_exact_and_reduced() {
        let a = Number::rational(1, 3).unwrap();
        let b = Number::rational(1, 6).unwrap();
        assert_eq!(a.add(&b), Number::rational(1, 2).unwrap());
        assert_eq!(a.mul(&b), Number::rational(1, 18).unwrap());
        assert_eq!(
            Number::rational(2, -4).unwrap(),
            Number::rational(-1, 2).unwrap()
        );
    }

    #[test]
    fn overflow_moves_to_big_integers_and_back() {
        let big = Number::int(i64::MAX);
        let sq = big.mul(&big);
        assert!(matches!(sq, Number::Big(_)));
        let back = sq.div(&big).unwrap();
        assert_eq!(back, Number::int(i64::MAX));
        assert_eq!(
            Number::int(i64::MIN).neg().sub(&Number::ONE),
            Number::int(i64::MAX)
        );
    }

    #[test]
    fn literals_keep_what_the_user_wrote() {
        assert_eq!(Number::parse_literal("12"), Some(Number::int(12)));
        assert_eq!(Number::parse_literal("0.5"), Some(Number::Float(0.5)));
        assert!(Number::parse_literal("123456789012345678901234567890")
            .unwrap()
            .is_integer());
        assert_eq!(Number::Float(0.1).to_string(), "0.1");
        assert_eq!(Number::Float(3.0).to_string(), "3.0");
    }

    #[test]
    fn roots_and_gcd() {
        assert_eq!(
            Number::rational(9, 4).unwrap().exact_root(2),
            Some(Number::rational(3, 2).unwrap())
        );
        assert_eq!(Number::int(8).exact_root(2), None);
        assert_eq!(
            Number::rational(2, 3)
                .unwrap()
                .gcd(&Number::rational(4, 9).unwrap()),
            Number::rational(2, 9).unwrap()
        );
    }
}
