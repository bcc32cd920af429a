//! A solution as a document — sections of prose, aligned equations, tables, figures and
//! remarks — and its renderings: the terminal (Unicode, 80 columns), MyST Markdown (math in
//! `$$…$$`, ready for a Jupyter Book like the seed's) and a standalone LaTeX document.
//!
//! The mechanics fills a [`Document`]; the renderers know nothing about mechanics. Every piece
//! of mathematics is carried in both notations ([`Math`]), printed by the symbolic core, so the
//! three renderings say the same thing.

mod json;
mod latex;
mod markdown;
mod positive;
mod prose;
mod shared;
mod text;

pub use positive::positive_root;
pub use shared::Named;

use std::cell::RefCell;
use std::rc::Rc;

use cas::print::{to_latex, to_unicode};
use cas::Expr;

use text::top_level_terms;

/// A sum is written term by term ([`Notation::sum`]) only up to this many terms.
const TERMWISE_MAX: usize = 4;

/// How a report writes the system's expressions: the model's named constants folded back in
/// (`m g b sin θ`, not `m g d cos² α sin θ`) and a time-independent denominator spread over
/// the terms (`(I1 + I2 r²) φ̈1`, not one fraction over `R2²`); see
/// [`cas::print::spread_and_fold`]. The value is never changed. It also names the Lagrangian:
/// `ℒ` (`\mathcal{L}`) as the course writes it, so that a length `L` reads apart from it;
/// [`Notation::with_lagrangian`] changes that (docs/solve.md).
///
/// A notation also remembers the names it gave to long shared sub-expressions
/// ([`Notation::name_shared`]); its clones share them, so a name is defined once per document.
#[derive(Clone, Debug)]
pub struct Notation {
    names: Vec<(Expr, Expr)>,
    lagrangian: Math,
    /// The model's own names, which a new name must not take.
    taken: Vec<String>,
    /// The names given so far (symbol, definition), shared by the clones.
    shared: Rc<RefCell<Vec<(Expr, Expr)>>>,
    /// The parameters whose values are positive, taken positive in symbolic statements.
    positive: Vec<String>,
}

impl Default for Notation {
    fn default() -> Notation {
        Notation {
            names: Vec::new(),
            lagrangian: Math::label("ℒ", r"\mathcal{L}"),
            taken: Vec::new(),
            shared: Rc::default(),
            positive: Vec::new(),
        }
    }
}

impl Notation {
    /// The notation of a system: its named constants.
    #[must_use]
    pub fn of(system: &mechanics::System) -> Notation {
        Notation {
            names: system
                .constants()
                .iter()
                .map(|(name, value)| (Expr::symbol(name), *value))
                .collect(),
            taken: system
                .parameters()
                .iter()
                .map(|(name, _)| name.clone())
                .chain(system.coordinates().iter().cloned())
                .chain(system.constants().iter().map(|(name, _)| name.clone()))
                .collect(),
            positive: positive_parameters(system),
            ..Notation::default()
        }
    }

    /// The same notation with another symbol for the Lagrangian (`"L"`, `"L"`; default `ℒ`,
    /// `\mathcal{L}`).
    #[must_use]
    pub fn with_lagrangian(mut self, unicode: &str, latex: &str) -> Notation {
        self.lagrangian = Math::label(unicode, latex);
        self
    }

    /// The symbol of the Lagrangian in both notations.
    #[must_use]
    pub fn lagrangian(&self) -> &Math {
        &self.lagrangian
    }

    /// The expression as people read it in this notation.
    #[must_use]
    pub fn shape(&self, e: Expr) -> Expr {
        let e = self.split_roots(e);
        if self.has_shared_name(e) {
            return cas::print::fold_names(e, &self.names);
        }
        cas::print::spread_and_fold(e, &self.names)
    }

    /// [`Math::expr`] of the shaped expression; a sum whose compact form puts a minus sign
    /// in front of a bracket of terms with mixed signs (`−½ (k x² − 2 m_B g ℓ cos θ)`) is
    /// written term by term instead (`−½ k x² + m_B g ℓ cos θ`, as the course writes it)
    /// when that is not longer.
    #[must_use]
    pub fn math(&self, e: Expr) -> Math {
        self.unbracketed(e, true)
    }

    /// [`Notation::math`] of a sum the course writes term by term, like the force function
    /// (`U = −½ k θ² − m g ℓ sin θ`): a minus sign in front of a bracket is given back to the
    /// terms whatever their signs, when that is not longer.
    #[must_use]
    pub fn sum(&self, e: Expr) -> Math {
        self.unbracketed(e, false)
    }

