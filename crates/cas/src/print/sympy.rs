//! The SymPy-syntax printer. In exact mode it prints every node as it is, in the tree's own
//! order, with just the parentheses that make [`parse`](crate::parse::parse) rebuild the identical node
//! through the canonicalising constructors; in ordered mode (for the compact form) it sorts
//! terms and factors as the course does.
//!
//! The parser mirrors Python's precedences: `-x**2` is `-(x**2)`, `**` is right-associative,
//! and `a - b` builds `a + (-1)*b`, which is exactly how the constructors store a difference.

use crate::expr::{split_coefficient, Expr, Node, SymbolKind};
use crate::number::Number;
use crate::Func;

use super::order::{cmp_factors, sort_terms};

/// How tightly a printed form binds; a child binding less tightly than its slot needs is
/// parenthesised.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
enum Prec {
    Sum,
    /// A product, a quotient or a leading minus.
    Product,
    Power,
    Atom,
}

pub(super) fn print(e: Expr, ordered: bool) -> String {
    Printer { ordered }.expr(e).0
}

struct Printer {
    ordered: bool,
}

impl Printer {
    fn expr(&self, e: Expr) -> (String, Prec) {
        match e.node() {
            Node::Number(n) => number(n),
            Node::Symbol(s) => {
                let name = match s.kind() {
                    SymbolKind::TimeFunction { order } if order > 0 => {
                        format!("{}_{}", s.name(), "d".repeat(usize::from(order)))
                    }
                    _ => s.name().to_owned(),
                };
                (name, Prec::Atom)
            }
            Node::Constant(_) => ("pi".to_owned(), Prec::Atom),
            Node::Add(terms) => (self.sum(terms), Prec::Sum),
            Node::Mul(_) => {
                let (c, rest) = split_coefficient(e);
                let factors = match rest.node() {
                    Node::Mul(f) => f.to_vec(),
                    _ => vec![rest],
                };
                self.product(&c, &factors)
            }
            Node::Pow([b, x]) => match denominator(e) {
                Some(_) => self.product(&Number::ONE, &[e]),
                None => self.power(*b, *x),
            },
            Node::Func(Func::Exp, args) if is_exact_one(args[0]) => ("E".to_owned(), Prec::Atom),
            Node::Func(f, args) => {
                let args: Vec<String> = args.iter().map(|a| self.expr(*a).0).collect();
                (format!("{}({})", f.name(), args.join(", ")), Prec::Atom)
            }
        }
    }

    fn sum(&self, terms: &[Expr]) -> String {
        let mut terms = terms.to_vec();
        if self.ordered {
            sort_terms(&mut terms);
        }
        let mut out = String::new();
        for (i, t) in terms.iter().enumerate() {
            let (c, rest) = split_coefficient(*t);
            let (negative, body) = if c.is_negative() {
                let factors = factors_of(rest);
                let body = if rest.is_literal_one() {
                    number(&c.neg()).0
                } else {
                    self.wrap(self.product(&c.neg(), &factors), Prec::Product)
                };
                (true, body)
            } else {
                (false, self.expr(*t).0)
            };
            match (i, negative) {
                (0, true) => out.push('-'),
                (0, false) => {}
                (_, true) => out.push_str(" - "),
                (_, false) => out.push_str(" + "),
            }
            out.push_str(&body);
        }
        out
    }

