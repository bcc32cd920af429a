//! A generated model held twice over: as the model text a user would write (what lagrange
//! reads) and as plain data the numeric route evaluates (frames as rotation matrices, points
//! as sums of unit vectors). Both are printed/evaluated from the one description below, so
//! they describe the same geometry; nothing here goes through lagrange's symbolic core.

use std::fmt::Write;

use super::dual::Scalar;

/// A scalar expression of numbers, parameters, coordinates, driven coordinates and `t`.
#[derive(Clone, Debug)]
pub enum E {
    /// A number: its value and its text as written (`0.3`, `1.39`, `2`).
    Num(f64, String),
    Param(usize),
    Coord(usize),
    Driven(usize),
    Time,
    Add(Box<E>, Box<E>),
    Sub(Box<E>, Box<E>),
    Mul(Box<E>, Box<E>),
    Neg(Box<E>),
    Sin(Box<E>),
    Cos(Box<E>),
}

impl E {
    pub fn add(self, o: E) -> E {
        E::Add(Box::new(self), Box::new(o))
    }
    pub fn sub(self, o: E) -> E {
        E::Sub(Box::new(self), Box::new(o))
    }
    pub fn mul(self, o: E) -> E {
        E::Mul(Box::new(self), Box::new(o))
    }
    pub fn sin(self) -> E {
        E::Sin(Box::new(self))
    }
    pub fn cos(self) -> E {
        E::Cos(Box::new(self))
    }
}

/// An axis of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    pub const ALL: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];
    pub fn index(self) -> usize {
        self as usize
    }
    pub fn name(self) -> &'static str {
        ["x", "y", "z"][self.index()]
    }
}

/// A frame: its parent turned by each angle about each axis in turn (`rotated … then …`).
#[derive(Clone, Debug)]
pub struct Frame {
    pub name: String,
    pub parent: usize,
    pub rotations: Vec<(E, Axis)>,
}

/// `coefficient * frame.axis`.
#[derive(Clone, Debug)]
pub struct Term {
    pub coefficient: E,
    pub frame: usize,
    pub axis: Axis,
}

/// A point: another point (or `origin`) plus a sum of terms.
#[derive(Clone, Debug)]
pub struct Point {
    pub name: String,
    pub base: Option<usize>,
    pub terms: Vec<Term>,
}

/// A particle or a rigid body. `inertia` is the tensor about the centre of mass in the
/// body frame's axes (what the numeric route uses); `inertia_text` is how the model writes it
/// (principal moments, components, possibly about another point).
#[derive(Clone, Debug)]
pub enum Mass {
    Particle {
        point: usize,
        mass: E,
    },
    Body {
        name: String,
        point: usize,
        frame: usize,
        mass: E,
        inertia: [[f64; 3]; 3],
        inertia_text: String,
    },
}

/// A load, as the model language has them.
#[derive(Clone, Debug)]
pub enum Load {
    Gravity(Vec<Term>),
    Spring {
        k: E,
        from: Option<usize>,
        to: usize,
        rest: Option<E>,
    },
    Torsion {
        k: E,
        on: E,
        rest: Option<E>,
    },
    Damper {
        c: E,
        from: Option<usize>,
        to: usize,
    },
    DamperOn {
        c: E,
        on: E,
    },
    Force {
        terms: Vec<Term>,
        at: usize,
    },
    Couple {
        terms: Vec<Term>,
        body: usize,
    },
}

/// A whole generated model. Frame 0 is the inertial frame `N`.
#[derive(Clone, Debug, Default)]
pub struct Model {
    pub comment: String,
    pub params: Vec<(String, f64, String)>,
    pub coords: Vec<String>,
    pub driven: Vec<(String, E)>,
    pub frames: Vec<Frame>,
    pub points: Vec<Point>,
    pub masses: Vec<Mass>,
    pub loads: Vec<Load>,
    /// What lagrange must report: `Some("energy")`, `Some("jacobi")`, or `None` when the
    /// model is not conservative (damping, forces that are not potential, a driven pivot).
    pub integral: Option<&'static str>,
}

/// The values the numeric route evaluates at.
pub struct Env<'a, S> {
    pub params: &'a [f64],
    pub q: &'a [S],
    pub t: S,
    pub driven: &'a [(String, E)],
}

impl E {
    /// The value at `env`.
    pub fn eval<S: Scalar>(&self, env: &Env<'_, S>) -> S {
        match self {
            E::Num(v, _) => S::c(*v),
            E::Param(i) => S::c(env.params[*i]),
            E::Coord(i) => env.q[*i],
            E::Driven(i) => env.driven[*i].1.eval(env),
            E::Time => env.t,
            E::Add(a, b) => a.eval(env) + b.eval(env),
            E::Sub(a, b) => a.eval(env) - b.eval(env),
            E::Mul(a, b) => a.eval(env) * b.eval(env),
            E::Neg(a) => -a.eval(env),
            E::Sin(a) => a.eval(env).sin(),
            E::Cos(a) => a.eval(env).cos(),
        }
    }

    /// Model text; `outer` is the binding strength around it (0 sum, 1 product operand).
    fn write(&self, m: &Model, outer: u8, out: &mut String) {
        let open = outer > 0
            && (matches!(self, E::Add(..) | E::Sub(..) | E::Neg(_))
                || matches!(self, E::Num(v, _) if *v < 0.0));
        if open {
            out.push('(');
        }
        match self {
            E::Num(_, text) => out.push_str(text),
            E::Param(i) => out.push_str(&m.params[*i].0),
            E::Coord(i) => out.push_str(&m.coords[*i]),
            E::Driven(i) => out.push_str(&m.driven[*i].0),
            E::Time => out.push('t'),
            E::Add(a, b) => {
                a.write(m, 0, out);
                out.push_str(" + ");
                b.write(m, 0, out);
            }
            E::Sub(a, b) => {
                a.write(m, 0, out);
                out.push_str(" - ");
                b.write(m, 1, out);
            }
            E::Mul(a, b) => {
                a.write(m, 1, out);
                out.push('*');
                b.write(m, 1, out);
            }
            E::Neg(a) => {
                out.push('-');
                a.write(m, 1, out);
            }
            E::Sin(a) | E::Cos(a) => {
                out.push_str(if matches!(self, E::Sin(_)) {
                    "sin("
                } else {
                    "cos("
                });
                a.write(m, 0, out);
                out.push(')');
            }
        }
        if open {
            out.push(')');
        }
    }