    fn unbracketed(&self, e: Expr, only_mixed: bool) -> Math {
        let whole = Math::expr(self.shape(e));
        if !whole.unicode.starts_with('−') || !whole.unicode.contains('(') {
            return whole;
        }
        let e = e.normal();
        if !matches!(e.node(), cas::Node::Add(_)) {
            return whole;
        }
        let shaped: Vec<Expr> = cas::print::terms_in_print_order(e)
            .into_iter()
            .map(|t| self.shape(t))
            .collect();
        let negative: Vec<bool> = shaped
            .iter()
            .map(|t| to_unicode(*t).starts_with('−'))
            .collect();
        let mixed = negative.iter().any(|n| *n) && !negative.iter().all(|n| *n);
        // A long sum keeps the grouping of its compact form (`(k1 + k2) x1²`).
        if !(2..=TERMWISE_MAX).contains(&shaped.len()) || (only_mixed && !mixed) {
            return whole;
        }
        let termwise = Math::terms(&shaped);
        if termwise.unicode.chars().count() <= whole.unicode.chars().count() {
            termwise
        } else {
            whole
        }
    }

    /// [`Math::vector`] of the shaped components.
    #[must_use]
    pub fn vector(&self, components: &[Expr; 3]) -> Math {
        Math::vector(&components.map(|c| self.shape(c)))
    }
}

/// The parameters whose values (from the earlier parameters) are positive numbers.
fn positive_parameters(system: &mechanics::System) -> Vec<String> {
    let mut values: Vec<(String, f64)> = Vec::new();
    for (name, value) in system.parameters() {
        let Some(value) = value else { continue };
        let lookup = |s: cas::Symbol| values.iter().find(|(n, _)| n == s.name()).map(|(_, v)| *v);
        if let Ok(x) = value.eval(&lookup) {
            values.push((name.clone(), x));
        }
    }
    values
        .into_iter()
        .filter(|(_, v)| *v > 0.0)
        .map(|(n, _)| n)
        .collect()
}

/// A piece of mathematics in the two notations people read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Math {
    /// For terminals: `θ̇`, `ℓ`, `cos(θ1 − θ2)`.
    pub unicode: String,
    /// For Markdown and LaTeX: `\dot{\theta}`, `\ell`.
    pub latex: String,
}

impl Math {
    /// An expression, in the compact form people read.
    #[must_use]
    pub fn expr(e: Expr) -> Math {
        Math {
            unicode: to_unicode(e),
            latex: to_latex(e),
        }
    }

    /// A symbol or label written by hand in both notations.
    #[must_use]
    pub fn label(unicode: impl Into<String>, latex: impl Into<String>) -> Math {
        Math {
            unicode: unicode.into(),
            latex: latex.into(),
        }
    }

    /// A sum written term by term, in the order given: `−½ k x² + m_B g ℓ cos θ`.
    #[must_use]
    pub fn terms(terms: &[Expr]) -> Math {
        let mut unicode = String::new();
        let mut latex = String::new();
        for t in terms {
            let negative = to_unicode(*t).starts_with('−');
            let magnitude = if negative { -*t } else { *t };
            push_sign(&mut unicode, &mut latex, negative);
            unicode.push_str(&to_unicode(magnitude));
            latex.push_str(&to_latex(magnitude));
        }
        if unicode.is_empty() {
            return Math::label("0", "0");
        }
        Math { unicode, latex }
    }

    /// A vector from its inertial components, as the seed writes it: `a x̂ + b ŷ + c ẑ`.
    #[must_use]
    pub fn vector(components: &[Expr; 3]) -> Math {
        const UNITS: [(&str, &str); 3] = [("x̂", r"\hat{x}"), ("ŷ", r"\hat{y}"), ("ẑ", r"\hat{z}")];
        let mut unicode = String::new();
        let mut latex = String::new();
        for (c, (u, l)) in components.iter().zip(UNITS) {
            if c.is_literal_zero() {
                continue;
            }
            let negative = to_unicode(*c).starts_with('−');
            let magnitude = if negative { -*c } else { *c };
            let (mut cu, mut cl) = (to_unicode(magnitude), to_latex(magnitude));
            if top_level_terms(&cu).len() > 1 {
                cu = format!("({cu})");
                cl = format!(r"\left({cl}\right)");
            }
            push_sign(&mut unicode, &mut latex, negative);
            if cu != "1" {
                unicode.push_str(&cu);
                unicode.push(' ');
                latex.push_str(&cl);
                latex.push(' ');
            }
            unicode.push_str(u);
            latex.push_str(l);
        }
        if unicode.is_empty() {
            return Math::label("0", r"\vec{0}");
        }
        Math { unicode, latex }
    }
}

