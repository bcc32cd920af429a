//! Expression → normal form: the [`Normalizer`] walks an expression tree and builds its [`Rf`],
//! handling powers and roots, functions, and `exp` of sums; numeric values of functions at
//! float arguments.

use rustc_hash::FxHashMap;

use crate::expr::{Expr, Func, Node};
use crate::number::Number;
use crate::poly::{plain_atom, root_atom, Poly};

use super::{cached_rf, monomial_to_expr, poly_to_expr, Rf};

/// Converts expressions to normal form, remembering the nodes it has seen (expressions are
/// DAGs: a shared sub-expression is converted once).
#[derive(Default)]
pub(crate) struct Normalizer {
    memo: FxHashMap<Expr, Rf>,
}

impl Normalizer {
    pub(crate) fn rf(&mut self, e: Expr) -> Rf {
        if let Some(r) = self.memo.get(&e) {
            return r.clone();
        }
        if let Some(r) = cached_rf(e) {
            return Rf::clone(&r);
        }
        let r = self.convert(e);
        self.memo.insert(e, r.clone());
        r
    }

    fn convert(&mut self, e: Expr) -> Rf {
        match e.node() {
            Node::Number(n) => Rf::constant(n.clone()),
            Node::Symbol(_) | Node::Constant(_) => Rf::atom(plain_atom(e)),
            Node::Add(terms) => {
                // Adding terms one by one into a sorted accumulator is quadratic; gather the
                // polynomial parts and sort-merge them once, and add the fractions after.
                let mut polynomial_terms = Vec::new();
                let mut fractions = Rf::zero();
                for t in terms.iter() {
                    let r = self.rf(*t);
                    if r.den.is_one() {
                        polynomial_terms.extend(r.num.terms);
                    } else {
                        fractions = fractions.add(&r);
                    }
                }
                Rf::from_poly(Poly::from_terms(polynomial_terms)).add(&fractions)
            }
            Node::Mul(factors) => {
                let mut acc = Rf::one();
                for f in factors.iter() {
                    acc = acc.mul(&self.rf(*f));
                    if acc.is_zero() {
                        break;
                    }
                }
                acc
            }
            Node::Pow([base, exp]) => self.power(*base, *exp),
            Node::Func(f, args) => self.function(*f, args),
        }
    }

    /// An application the algebra does not rewrite, as an atom of its own. The constructors
    /// fold literal arguments (`ln 1 = 0`, `tan 0 = 0`), and a number must never become an
    /// atom: its printed tree would be the number while the polynomial kept a variable.
    fn opaque(&mut self, e: Expr) -> Rf {
        match e.node() {
            Node::Number(n) => Rf::constant(n.clone()),
            _ => Rf::atom(plain_atom(e)),
        }
    }

    fn power(&mut self, base: Expr, exp: Expr) -> Rf {
        let b = self.rf(base);
        let x = self.rf(exp);
        if let Some(k) = x.as_constant() {
            if let Some(k) = k.to_i64() {
                return b
                    .powi(k)
                    .unwrap_or_else(|| self.opaque(Expr::pow(b.to_expr(), Expr::int(k))));
            }
            if let Some((p, q)) = k.to_small_ratio() {
                if let Ok(q) = u32::try_from(q) {
                    if let Some(r) = self.rational_power(&b, p, q) {
                        return r;
                    }
                }
            }
            if k.is_float() {
                if let Some(c) = b.as_constant() {
                    let v = c.to_f64().powf(k.to_f64());
                    if v.is_finite() {
                        return Rf::constant(Number::Float(v));
                    }
                }
            }
        }
        if let Some(c) = b.as_constant() {
            if c.is_zero() || c.is_one() {
                return Rf::constant(c);
            }
        }
        // A symbolic exponent: keep `b^x` as an atom of normalised parts.
        let atom = Expr::pow(b.to_expr(), x.to_expr());
        match atom.node() {
            Node::Pow(..) => self.opaque(atom),
            _ => self.rf(atom),
        }
    }

