//! Kane's equations as expressions: the same derivation as at a numeric state
//! ([`KaneSystem::reduced`]), carried out over [`Sym`], a scalar that is an expression of the
//! `cas` together with its value at a sample state.
//!
//! The value only steers the choices that a numeric derivation makes by size (the pivots of
//! the eliminations): at a generic sample state an entry whose value is not zero is not the
//! zero expression. The expressions are then brought to the normal form one by one, under a
//! size limit on the graph first (the Whipple bicycle's reduced equations, expanded, are far
//! beyond anything worth printing) and the `cas` work limits after.

use std::collections::HashSet;
use std::ops::{Add, Div, Mul, Neg, Sub};

use cas::Expr;

use super::dynamics::{KaneSystem, SpeedSplit};
use super::scalar::Scalar;
use super::KaneError;

/// The most operations of the compiled geometry for which the symbolic form is attempted
/// (the rolling disk's has 43, the four-bar's 50; the Whipple bicycle's 404, whose expanded
/// equations pass the `cas` work limits after seconds).
pub const MAX_PROGRAM: usize = 200;
/// The most distinct expression nodes the reduced equations may have before the normal form.
pub const MAX_NODES: usize = 60_000;

/// An expression with its value at the sample state.
#[derive(Clone, Copy, Debug)]
pub struct Sym {
    /// The expression.
    pub expr: Expr,
    /// Its value at the sample state.
    pub value: f64,
}

/// Kane's reduced equations as expressions, in the normal form.
#[derive(Clone, Debug)]
pub struct KaneEquations {
    /// The coordinates, in the system's order.
    pub coordinates: Vec<String>,
    /// Which rates are the generalized speeds `u` (the rates of the independent
    /// coordinates), and which constraint rows fix the others.
    pub split: SpeedSplit,
    /// All rates `q̇ = T u + s` in the speeds (the kinematic differential equations; a speed's
    /// own rate is itself).
    pub rates: Vec<Expr>,
    /// `T` (n×p).
    pub speed_matrix: Vec<Vec<Expr>>,
    /// The accelerations the constraints need at `u̇ = 0`: `q̈ = T u̇ + bias`.
    pub bias: Vec<Expr>,
    /// `M_r = Tᵀ M T` (p×p).
    pub mass: Vec<Vec<Expr>>,
    /// `f_r`, so that `Fr + Fr* = f_r − M_r u̇ = 0`.
    pub forcing: Vec<Expr>,
}

impl KaneSystem {
    /// Kane's reduced equations as expressions, symbolic in the coordinates, the speeds and
    /// the named values. `q` and `values` are a sample state where the pivots are chosen
    /// (generic: no entry should vanish there that does not vanish everywhere).
    ///
    /// # Errors
    /// [`KaneError::TooLarge`] when the geometry or the equations pass the size limits,
    /// [`KaneError::WorkLimit`] when their normal form passes the `cas` work limits, or the
    /// errors of [`KaneSystem::split`] at the sample state.
    pub fn symbolic(&self, q: &[f64], values: &[f64]) -> Result<KaneEquations, KaneError> {
        if self.geometry.len() > MAX_PROGRAM {
            return Err(KaneError::TooLarge {
                what: "the compiled geometry",
                size: self.geometry.len(),
                limit: MAX_PROGRAM,
            });
        }
        let split = self.eom_split(q, values)?;
        self.symbolic_with(split, q, values)
    }

