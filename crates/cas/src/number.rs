//! Numbers of the symbolic core: exact rationals of any size, and floats where numeric work
//! asks for one.
//!
//! [`Number`] keeps a fast path for rationals whose numerator and denominator fit in an `i64`
//! and moves to big integers on overflow, so arithmetic is exact and never wraps silently.
//! A number literal is exact whatever its form ([`Number::parse_literal`]: `0.7` is 7/10,
//! `1e-3` is 1/1000), so no float enters an expression from what a user wrote. Floats are
//! contagious (a float plus a rational is a float), as in every CAS; they come only from
//! numeric evaluation ([`Expr::float`](crate::Expr::float)).

use std::cmp::Ordering;
use std::fmt;
use std::hash::{Hash, Hasher};

use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

/// The largest exponent a number literal may be written with (`1e10000` is accepted,
/// `1e10001` is not): its exact value has about 33,000 bits, while `1e1000000000` would take
/// gigabytes.
pub const MAX_LITERAL_EXPONENT: u32 = 10_000;

/// Why a number literal was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum LiteralError {
    /// The text is not a number literal.
    #[error("malformed number `{0}`")]
    Malformed(String),
    /// The written exponent is beyond ±[`MAX_LITERAL_EXPONENT`].
    #[error("the exponent of `{text}` is beyond ±{limit}")]
    ExponentTooLarge {
        /// The literal as written.
        text: String,
        /// The largest exponent allowed.
        limit: u32,
    },
}