    /// `b^(p/q)` for `q ≥ 2`, through the root atom `(N D^(q−1))^(1/q)`.
    fn rational_power(&mut self, b: &Rf, p: i64, q: u32) -> Option<Rf> {
        if let Some(c) = b.as_constant() {
            if c.is_float() {
                let v = c.to_f64().powf(p as f64 / q as f64);
                return v.is_finite().then(|| Rf::constant(Number::Float(v)));
            }
        }
        // (N/D)^(1/q) = (N D^(q−1))^(1/q) / D holds for odd q, and for even q only where
        // D > 0, which the algebra cannot know: an even root of a fraction stays an atom.
        if q % 2 == 0 && !b.den.is_one() {
            let atom = Expr::pow(b.to_expr(), Expr::number(Number::rational(1, q as i64)?));
            return Rf::atom(plain_atom(atom)).powi(p);
        }
        let radicand = b.num.mul(&b.den.pow(q - 1));
        let root = self.root_of_poly(&radicand, q)?;
        let root = root.div(&Rf::from_poly(b.den.clone()))?;
        root.powi(p)
    }

    /// `P^(1/q)` for a polynomial `P`: the rational content's exact part comes out, the rest
    /// becomes root atoms of a number and of a primitive polynomial.
    fn root_of_poly(&mut self, p: &Poly, q: u32) -> Option<Rf> {
        if p.is_zero() {
            return Some(Rf::zero());
        }
        // Only a positive content may leave the root: `√(3 − c²)` is not `√−1 · √(c² − 3)`
        // over the reals.
        let content = p.content().abs();
        let primitive = p.scale(&content.recip()?);
        let mut result = self.root_of_number(&content, q)?;
        if !primitive.is_one() {
            let expr = Expr::pow(
                poly_to_expr(&primitive),
                Expr::number(Number::rational(1, q as i64)?),
            );
            let id = root_atom(expr, primitive, q);
            result = result.mul(&Rf::atom(id));
        }
        Some(result)
    }

    pub(super) fn root_of_number(&mut self, c: &Number, q: u32) -> Option<Rf> {
        if let Some(r) = c.exact_root(q) {
            return Some(Rf::constant(r));
        }
        // Split c = s^q · r with r free of q-th powers: integers by trial division.
        let (n, d) = c.to_small_ratio()?;
        // c = n/d; write as (n d^(q−1)) / d^q so only an integer is under the root.
        let mut radicand = (n as i128).checked_mul((d as i128).checked_pow(q - 1)?)?;
        let mut outside: i128 = 1;
        let negative = radicand < 0;
        radicand = radicand.abs();
        let mut f: i128 = 2;
        while f * f <= radicand && f < 10_000 {
            let fq = f.checked_pow(q)?;
            while radicand % fq == 0 {
                radicand /= fq;
                outside *= f;
            }
            f += 1;
        }
        if negative {
            radicand = -radicand;
        }
        let scale = Number::rational(i64::try_from(outside).ok()?, d)?;
        if radicand == 1 {
            return Some(Rf::constant(scale));
        }
        let r = Number::int(i64::try_from(radicand).ok()?);
        let expr = Expr::pow(
            Expr::number(r.clone()),
            Expr::number(Number::rational(1, q as i64)?),
        );
        let id = root_atom(expr, Poly::constant(r), q);
        Some(Rf::atom(id).scale(&scale))
    }