    /// As [`KaneSystem::symbolic`], with the speeds of `split` (a steady motion's: chosen
    /// where the motion is, so the cyclic coordinates' rates are the dependent ones there).
    ///
    /// # Errors
    /// As [`KaneSystem::symbolic`].
    pub fn symbolic_with(
        &self,
        split: SpeedSplit,
        q: &[f64],
        values: &[f64],
    ) -> Result<KaneEquations, KaneError> {
        if self.geometry.len() > MAX_PROGRAM {
            return Err(KaneError::TooLarge {
                what: "the compiled geometry",
                size: self.geometry.len(),
                limit: MAX_PROGRAM,
            });
        }
        let (qs, u, t, vals) = self.sample_symbols(&split, q, values);
        let r = self.reduced::<Sym>(&split, &qs, &u, t, &vals)?;
        let nodes = distinct_nodes(
            r.mass
                .iter()
                .flatten()
                .chain(&r.forcing)
                .chain(&r.rates)
                .chain(r.speed_matrix.iter().flatten())
                .chain(&r.bias)
                .map(|s| s.expr),
            MAX_NODES,
        );
        if nodes > MAX_NODES {
            return Err(KaneError::TooLarge {
                what: "the reduced equations",
                size: nodes,
                limit: MAX_NODES,
            });
        }
        cas::limited(|| KaneEquations {
            coordinates: self.coordinates.clone(),
            split: split.clone(),
            rates: normal_all(&r.rates),
            speed_matrix: r.speed_matrix.iter().map(|row| normal_all(row)).collect(),
            bias: normal_all(&r.bias),
            mass: r.mass.iter().map(|row| normal_all(row)).collect(),
            forcing: normal_all(&r.forcing),
        })
        .map_err(KaneError::WorkLimit)
    }

    /// The split for the equations of motion: cyclic coordinates preferred as the dependent
    /// ones (the contact point's `x`, `y` of a rolling disk), so the speeds are the rates
    /// the equations are about.
    pub fn eom_split(&self, q: &[f64], values: &[f64]) -> Result<SpeedSplit, KaneError> {
        let n = q.len();
        let (none, all) = (vec![false; n], vec![true; n]);
        let first = self.split(q, 0.0, values, &none, &all)?;
        if first.dependent.is_empty() {
            return Ok(first);
        }
        // Which coordinates are cyclic is judged where the holonomic constraints hold; when
        // they cannot be satisfied near the sample, no preference is given.
        let prefer = self
            .cyclic_and_preferred(q, 0.0, values)
            .map_or(none, |(_, prefer)| prefer);
        self.split(q, 0.0, values, &prefer, &all)
    }

    /// The variables as symbols with their sample values: coordinates, the speeds (the rates
    /// of the independent coordinates), time, the named values.
    fn sample_symbols(
        &self,
        split: &SpeedSplit,
        q: &[f64],
        values: &[f64],
    ) -> (Vec<Sym>, Vec<Sym>, Sym, Vec<Sym>) {
        let n = self.coordinates.len();
        let mut read: Vec<Option<Expr>> = vec![None; self.vars.len()];
        for (k, e) in self.geometry.symbols().iter().chain(self.rates.symbols()) {
            read[*k] = Some(*e);
        }
        let qs = (0..n)
            .map(|j| Sym {
                expr: read[j].unwrap_or_else(|| Expr::coordinate(&self.coordinates[j])),
                value: q[j],
            })
            .collect();
        let u = split
            .independent
            .iter()
            .enumerate()
            .map(|(k, j)| Sym {
                expr: read[n + j].unwrap_or_else(|| Expr::rate(&self.coordinates[*j], 1)),
                value: 0.6 + 0.17 * k as f64,
            })
            .collect();
        let t = Sym {
            expr: Expr::time(),
            value: 0.0,
        };
        let vals = values
            .iter()
            .enumerate()
            .map(|(k, v)| Sym {
                expr: read[2 * n + 1 + k].unwrap_or_else(|| Expr::symbol(&self.values[k])),
                value: *v,
            })
            .collect();
        (qs, u, t, vals)
    }
}

/// The normal form of each expression (inside a limited scope: a limit hit is the scope's).
fn normal_all(xs: &[Sym]) -> Vec<Expr> {
    xs.iter().map(|x| x.expr.normal()).collect()
}

/// The number of distinct nodes under `roots`, counted up to just past `limit`.
fn distinct_nodes(roots: impl Iterator<Item = Expr>, limit: usize) -> usize {
    let mut seen: HashSet<Expr> = HashSet::new();
    let mut stack: Vec<Expr> = roots.collect();
    while let Some(e) = stack.pop() {
        if seen.len() > limit {
            break;
        }
        if seen.insert(e) {
            stack.extend(e.children().iter().copied());
        }
    }
    seen.len()
}