    /// `coefficient * factors`, with factors that have negative exact exponents written as a
    /// denominator (`x/(2*y)`), which reads back to the same powers.
    fn product(&self, coefficient: &Number, factors: &[Expr]) -> (String, Prec) {
        if coefficient.is_negative() {
            let s = self.wrap(self.product(&coefficient.neg(), factors), Prec::Product);
            return (format!("-{s}"), Prec::Product);
        }
        let rest = || {
            factors
                .iter()
                .map(|f| f.to_string_sympy())
                .collect::<Vec<_>>()
                .join("*")
        };
        // A float zero coefficient survives only as a sum's cancelled term (`1.5 x − 1.5 x`); no
        // product reads back to it, so write the cancellation itself.
        if coefficient.is_zero() && coefficient.is_float() {
            let r = rest();
            return (format!("(1.0*{r} - 1.0*{r})"), Prec::Atom);
        }
        let mut factors = factors.to_vec();
        if self.ordered {
            factors.sort_by(|a, b| cmp_factors(*a, *b));
        }
        let mut num: Vec<String> = Vec::new();
        let mut den: Vec<String> = Vec::new();
        // `1/(7*0)` would fold `7*0` before inverting; a bare number in the denominator (only
        // `0^-1` stays unevaluated) is divided by on its own instead: `1/7/0`.
        let mut chain = false;
        let (p, q) = match coefficient {
            Number::Float(_) => (coefficient.clone(), Number::ONE),
            _ => (coefficient.numer(), coefficient.denom()),
        };
        if !p.is_one() || p.is_float() {
            num.push(number(&p).0);
        }
        if !q.is_one() {
            den.push(number(&q).0);
        }
        for f in &factors {
            match denominator(*f) {
                Some((b, positive)) => {
                    chain |= b.as_number().is_some() && positive.is_one();
                    den.push(self.wrap(self.power_number(b, &positive), Prec::Power));
                }
                None => num.push(self.wrap(self.expr(*f), Prec::Power)),
            }
        }
        let num_str = if num.is_empty() {
            "1".to_owned()
        } else {
            num.join("*")
        };
        match den.len() {
            0 if num.len() == 1 && factors.len() == 1 && p.is_one() && !p.is_float() => {
                // A single factor keeps its own precedence (`x**2`, `sin(x)`).
                self.expr(factors[0])
            }
            0 => (num_str, Prec::Product),
            1 => (format!("{num_str}/{}", den[0]), Prec::Product),
            _ if chain => (format!("{num_str}/{}", den.join("/")), Prec::Product),
            _ => (format!("{num_str}/({})", den.join("*")), Prec::Product),
        }
    }

    fn power(&self, base: Expr, exp: Expr) -> (String, Prec) {
        if let Some(n) = exp.as_number() {
            return self.power_number(base, n);
        }
        let b = self.wrap(self.expr(base), Prec::Atom);
        // `**` is right-associative, so a power in the exponent needs no parentheses.
        let x = self.wrap(self.expr(exp), Prec::Power);
        (format!("{b}**{x}"), Prec::Power)
    }

    fn power_number(&self, base: Expr, exp: &Number) -> (String, Prec) {
        if exp.is_one() && !exp.is_float() {
            return self.expr(base);
        }
        if *exp == (Number::Small { num: 1, den: 2 }) {
            return (format!("sqrt({})", self.expr(base).0), Prec::Atom);
        }
        let b = self.wrap(self.expr(base), Prec::Atom);
        let x = self.wrap(number(exp), Prec::Atom);
        (format!("{b}**{x}"), Prec::Power)
    }

    fn wrap(&self, (s, p): (String, Prec), need: Prec) -> String {
        if p < need {
            format!("({s})")
        } else {
            s
        }
    }
}

/// A factor `b^(−e)` with an exact negative exponent, which prints as a division by `b^e`: the
/// base and the positive exponent. A zero base stays a power (`0**(-1/2)`), because `1/sqrt(0)`
/// would read back as `1/0`.
fn denominator(f: Expr) -> Option<(Expr, Number)> {
    match f.node() {
        Node::Pow([b, x]) if !b.is_literal_zero() => match x.as_number() {
            Some(n) if n.is_negative() && !n.is_float() => Some((*b, n.neg())),
            _ => None,
        },
        _ => None,
    }
}

fn factors_of(rest: Expr) -> Vec<Expr> {
    match rest.node() {
        Node::Mul(f) => f.to_vec(),
        _ => vec![rest],
    }
}

fn number(n: &Number) -> (String, Prec) {
    // SymPy's names for the floats that have no digits; the parser reads them back.
    if let Number::Float(x) = n {
        if x.is_nan() {
            return ("nan".to_owned(), Prec::Atom);
        }
        if x.is_infinite() {
            return (
                if *x > 0.0 { "oo" } else { "-oo" }.to_owned(),
                if *x > 0.0 { Prec::Atom } else { Prec::Product },
            );
        }
    }
    let s = n.to_string();
    // A minus sign or a fraction bar binds like a product.
    let prec = if s.starts_with('-') || s.contains('/') {
        Prec::Product
    } else {
        Prec::Atom
    };
    (s, prec)
}

trait SympyString {
    fn to_string_sympy(self) -> String;
}

impl SympyString for Expr {
    fn to_string_sympy(self) -> String {
        let (s, p) = Printer { ordered: false }.expr(self);
        if p < Prec::Power {
            format!("({s})")
        } else {
            s
        }
    }
}

/// Whether `e` is the exact number 1 (not the float `1.0`, which prints differently).
fn is_exact_one(e: Expr) -> bool {
    e.as_number().is_some_and(|n| n.is_one() && !n.is_float())
}
