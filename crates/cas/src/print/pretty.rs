//! The printers for people: Unicode for terminals and LaTeX in the seed's notation. Both walk
//! the (already compacted) tree the same way and differ only in how each construct is drawn,
//! so they share this file and a [`Style`] switch.
//!
//! Sums are printed in the course's order with a leading minus where the first term is
//! negative; products put their factors in the course's order, with factors of negative exact
//! exponent (and the coefficient's denominator) drawn as a fraction; `sin² θ` is drawn as the
//! course writes it.

use std::cell::RefCell;

use rustc_hash::FxHashMap;

use crate::expr::{split_coefficient, Expr, Node};
use crate::number::Number;
use crate::Func;

use super::names;
use super::order::{cmp_factors, sort_terms};

/// The drawing style.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Style {
    Unicode,
    Latex,
}

/// How tightly a printed form binds.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
enum Prec {
    Sum,
    /// A product, a fraction written with `/`, or a leading minus.
    Product,
    Power,
    Atom,
}

pub(super) fn print(e: Expr, style: Style) -> String {
    Pretty {
        style,
        memo: RefCell::default(),
    }
    .expr(e)
    .0
}

struct Pretty {
    style: Style,
    /// Each shared sub-expression is drawn once: drawing a node's parts more than once (an
    /// exponent, a lone numerator or denominator) costs 2^depth on deep nestings otherwise.
    memo: RefCell<FxHashMap<Expr, (String, Prec)>>,
}

impl Pretty {
    fn latex(&self) -> bool {
        self.style == Style::Latex
    }