/// Blocks of lines (matrices written one row a line) set side by side, `sep` between them on
/// their first line and as many spaces on the others; each block padded to its widest line.
#[must_use]
pub fn side_by_side(blocks: &[&str], sep: &str) -> String {
    let height = blocks.iter().map(|b| b.lines().count()).max().unwrap_or(0);
    let blank = " ".repeat(sep.chars().count());
    let mut rows = vec![String::new(); height];
    for (k, block) in blocks.iter().enumerate() {
        let width = block.lines().map(|l| l.chars().count()).max().unwrap_or(0);
        let lines: Vec<&str> = block.lines().collect();
        for (i, row) in rows.iter_mut().enumerate() {
            if k > 0 {
                row.push_str(if i == 0 { sep } else { &blank });
            }
            let line = lines.get(i).copied().unwrap_or("");
            row.push_str(line);
            if k + 1 < blocks.len() {
                row.push_str(&" ".repeat(width - line.chars().count()));
            }
        }
    }
    rows.iter()
        .map(|r| r.trim_end())
        .collect::<Vec<_>>()
        .join("\n")
}

/// Appends the sign of the next term of a sum written out by hand: a leading `−` for a
/// negative first term, ` + ` or ` − ` between terms.
pub(crate) fn push_sign(unicode: &mut String, latex: &mut String, negative: bool) {
    match (unicode.is_empty(), negative) {
        (true, true) => {
            unicode.push('−');
            latex.push('-');
        }
        (true, false) => {}
        (false, true) => {
            unicode.push_str(" − ");
            latex.push_str(" - ");
        }
        (false, false) => {
            unicode.push_str(" + ");
            latex.push_str(" + ");
        }
    }
}

/// One line of an aligned display: `lhs = rhs`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Equation {
    /// The left-hand side.
    pub lhs: Math,
    /// The right-hand side.
    pub rhs: Math,
}

impl Equation {
    /// `lhs = rhs`.
    #[must_use]
    pub fn new(lhs: Math, rhs: Math) -> Equation {
        Equation { lhs, rhs }
    }
}

/// A table cell: prose or mathematics.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Cell {
    /// Plain text.
    Text(String),
    /// Mathematics.
    Math(Math),
}

/// The pieces a section is made of.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Block {
    /// A paragraph of prose.
    Paragraph(String),
    /// Aligned equations, one per line.
    Equations(Vec<Equation>),
    /// A table with a header row.
    Table {
        /// Column titles.
        header: Vec<String>,
        /// Rows of cells.
        rows: Vec<Vec<Cell>>,
    },
    /// A figure written beside the document.
    Figure {
        /// The file name, relative to the document.
        path: String,
        /// What it shows.
        caption: String,
        /// Its width in print, in percent of the text's width.
        width: u8,
    },
    /// A remark worth noticing, like the seed's *Obs.*
    Remark(String),
    /// A bulleted list of short paragraphs (the model's notes).
    List(Vec<String>),
    /// A file written beside the document that a reader opens on its own (an animation).
    Link {
        /// The file name, relative to the document.
        path: String,
        /// What it is.
        text: String,
    },
}

/// A titled section.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Section {
    /// Its title.
    pub title: String,
    /// 2 for a section, 3 for a subsection.
    pub level: u8,
    /// What it says, in order.
    pub blocks: Vec<Block>,
}

impl Section {
    /// An empty section.
    #[must_use]
    pub fn new(title: impl Into<String>, level: u8) -> Section {
        Section {
            title: title.into(),
            level,
            blocks: Vec::new(),
        }
    }

    /// Adds a paragraph.
    pub fn paragraph(&mut self, text: impl Into<String>) -> &mut Section {
        self.blocks.push(Block::Paragraph(text.into()));
        self
    }

    /// Adds a display of equations (nothing when `lines` is empty).
    pub fn equations(&mut self, lines: Vec<Equation>) -> &mut Section {
        if !lines.is_empty() {
            self.blocks.push(Block::Equations(lines));
        }
        self
    }

    /// Adds a remark.
    pub fn remark(&mut self, text: impl Into<String>) -> &mut Section {
        self.blocks.push(Block::Remark(text.into()));
        self
    }
}