    fn function(&mut self, f: Func, args: &[Expr]) -> Rf {
        let normal_args: Vec<Rf> = args.iter().map(|a| self.rf(*a)).collect();
        match (f, normal_args.as_slice()) {
            (Func::Sin, [a]) => self.trig(a).1,
            (Func::Cos, [a]) => self.trig(a).0,
            (Func::Tan, [a]) => {
                let (c, s) = self.trig(a);
                s.div(&c)
                    .unwrap_or_else(|| self.opaque(Expr::func(Func::Tan, vec![a.to_expr()])))
            }
            (Func::Exp, [a]) => self.exponential(a),
            (Func::Ln, [a]) => {
                // ln(exp(u)) = u for real u.
                let e = a.to_expr();
                if let Node::Func(Func::Exp, inner) = e.node() {
                    return self.rf(inner[0]);
                }
                if let Some(c) = a.as_constant() {
                    if c.is_float() && c.signum() > 0 {
                        return Rf::constant(Number::Float(c.to_f64().ln()));
                    }
                }
                self.opaque(Expr::func(Func::Ln, vec![e]))
            }
            (Func::Abs | Func::Sign, [a]) => {
                if let Some(c) = a.as_constant() {
                    return Rf::constant(if f == Func::Abs {
                        c.abs()
                    } else {
                        Number::int(c.signum() as i64)
                    });
                }
                // |−u| = |u|, sign(−u) = −sign(u): choose the sign of the argument so that its
                // leading term is positive.
                let flip = self.negative_lead(a);
                let arg = if flip { a.neg() } else { a.clone() };
                let r = self.opaque(Expr::func(f, vec![arg.to_expr()]));
                if flip && f == Func::Sign {
                    r.neg()
                } else {
                    r
                }
            }
            _ => {
                let constants: Option<Vec<f64>> = normal_args
                    .iter()
                    .map(|a| a.as_constant().filter(|c| c.is_float()).map(|c| c.to_f64()))
                    .collect();
                if let Some(v) = constants {
                    if let Some(x) = eval_float(f, &v) {
                        return Rf::constant(Number::Float(x));
                    }
                }
                let e = Expr::func(f, normal_args.iter().map(|a| a.to_expr()).collect());
                match e.node() {
                    Node::Func(..) => self.opaque(e),
                    _ => self.rf(e),
                }
            }
        }
    }

    fn negative_lead(&self, a: &Rf) -> bool {
        a.num
            .terms
            .iter()
            .max_by(|x, y| monomial_to_expr(&x.0).cmp_structure(monomial_to_expr(&y.0)))
            .is_some_and(|(_, c)| c.is_negative())
    }

    /// `exp` of a normalised argument: `exp(Σ c_k m_k) = Π exp(m_k)^c_k` for integer `c_k`.
    fn exponential(&mut self, a: &Rf) -> Rf {
        if let Some(c) = a.as_constant() {
            if c.is_float() {
                return Rf::constant(Number::Float(c.to_f64().exp()));
            }
        }
        if !a.den.is_one() {
            return self.opaque(Expr::func(Func::Exp, vec![a.to_expr()]));
        }
        let mut acc = Rf::one();
        for (m, c) in &a.num.terms {
            let unit = monomial_to_expr(m);
            let r = match c.to_i64() {
                Some(k) if !m.is_empty() => {
                    let atom = Rf::atom(plain_atom(Expr::func(Func::Exp, vec![unit])));
                    atom.powi(k).unwrap_or_else(Rf::one)
                }
                _ => {
                    let e = Expr::number(c.clone()) * unit;
                    Rf::atom(plain_atom(Expr::func(Func::Exp, vec![e])))
                }
            };
            acc = acc.mul(&r);
        }
        acc
    }
}

/// Numeric values of the functions at float arguments.
pub(crate) fn eval_float(f: Func, args: &[f64]) -> Option<f64> {
    let v = match (f, args) {
        (Func::Sin, [x]) => x.sin(),
        (Func::Cos, [x]) => x.cos(),
        (Func::Tan, [x]) => x.tan(),
        (Func::Asin, [x]) => x.asin(),
        (Func::Acos, [x]) => x.acos(),
        (Func::Atan, [x]) => x.atan(),
        (Func::Atan2, [y, x]) => y.atan2(*x),
        (Func::Exp, [x]) => x.exp(),
        (Func::Ln, [x]) => x.ln(),
        (Func::Abs, [x]) => x.abs(),
        (Func::Sign, [x]) => {
            if *x > 0.0 {
                1.0
            } else if *x < 0.0 {
                -1.0
            } else {
                0.0
            }
        }
        _ => return None,
    };
    v.is_finite().then_some(v)
}