    fn minus(&self) -> &'static str {
        if self.latex() {
            "-"
        } else {
            "−"
        }
    }

    fn paren(&self, s: &str) -> String {
        if self.latex() {
            format!(r"\left( {s} \right)")
        } else {
            format!("({s})")
        }
    }

    fn wrap(&self, (s, p): (String, Prec), need: Prec) -> String {
        if p < need {
            self.paren(&s)
        } else {
            s
        }
    }

    fn expr(&self, e: Expr) -> (String, Prec) {
        if let Some(done) = self.memo.borrow().get(&e) {
            return done.clone();
        }
        let drawn = self.draw(e);
        self.memo.borrow_mut().insert(e, drawn.clone());
        drawn
    }

    fn draw(&self, e: Expr) -> (String, Prec) {
        match e.node() {
            Node::Number(n) => self.lone_number(n),
            Node::Symbol(s) => {
                let text = if self.latex() {
                    names::latex(*s)
                } else {
                    names::unicode(*s)
                };
                (text, Prec::Atom)
            }
            Node::Constant(_) => (
                (if self.latex() { r"\pi" } else { "π" }).to_owned(),
                Prec::Atom,
            ),
            Node::Add(terms) => (self.sum(terms), Prec::Sum),
            Node::Mul(_) => {
                let (c, rest) = split_coefficient(e);
                self.product(&c, &factors_of(rest))
            }
            Node::Pow([b, x]) => match x.as_number() {
                Some(n) if n.is_negative() && !n.is_float() => self.product(&Number::ONE, &[e]),
                _ => self.power(*b, *x),
            },
            Node::Func(f, args) => self.func(*f, args, None),
        }
    }

    /// A number standing alone (a parameter's value, say) reads as the decimal it was
    /// probably written as whenever it is one (`0.5`, `0.4`); as a coefficient, `1/2` and `2/5`
    /// stay fractions (`½ m v²`), see [`Pretty::number`].
    fn lone_number(&self, n: &Number) -> (String, Prec) {
        match n.abs().to_terminating_decimal() {
            Some((digits, exponent)) if digits.to_string().len() <= 12 => {
                let (s, p) = self.decimal(&digits.to_string(), exponent);
                if n.is_negative() {
                    (format!("{}{s}", self.minus()), Prec::Product)
                } else {
                    (s, p)
                }
            }
            _ => self.number(n),
        }
    }

    fn number(&self, n: &Number) -> (String, Prec) {
        if n.is_negative() {
            let (s, _) = self.number(&n.neg());
            return (format!("{}{s}", self.minus()), Prec::Product);
        }
        if let Some((digits, exponent)) = n.to_decimal() {
            return self.decimal(&digits.to_string(), exponent);
        }
        match n {
            Number::Float(_) => (n.to_string(), Prec::Atom),
            _ if n.is_integer() => (n.to_string(), Prec::Atom),
            _ if self.latex() => (
                format!(r"\frac{{{}}}{{{}}}", n.numer(), n.denom()),
                Prec::Atom,
            ),
            _ => (format!("{}/{}", n.numer(), n.denom()), Prec::Product),
        }
    }

    /// `digits × 10^exponent` (`exponent < 0`) as people write it: `9.81`, `0.001`, and in
    /// scientific notation once more than a few zeros would follow the point (`1.5e-300`,
    /// which the parser reads back exactly).
    fn decimal(&self, digits: &str, exponent: i64) -> (String, Prec) {
        let len = i64::try_from(digits.len()).unwrap_or(i64::MAX);
        let leading_zeros = -exponent - len;
        if leading_zeros < 0 {
            let point = digits.len() - exponent.unsigned_abs() as usize;
            return (
                format!("{}.{}", &digits[..point], &digits[point..]),
                Prec::Atom,
            );
        }
        if leading_zeros <= 4 {
            let zeros = "0".repeat(leading_zeros as usize);
            return (format!("0.{zeros}{digits}"), Prec::Atom);
        }
        let mantissa = match digits.len() {
            1 => digits.to_owned(),
            _ => format!("{}.{}", &digits[..1], &digits[1..]),
        };
        let power = exponent + len - 1;
        if self.latex() {
            (format!(r"{mantissa} \cdot 10^{{{power}}}"), Prec::Product)
        } else {
            (format!("{mantissa}e{power}"), Prec::Atom)
        }
    }

    fn sum(&self, terms: &[Expr]) -> String {
        let mut terms = terms.to_vec();
        sort_terms(&mut terms);
        let mut out = String::new();
        for (i, t) in terms.iter().enumerate() {
            let (c, rest) = split_coefficient(*t);
            let negative = c.is_negative();
            let body = if negative {
                if rest.is_literal_one() {
                    self.number(&c.neg()).0
                } else {
                    self.wrap(self.product(&c.neg(), &factors_of(rest)), Prec::Product)
                }
            } else {
                self.expr(*t).0
            };
            let sign = match (i, negative) {
                (0, true) => self.minus().to_owned(),
                (0, false) => String::new(),
                (_, true) => format!(" {} ", self.minus()),
                (_, false) => " + ".to_owned(),
            };
            out.push_str(&sign);
            out.push_str(&body);
        }
        out
    }

    fn product(&self, coefficient: &Number, factors: &[Expr]) -> (String, Prec) {
        if coefficient.is_negative() {
            let s = self.wrap(self.product(&coefficient.neg(), factors), Prec::Product);
            return (format!("{}{s}", self.minus()), Prec::Product);
        }
        let mut factors = factors.to_vec();
        factors.sort_by(|a, b| cmp_factors(*a, *b));
        // A float or a decimal (`0.49 m`) is written whole in front, not as a fraction.
        let (p, q) = match coefficient {
            Number::Float(_) => (coefficient.clone(), Number::ONE),
            _ if coefficient.to_decimal().is_some() => (coefficient.clone(), Number::ONE),
            _ => (coefficient.numer(), coefficient.denom()),
        };
        let mut num: Vec<String> = Vec::new();
        let mut den: Vec<String> = Vec::new();
        for f in &factors {
            match f.node() {
                Node::Pow([b, x]) if in_denominator(*f) => {
                    let positive = x.as_number().map(Number::neg).unwrap_or(Number::ONE);
                    let part = self.power_number(*b, &positive);
                    den.push(self.wrap(part, Prec::Power));
                }
                _ => num.push(self.wrap(self.expr(*f), Prec::Power)),
            }
        }
        if self.latex() {
            return self.latex_product(&p, &q, num, den, &factors);
        }
        let only = num.len() == 1 && den.is_empty() && p.is_one() && !p.is_float() && q.is_one();
        if only {
            // A single factor keeps its own precedence.
            return self.expr(factors[0]);
        }
        if !p.is_one() || p.is_float() || num.is_empty() {
            num.insert(0, self.number(&p).0);
        }
        if !q.is_one() {
            den.insert(0, q.to_string());
        }
        let num_s = num.join(" ");
        match den.len() {
            0 => (num_s, Prec::Product),
            // A single denominator is already parenthesised if it needs it.
            1 => (format!("{num_s}/{}", den[0]), Prec::Product),
            _ => (format!("{num_s}/({})", den.join(" ")), Prec::Product),
        }
    }

    fn latex_product(
        &self,
        p: &Number,
        q: &Number,
        mut num: Vec<String>,
        mut den: Vec<String>,
        factors: &[Expr],
    ) -> (String, Prec) {
        if num.len() == 1 && den.is_empty() && p.is_one() && !p.is_float() && q.is_one() {
            return self.expr(factors[0]);
        }
        if den.is_empty() {
            // The seed writes `\frac{1}{2} m_A \dot{x}^2`: the coefficient as a fraction in front.
            let c = if q.is_one() {
                p.clone()
            } else {
                p.div(q).unwrap_or_else(|| p.clone())
            };
            if !c.is_one() || c.is_float() || num.is_empty() {
                num.insert(0, self.number(&c).0);
            }
            return (num.join(" "), Prec::Product);
        }
        // The fraction bar groups: a lone sum above or below it needs no parentheses.
        let above: Vec<Expr> = factors
            .iter()
            .copied()
            .filter(|f| !in_denominator(*f))
            .collect();
        if let ([only], true) = (above.as_slice(), p.is_one() && !p.is_float()) {
            num = vec![self.expr(*only).0];
        }
        let below: Vec<Expr> = factors
            .iter()
            .copied()
            .filter(|f| in_denominator(*f))
            .collect();
        if let ([only], true) = (below.as_slice(), q.is_one()) {
            if let Node::Pow([b, x]) = only.node() {
                if x.as_number().is_some_and(Number::is_minus_one) {
                    den = vec![self.expr(*b).0];
                }
            }
        }
        if !p.is_one() || p.is_float() || num.is_empty() {
            num.insert(0, self.number(p).0);
        }
        if !q.is_one() {
            den.insert(0, q.to_string());
        }
        (
            format!(r"\frac{{{}}}{{{}}}", num.join(" "), den.join(" ")),
            Prec::Atom,
        )
    }

    fn power(&self, base: Expr, exp: Expr) -> (String, Prec) {
        if let Some(n) = exp.as_number() {
            return self.power_number(base, n);
        }
        let b = self.base(base);
        // The exponent is printed once: printing it twice per level made a tower `x^x^…^x`
        // cost 2^depth (issue 23).
        let (x, precedence) = self.expr(exp);
        if self.latex() {
            (format!("{b}^{{{x}}}"), Prec::Power)
        } else {
            let x = self.wrap((x, precedence), Prec::Atom);
            (format!("{b}^{x}"), Prec::Power)
        }
    }

    fn power_number(&self, base: Expr, exp: &Number) -> (String, Prec) {
        if exp.is_one() && !exp.is_float() {
            return self.expr(base);
        }
        if *exp == (Number::Small { num: 1, den: 2 }) {
            let (s, p) = self.expr(base);
            return if self.latex() {
                (format!(r"\sqrt{{{s}}}"), Prec::Atom)
            } else if p == Prec::Atom {
                (format!("√{s}"), Prec::Atom)
            } else {
                (format!("√({s})"), Prec::Atom)
            };
        }
        // `sin² θ`, as the course writes powers of trigonometric functions.
        if let (Node::Func(f, args), Some(k)) = (base.node(), exp.to_i64()) {
            if k > 0 && matches!(f, Func::Sin | Func::Cos | Func::Tan) {
                return self.func(*f, args, Some(k));
            }
        }
        let b = self.base(base);
        let s = match (self.latex(), exp.to_i64()) {
            (true, Some(k)) if (0..10).contains(&k) => format!("{b}^{k}"),
            (true, _) => format!("{b}^{{{}}}", self.number(exp).0),
            (false, Some(k)) => format!("{b}{}", names::superscript(&k.to_string())),
            (false, None) => format!("{b}^{}", self.wrap(self.number(exp), Prec::Atom)),
        };
        (s, Prec::Power)
    }

    /// A power's base: atoms as they are, functions with their argument in parentheses,
    /// everything else in parentheses.
    fn base(&self, base: Expr) -> String {
        match base.node() {
            Node::Func(f, args) if !(*f == Func::Exp && is_exact_one(args[0])) => {
                self.paren(&self.func_call(*f, args))
            }
            _ => self.wrap(self.expr(base), Prec::Atom),
        }
    }

    fn func_call(&self, f: Func, args: &[Expr]) -> String {
        let args: Vec<String> = args.iter().map(|a| self.expr(*a).0).collect();
        let joined = args.join(", ");
        let name = self.func_name(f);
        if self.latex() {
            format!(r"{name}\left({joined}\right)")
        } else {
            format!("{name}({joined})")
        }
    }

    fn func_name(&self, f: Func) -> &'static str {
        if !self.latex() {
            return match f {
                Func::Ln => "ln",
                Func::Abs => "abs",
                _ => f.name(),
            };
        }
        match f {
            Func::Sin => r"\sin",
            Func::Cos => r"\cos",
            Func::Tan => r"\tan",
            Func::Asin => r"\arcsin",
            Func::Acos => r"\arccos",
            Func::Atan => r"\arctan",
            Func::Atan2 => r"\operatorname{atan2}",
            Func::Exp => r"\exp",
            Func::Ln => r"\ln",
            Func::Abs => r"\operatorname{abs}",
            Func::Sign => r"\operatorname{sign}",
        }
    }

    /// A function application; `power` draws `sin² θ`.
    fn func(&self, f: Func, args: &[Expr], power: Option<i64>) -> (String, Prec) {
        if f == Func::Exp && is_exact_one(args[0]) && power.is_none() {
            return ("e".to_owned(), Prec::Atom);
        }
        if f == Func::Abs && power.is_none() {
            let inner = self.expr(args[0]).0;
            return if self.latex() {
                (format!(r"\left|{inner}\right|"), Prec::Atom)
            } else {
                (format!("|{inner}|"), Prec::Atom)
            };
        }
        let name = self.func_name(f);
        let name = match power {
            Some(k) if self.latex() => format!("{name}^{{{k}}}"),
            Some(k) => format!("{name}{}", names::superscript(&k.to_string())),
            None => name.to_owned(),
        };
        // A lone symbol or number is written without parentheses, as in `cos θ`; the function
        // then binds like a product factor, so it is parenthesised where that matters.
        let simple = args.len() == 1
            && matches!(f, Func::Sin | Func::Cos | Func::Tan | Func::Ln)
            && matches!(args[0].node(), Node::Symbol(_) | Node::Constant(_))
            || (args.len() == 1
                && matches!(f, Func::Sin | Func::Cos | Func::Tan | Func::Ln)
                && args[0]
                    .as_number()
                    .is_some_and(|n| !n.is_negative() && n.is_integer()));
        if simple {
            let arg = self.expr(args[0]).0;
            return (format!("{name} {arg}"), Prec::Atom);
        }
        let args: Vec<String> = args.iter().map(|a| self.expr(*a).0).collect();
        let joined = args.join(", ");
        if self.latex() {
            (format!(r"{name}\left({joined}\right)"), Prec::Atom)
        } else {
            (format!("{name}({joined})"), Prec::Atom)
        }
    }
}

/// Whether a factor has an exact negative exponent, so it is drawn below a fraction bar.
fn in_denominator(f: Expr) -> bool {
    matches!(f.node(), Node::Pow([_, x]) if x.as_number().is_some_and(|n| n.is_negative() && !n.is_float()))
}

fn factors_of(rest: Expr) -> Vec<Expr> {
    match rest.node() {
        Node::Mul(f) => f.to_vec(),
        _ => vec![rest],
    }
}

/// Whether `e` is the exact number 1 (not the float `1.0`, which prints differently).
fn is_exact_one(e: Expr) -> bool {
    e.as_number().is_some_and(|n| n.is_one() && !n.is_float())
}