/// A whole solution.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Document {
    /// The title.
    pub title: String,
    /// The sections, in order.
    pub sections: Vec<Section>,
}

#[cfg(test)]
mod tests {
    use super::latex::{aligned_lines, breakable_latex, visible_width, LATEX_LINE};
    use super::text::{wrap_equation, COLUMNS};
    use super::*;

    fn sample() -> Document {
        let th = Expr::coordinate("theta");
        let l = Expr::symbol("l");
        let mut s = Section::new("Kinematics", 2);
        s.paragraph("Position of the bob, 100% on the rod_1 & #2.");
        s.equations(vec![Equation::new(
            Math::label("r_P", r"\vec{r}_P"),
            Math::vector(&[l * th.sin(), -(l * th.cos()), Expr::zero()]),
        )]);
        s.remark("θ = 0 is stable.");
        s.blocks.push(Block::Table {
            header: vec!["θ".into(), "stable".into()],
            rows: vec![vec![
                Cell::Math(Math::expr(Expr::zero())),
                Cell::Text("yes".into()),
            ]],
        });
        Document {
            title: "Pendulum".into(),
            sections: vec![s],
        }
    }

    #[test]
    fn vectors_read_like_the_seed() {
        let th = Expr::coordinate("theta");
        let l = Expr::symbol("l");
        let v = Math::vector(&[l * th.sin(), -(l * th.cos()), Expr::zero()]);
        assert_eq!(v.unicode, "ℓ sin θ x̂ − ℓ cos θ ŷ");
        assert_eq!(
            v.latex,
            r"\ell \sin \theta \hat{x} - \ell \cos \theta \hat{y}"
        );
        let w = Math::vector(&[Expr::zero(), Expr::one(), th + l]);
        assert_eq!(w.unicode, "ŷ + (θ + ℓ) ẑ");
        assert_eq!(
            Math::vector(&[Expr::zero(), Expr::zero(), Expr::zero()]).unicode,
            "0"
        );
    }

    #[test]
    fn the_three_renderings_carry_the_same_content() {
        let d = sample();
        let text = d.to_text();
        assert!(text.contains("Kinematics\n──────────"));
        assert!(text.contains("  r_P = ℓ sin θ x̂ − ℓ cos θ ŷ"));
        assert!(text.contains("Obs. θ = 0 is stable."));
        let md = d.to_markdown();
        assert!(md.contains("## Kinematics"));
        assert!(md.contains("$$\n\\begin{aligned}\n\\vec{r}_P &= "));
        assert!(md.contains("```{note}\n$\\theta = 0$ is stable.\n```"));
        assert!(md.contains("| $0$ | yes |"));
        let tex = d.to_latex();
        assert!(tex.starts_with("\\documentclass"));
        assert!(tex.ends_with("\\end{document}\n"));
        assert!(tex.contains("100\\% on the rod\\_1 \\& \\#2."));
        assert!(tex.contains("\\textit{Obs.} $\\theta = 0$ is stable."));
        assert_eq!(
            tex.matches("\\begin{align*}").count(),
            tex.matches("\\end{align*}").count()
        );
    }

    #[test]
    fn prose_math_is_math_in_markdown_and_latex() {
        let mut s = Section::new("Notes", 2);
        s.paragraph("The cart of mass m_A carries Q_θ = C and ω² < 2 a g (`mesh`).");
        s.blocks
            .push(Block::List(vec!["The bob m_B, at r_B.".into()]));
        s.remark("θ̇ stays small.");
        let d = Document {
            title: "t".into(),
            sections: vec![s],
        };
        let md = d.to_markdown();
        let tex = d.to_latex();
        for out in [&md, &tex] {
            assert!(
                out.contains("mass $m_A$ carries $Q_{\\theta} = C$ and $\\omega^2 < 2 a g$"),
                "{out}"
            );
            assert!(out.contains("The bob $m_B$, at $r_B$."), "{out}");
            assert!(out.contains("$\\dot{\\theta}$ stays small."), "{out}");
            assert!(!out.contains("m\\_A") && !out.contains('θ'), "{out}");
        }
        assert!(md.contains("(`mesh`)."), "{md}");
        assert!(tex.contains("(\\texttt{mesh})."), "{tex}");
        // The terminal keeps the Unicode.
        assert!(d.to_text().contains("mass m_A carries Q_θ = C"));
    }