/// `x` as an exact number where it is one with a small denominator (the constants of the
/// derivation: 0, 1, ½, the integer powers), a float otherwise.
pub(super) fn exact_number(x: f64) -> Expr {
    for den in [1_i64, 2, 3, 4, 6, 8, 12, 16] {
        let scaled = x * den as f64;
        if scaled.fract() == 0.0 && scaled.abs() < 1e15 {
            // In range: the cast is exact (checked just above).
            #[allow(clippy::cast_possible_truncation)]
            let num = scaled as i64;
            if let Some(r) = Expr::rational(num, den) {
                return r;
            }
        }
    }
    Expr::float(x)
}

impl Sym {
    fn of(expr: Expr, value: f64) -> Sym {
        Sym { expr, value }
    }
}

impl Add for Sym {
    type Output = Sym;
    fn add(self, o: Sym) -> Sym {
        Sym::of(self.expr + o.expr, self.value + o.value)
    }
}

impl Sub for Sym {
    type Output = Sym;
    fn sub(self, o: Sym) -> Sym {
        Sym::of(self.expr - o.expr, self.value - o.value)
    }
}

impl Mul for Sym {
    type Output = Sym;
    fn mul(self, o: Sym) -> Sym {
        Sym::of(self.expr * o.expr, self.value * o.value)
    }
}

impl Div for Sym {
    type Output = Sym;
    fn div(self, o: Sym) -> Sym {
        Sym::of(self.expr / o.expr, self.value / o.value)
    }
}

impl Neg for Sym {
    type Output = Sym;
    fn neg(self) -> Sym {
        Sym::of(-self.expr, -self.value)
    }
}

impl Scalar for Sym {
    const SYMBOLIC: bool = true;
    fn constant(x: f64) -> Sym {
        Sym::of(exact_number(x), x)
    }
    fn value(self) -> f64 {
        self.value
    }
    fn sin(self) -> Sym {
        Sym::of(self.expr.sin(), self.value.sin())
    }
    fn cos(self) -> Sym {
        Sym::of(self.expr.cos(), self.value.cos())
    }
    fn sqrt(self) -> Sym {
        Sym::of(self.expr.sqrt(), self.value.sqrt())
    }
    fn exp(self) -> Sym {
        Sym::of(self.expr.exp(), self.value.exp())
    }
    fn ln(self) -> Sym {
        Sym::of(self.expr.ln(), self.value.ln())
    }
    fn atan(self) -> Sym {
        Sym::of(self.expr.atan(), self.value.atan())
    }
    fn asin(self) -> Sym {
        Sym::of(self.expr.asin(), self.value.asin())
    }
    fn acos(self) -> Sym {
        Sym::of(self.expr.acos(), self.value.acos())
    }
    fn powi(self, k: i32) -> Sym {
        Sym::of(self.expr.powi(i64::from(k)), self.value.powi(k))
    }
    fn powf(self, p: f64) -> Sym {
        Sym::of(self.expr.pow(exact_number(p)), self.value.powf(p))
    }
    fn exact(exact: Expr, x: f64) -> Sym {
        Sym::of(exact, x)
    }
    fn pow_exact(self, exact: Expr, p: f64) -> Sym {
        Sym::of(self.expr.pow(exact), self.value.powf(p))
    }
    fn pow(self, e: Sym) -> Sym {
        Sym::of(self.expr.pow(e.expr), self.value.powf(e.value))
    }
    fn atan2(self, x: Sym) -> Sym {
        Sym::of(Expr::atan2(self.expr, x.expr), self.value.atan2(x.value))
    }
    fn abs(self) -> Sym {
        Sym::of(self.expr.abs(), self.value.abs())
    }
    fn sign(self) -> Sym {
        Sym::of(self.expr.sign(), self.signum())
    }
}