/// The exponent of a literal (after its `e`): an optional sign and digits, at most
/// [`MAX_LITERAL_EXPONENT`] in size.
fn parse_exponent(exponent: &str, text: &str) -> Result<i64, LiteralError> {
    let digits = exponent.strip_prefix(['+', '-']).unwrap_or(exponent);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return Err(LiteralError::Malformed(text.to_owned()));
    }
    let too_large = || LiteralError::ExponentTooLarge {
        text: text.to_owned(),
        limit: MAX_LITERAL_EXPONENT,
    };
    let significant = digits.trim_start_matches('0');
    // More than ten digits cannot be within the limit (and would overflow the parse).
    if significant.len() > 10 {
        return Err(too_large());
    }
    let size: i64 = significant.parse().unwrap_or(0);
    if size > i64::from(MAX_LITERAL_EXPONENT) {
        return Err(too_large());
    }
    Ok(if exponent.starts_with('-') {
        -size
    } else {
        size
    })
}

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

    /// Parses a number literal (`12`, `0.5`, `.5`, `2.`, `1e-3`, `2.5E+4`) to its exact value:
    /// `0.7` is 7/10, `9.81` is 981/100, `1e-3` is 1/1000, `2e0` is 2.
    ///
    /// # Errors
    /// [`LiteralError::Malformed`] for text that is not a literal, and
    /// [`LiteralError::ExponentTooLarge`] for a written exponent beyond
    /// ±[`MAX_LITERAL_EXPONENT`] (its exact value would take unbounded memory).
    pub fn parse_literal(text: &str) -> Result<Number, LiteralError> {
        let malformed = || LiteralError::Malformed(text.to_owned());
        let (digits, exponent) = match text.find(['e', 'E']) {
            Some(at) => (&text[..at], parse_exponent(&text[at + 1..], text)?),
            None => (text, 0),
        };
        let (integer, fraction) = digits.split_once('.').unwrap_or((digits, ""));
        let all_digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
        if (integer.is_empty() && fraction.is_empty())
            || !all_digits(integer)
            || !all_digits(fraction)
        {
            return Err(malformed());
        }
        let mantissa: BigInt = format!("{integer}{fraction}")
            .parse()
            .map_err(|_| malformed())?;
        // The fraction's digits are part of the text, so this shift is bounded by the input's
        // length plus the bounded exponent.
        let shift = exponent - i64::try_from(fraction.len()).map_err(|_| malformed())?;
        let power = num_traits::pow(BigInt::from(10), shift.unsigned_abs() as usize);
        let value = if shift >= 0 {
            BigRational::from_integer(mantissa * power)
        } else {
            BigRational::new(mantissa, power)
        };
        Ok(Self::from_big(value))
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

    /// The value as a terminating decimal `digits × 10^exponent` (`exponent < 0`, `digits`
    /// not a multiple of 10) when it is an exact rational whose denominator has no prime factor
    /// but 2 and 5 and is a multiple of 10 or of 25: the numbers people write as decimals
    /// (`7/10` is `(7, −1)`, `49/200` is `(245, −3)`, `1/25` is `(4, −2)`). `None` for integers,
    /// for `1/2`, `3/8`, `2/5`, `1/3` (which read better as fractions) and for floats.
    pub fn to_decimal(&self) -> Option<(BigInt, i64)> {
        let (digits, exponent, twos, fives) = self.terminating_decimal()?;
        // Powers of 2 (`1/2`, `3/8`) and small ones of 5 (`2/5`) read better as fractions;
        // `0.7`, `0.245`, `123.456` (= 15432/125) as decimals.
        (fives > 0 && (twos > 0 || fives >= 2)).then_some((digits, exponent))
    }

    /// The value as a decimal `digits × 10^exponent` when it is a non-integer exact rational
    /// whose denominator has no prime factor but 2 and 5 (`1/2` is `(5, −1)`): how a number
    /// standing alone, such as a parameter's value, reads best. `None` otherwise.
    pub fn to_terminating_decimal(&self) -> Option<(BigInt, i64)> {
        self.terminating_decimal()
            .map(|(digits, exponent, _, _)| (digits, exponent))
    }

    /// `(digits, exponent, a, b)` for a denominator `2^a 5^b > 1`.
    fn terminating_decimal(&self) -> Option<(BigInt, i64, u64, u64)> {
        let (num, den) = self.to_big_ratio()?;
        let two = BigInt::from(2);
        let five = BigInt::from(5);
        let (mut twos, mut fives) = (0u64, 0u64);
        let mut rest = den;
        while (&rest % &two).is_zero() {
            rest /= &two;
            twos += 1;
        }
        while (&rest % &five).is_zero() {
            rest /= &five;
            fives += 1;
        }
        if !rest.is_one() || twos + fives == 0 {
            return None;
        }
        // num/(2^a 5^b) = num 2^(k−a) 5^(k−b) / 10^k with k = max(a, b).
        let k = twos.max(fives);
        let scale =
            num_traits::pow(two, (k - twos) as usize) * num_traits::pow(five, (k - fives) as usize);
        Some((num * scale, -i64::try_from(k).ok()?, twos, fives))
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
            _ => self.big_op(other, |x, y| {
                if x.is_integer() && y.is_integer() {
                    BigRational::from_integer(x.to_integer() + y.to_integer())
                } else {
                    x + y
                }
            }),
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
            // Integers multiply without the rational cross-reduction: `num_rational` takes
            // `gcd(n, 1)` by Stein's algorithm, one shift of the whole number per bit, which
            // made the coefficient products of a GCD's remainder sequence quadratic in their
            // size (the four-bar's reactions spent most of 5 s there).
            _ => self.big_op(other, |x, y| {
                if x.is_integer() && y.is_integer() {
                    BigRational::from_integer(x.to_integer() * y.to_integer())
                } else {
                    x * y
                }
            }),
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
                // Not `Ratio`'s own hash: it follows the continued fraction recursively, one
                // stack frame per partial quotient, and overflowed the stack on a 10⁵-digit
                // power (`1.069999999999**9998`). A big number is always in lowest terms with
                // a positive denominator, so its numerator and denominator are its identity.
                1u8.hash(state);
                r.numer().hash(state);
                r.denom().hash(state);
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

    /// A number whose continued fraction is long (consecutive Fibonacci numbers: [1; 1, 1, …],
    /// 100,000 partial quotients) hashes without recursing on it: `Ratio`'s own hash took one
    /// stack frame per quotient and overflowed the stack (found by the property test
    /// `mutated_printed_text_never_panics` on `1.069999999999**9998`).
    #[test]
    fn a_big_number_with_a_long_continued_fraction_hashes_and_equal_ones_agree() {
        let (mut a, mut b) = (BigInt::one(), BigInt::one());
        for _ in 0..100_000 {
            let next = &a + &b;
            a = std::mem::replace(&mut b, next);
        }
        let ratio = Number::from_big(BigRational::new(b.clone(), a.clone()));
        assert!(matches!(ratio, Number::Big(_)));
        let hash = |n: &Number| {
            let mut h = std::collections::hash_map::DefaultHasher::new();
            n.hash(&mut h);
            h.finish()
        };
        // The same value built another way (not reduced by hand: `new` reduces) hashes alike.
        let again = Number::from_big(BigRational::new(&b * 3, &a * 3));
        assert_eq!(ratio, again);
        assert_eq!(hash(&ratio), hash(&again));
        assert_ne!(
            hash(&ratio),
            hash(&Number::from_big(BigRational::new(a, b)))
        );
    }

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
        assert_eq!(Number::parse_literal("12"), Ok(Number::int(12)));
        assert!(Number::parse_literal("123456789012345678901234567890")
            .unwrap()
            .is_integer());
        assert_eq!(Number::Float(0.1).to_string(), "0.1");
        assert_eq!(Number::Float(3.0).to_string(), "3.0");
    }

    /// Issue 23: a decimal literal is an exact rational, never a float.
    #[test]
    fn decimal_literals_are_exact_rationals() {
        let lit = |t: &str| Number::parse_literal(t).unwrap();
        let q = |n, d| Number::rational(n, d).unwrap();
        assert_eq!(lit("0.7"), q(7, 10));
        assert_eq!(lit("9.81"), q(981, 100));
        assert_eq!(lit("1e-3"), q(1, 1000));
        assert_eq!(lit("2e0"), Number::int(2));
        assert_eq!(lit("2.5E+4"), Number::int(25_000));
        assert_eq!(lit(".5"), q(1, 2));
        assert_eq!(lit("2."), Number::int(2));
        assert_eq!(lit("0.000"), Number::ZERO);
        assert_eq!(lit("1.50e-1"), q(3, 20));
        let big = lit("1e308").mul(&Number::int(10));
        let expected: BigInt = num_traits::pow(BigInt::from(10), 309);
        assert_eq!(big, Number::from(expected));
        assert!(!lit("1e-320").is_float() && lit("1e-320").signum() == 1);
        assert_eq!(lit("1e10000").denom(), Number::ONE);
    }

    #[test]
    fn numbers_people_write_as_decimals() {
        let dec = |n: i64, d: i64| Number::rational(n, d).unwrap().to_decimal();
        let d = |digits: i64, exponent: i64| Some((BigInt::from(digits), exponent));
        assert_eq!(dec(7, 10), d(7, -1));
        assert_eq!(dec(-981, 100), d(-981, -2));
        assert_eq!(dec(49, 200), d(245, -3));
        assert_eq!(dec(1, 1000), d(1, -3));
        assert_eq!(dec(1, 2), None);
        assert_eq!(dec(2, 5), None);
        assert_eq!(dec(3, 8), None);
        assert_eq!(dec(1, 25), d(4, -2));
        assert_eq!(dec(15432, 125), d(123_456, -3));
        assert_eq!(dec(1, 30), None);
        assert_eq!(dec(3, 1), None);
        assert_eq!(Number::Float(0.5).to_decimal(), None);
        let alone = |n: i64, d: i64| Number::rational(n, d).unwrap().to_terminating_decimal();
        assert_eq!(alone(1, 2), d(5, -1));
        assert_eq!(alone(3, 5), d(6, -1));
        assert_eq!(alone(1, 3), None);
        assert_eq!(alone(4, 1), None);
    }

    #[test]
    fn literals_beyond_the_exponent_limit_or_malformed_are_refused() {
        for text in ["1e10001", "1e-1000000000", "1e99999999999999999999999"] {
            assert_eq!(
                Number::parse_literal(text),
                Err(LiteralError::ExponentTooLarge {
                    text: text.to_owned(),
                    limit: MAX_LITERAL_EXPONENT
                })
            );
        }
        for text in ["", ".", "1e", "1e+", "x", "1.2.3", "-1", "1e-3.5", "١"] {
            assert_eq!(
                Number::parse_literal(text),
                Err(LiteralError::Malformed(text.to_owned())),
                "{text}"
            );
        }
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