    #[test]
    fn markdown_displays_break_to_a_book_column_narrower_than_the_page() {
        let rhs = (0..16)
            .map(|i| format!(r"m_{i} \ddot{{x}}_{i}"))
            .collect::<Vec<_>>()
            .join(" + ");
        let mut s = Section::new("Wide", 2);
        s.equations(vec![Equation::new(
            Math::label("f", "f"),
            Math::label("f", rhs),
        )]);
        let d = Document {
            title: "t".into(),
            sections: vec![s],
        };
        let rows = |out: &str, open: &str, close: &str| -> Vec<usize> {
            let start = out.find(open).map_or(0, |i| i + open.len());
            let end = out[start..].find(close).map_or(out.len(), |i| start + i);
            out[start..end]
                .split(" \\\\\n")
                .map(visible_width)
                .collect()
        };
        let md = rows(&d.to_markdown(), "\\begin{aligned}\n", "\n\\end{aligned}");
        let tex = rows(&d.to_latex(), "\\begin{align*}\n", "\n\\end{align*}");
        assert!(
            md.iter().all(|w| *w <= super::markdown::MARKDOWN_LINE),
            "{md:?}"
        );
        assert!(
            tex.iter().any(|w| *w > super::markdown::MARKDOWN_LINE),
            "{tex:?}"
        );
    }

    #[test]
    fn long_latex_breaks_at_top_level_signs_only() {
        let rhs = format!(
            "{} + \\left({} + c\\right) - {}",
            "x".repeat(60),
            "y".repeat(10),
            "z".repeat(50)
        );
        let body = aligned_lines(&[Equation::new(
            Math::label("f", "f"),
            Math::label("f", rhs.clone()),
        )]);
        assert_eq!(body.lines().count(), 2, "{body}");
        assert!(body.contains("\\left(yyyyyyyyyy + c\\right)"));
        assert!(
            body.lines()
                .nth(1)
                .is_some_and(|l| l.starts_with("&\\quad + \\left(")),
            "{body}"
        );
        assert!(
            body.lines().next().is_some_and(|l| l.ends_with("x \\\\")),
            "{body}"
        );
    }

    #[test]
    fn long_equations_wrap_at_top_level_signs() {
        let top = format!("{} + (a + b) − {}", "x".repeat(50), "y".repeat(40));
        let nested = format!("−({} + {} − c)/(d + e)", "x".repeat(50), "y".repeat(40));
        let long_lhs = wrap_equation(&format!("{} + {}", "a".repeat(50), "b".repeat(40)), "0");
        assert!(
            long_lhs.lines().all(|l| l.chars().count() <= COLUMNS),
            "{long_lhs}"
        );
        for rhs in [top, nested] {
            let out = wrap_equation("f", &rhs);
            assert!(out.lines().count() >= 2, "{out}");
            assert!(out.lines().all(|l| l.chars().count() <= COLUMNS), "{out}");
            // Nothing is lost: the pieces put together give the equation back.
            let joined: String = out.lines().map(str::trim).collect::<Vec<_>>().join(" ");
            assert_eq!(joined, format!("f = {rhs}"));
        }
    }

    #[test]
    fn latex_breaks_inside_long_fractions_and_brackets() {
        // A fraction whose numerator is too long for a line, as a long left-hand side.
        let sum = (0..12)
            .map(|i| format!(r"m_{i} \ddot{{x}}_{i} \left( a_{i} + b_{i} \right)"))
            .collect::<Vec<_>>()
            .join(" + ");
        let lhs = format!(r"\frac{{{sum}}}{{x_1 + x_2}}");
        let body = aligned_lines(&[Equation::new(
            Math::label("", lhs.clone()),
            Math::label("0", "0"),
        )]);
        let rows: Vec<&str> = body.split(" \\\\\n").collect();
        assert!(rows.len() > 2, "{body}");
        for row in &rows {
            assert!(visible_width(row) <= LATEX_LINE + 20, "{row}");
            // Every row is valid on its own: braces balance and no \left is left open.
            assert_eq!(row.matches('{').count(), row.matches('}').count(), "{row}");
            assert_eq!(
                row.matches("\\left").count(),
                row.matches("\\right").count(),
                "{row}"
            );
        }
        assert!(rows[0].starts_with("& \\bigl("), "{body}");
        assert!(
            body.ends_with(r"\bigr) / \bigl(x_1 + x_2\bigr) = 0"),
            "{body}"
        );
        // Short displays are untouched.
        assert_eq!(breakable_latex(r"\frac{a}{b}"), r"\frac{a}{b}");
        assert_eq!(
            breakable_latex(r"\left|x\right| \left( a + b \right)"),
            r"\bigl|x\bigr| \bigl( a + b \bigr)"
        );
    }
}