    pub fn text(&self, m: &Model) -> String {
        let mut s = String::new();
        self.write(m, 0, &mut s);
        s
    }
}

impl Model {
    fn vector(&self, terms: &[Term]) -> String {
        let mut s = String::new();
        for (i, term) in terms.iter().enumerate() {
            let unit = format!("{}.{}", self.frames[term.frame].name, term.axis.name());
            // A negative number reads as a subtraction, as people write it.
            match &term.coefficient {
                E::Num(v, text) if *v < 0.0 => {
                    let text = text.trim_start_matches('-');
                    let _ = write!(s, "{}{text}*{unit}", if i == 0 { "-" } else { " - " });
                }
                E::Neg(c) => {
                    let c = c.text_in_product(self);
                    let _ = write!(s, "{}{c}*{unit}", if i == 0 { "-" } else { " - " });
                }
                c => {
                    if i > 0 {
                        s.push_str(" + ");
                    }
                    let _ = write!(s, "{}*{unit}", c.text_in_product(self));
                }
            }
        }
        if s.is_empty() {
            s.push_str("0*N.x");
        }
        s
    }

    fn point_name(&self, p: Option<usize>) -> &str {
        p.map_or("origin", |p| &self.points[p].name)
    }

    /// The model text.
    pub fn text(&self) -> String {
        let mut s = format!("# {}\n", self.comment);
        let _ = writeln!(s, "coordinates {}", self.coords.join(", "));
        if !self.params.is_empty() {
            let list: Vec<String> = self
                .params
                .iter()
                .map(|(n, _, t)| format!("{n} = {t}"))
                .collect();
            let _ = writeln!(s, "parameters {}", list.join(", "));
        }
        for (name, e) in &self.driven {
            let _ = writeln!(s, "driven {name} = {}", e.text(self));
        }
        for (i, f) in self.frames.iter().enumerate() {
            if i == 0 {
                let _ = writeln!(s, "frame {}", f.name);
                continue;
            }
            let turns: Vec<String> = f
                .rotations
                .iter()
                .map(|(a, axis)| format!("{} about {}", a.text(self), axis.name()))
                .collect();
            let _ = writeln!(
                s,
                "frame {} = {} rotated {}",
                f.name,
                self.frames[f.parent].name,
                turns.join(" then ")
            );
        }
        for p in &self.points {
            let base = p.base.map(|b| self.points[b].name.clone());
            let v = self.vector(&p.terms);
            let _ = match base {
                Some(b) if v.starts_with('-') => {
                    writeln!(s, "point {} = {b} - {}", p.name, &v[1..])
                }
                Some(b) => writeln!(s, "point {} = {b} + {v}", p.name),
                None => writeln!(s, "point {} = {v}", p.name),
            };
        }
        for mass in &self.masses {
            match mass {
                Mass::Particle { point, mass } => {
                    let _ = writeln!(
                        s,
                        "particle {} mass {}",
                        self.points[*point].name,
                        mass.text(self)
                    );
                }
                Mass::Body {
                    name,
                    point,
                    frame,
                    mass,
                    inertia_text,
                    ..
                } => {
                    let _ = writeln!(
                        s,
                        "body {name} mass {} at {} frame {} inertia {inertia_text}",
                        mass.text(self),
                        self.points[*point].name,
                        self.frames[*frame].name
                    );
                }
            }
        }
        for load in &self.loads {
            let _ = writeln!(s, "{}", self.load_text(load));
        }
        s
    }

    fn load_text(&self, load: &Load) -> String {
        let rest = |r: &Option<E>, word: &str| {
            r.as_ref()
                .map_or(String::new(), |r| format!(" {word} {}", r.text(self)))
        };
        match load {
            Load::Gravity(terms) => format!("gravity {}", self.vector(terms)),
            Load::Spring {
                k,
                from,
                to,
                rest: r,
            } => format!(
                "spring {} from {} to {}{}",
                k.text_in_product(self),
                self.point_name(*from),
                self.point_name(Some(*to)),
                rest(r, "length")
            ),
            Load::Torsion { k, on, rest: r } => format!(
                "spring {} on {}{}",
                k.text_in_product(self),
                on.text(self),
                rest(r, "rest")
            ),
            Load::Damper { c, from, to } => format!(
                "damper {} from {} to {}",
                c.text_in_product(self),
                self.point_name(*from),
                self.point_name(Some(*to))
            ),
            Load::DamperOn { c, on } => {
                format!("damper {} on {}", c.text_in_product(self), on.text(self))
            }
            Load::Force { terms, at } => {
                format!("force {} at {}", self.vector(terms), self.points[*at].name)
            }
            Load::Couple { terms, body } => {
                let Mass::Body { name, .. } = &self.masses[*body] else {
                    unreachable!("couples are generated on bodies only")
                };
                format!("couple {} on {name}", self.vector(terms))
            }
        }
    }
}

impl E {
    /// As an operand of a product (parenthesised when a sum).
    fn text_in_product(&self, m: &Model) -> String {
        let mut s = String::new();
        self.write(m, 1, &mut s);
        s
    }
}
