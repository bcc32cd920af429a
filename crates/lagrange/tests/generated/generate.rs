//! Random models as people write them: planar and 3-D chains and trees of revolute and
//! sliding joints carrying particles and rigid bodies off their axes (principal, full and
//! hinge-referred inertia tensors), constant angle offsets inline (`th2 + 0.3`, `rotated 1.39`)
//! and as parameters, springs with and without rest lengths, torsional springs, dampers,
//! gravity in any direction, constant and follower forces, couples, a driven pivot or a
//! frame spun at a constant rate. Every number is a short decimal, written inline or as a
//! parameter. A seed gives one model, always the same.

use super::model::{Axis, Frame, Load, Mass, Model, Point, Term, E};

/// SplitMix64: small, fast, and the same on every platform.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x5851_f42d_4c95_7f2d)
    }
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    pub fn axis(&mut self) -> Axis {
        Axis::ALL[self.below(3)]
    }
}

/// How large the models may be.
#[derive(Clone, Copy, Debug)]
pub struct Size {
    pub max_links: usize,
}

/// A decimal with at most `places` places, never 0: its value and its text.
fn decimal(rng: &mut Rng, lo: f64, hi: f64, places: usize) -> (f64, String) {
    loop {
        let text = format!("{:.*}", places, rng.uniform(lo, hi));
        let text = if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        };
        let value: f64 = text.parse().expect("a decimal");
        if value != 0.0 {
            return (value, if text == "-0" { "0".into() } else { text });
        }
    }
}

struct Gen {
    rng: Rng,
    m: Model,
    planar: bool,
    /// Per link: the frame its children and masses use, its origin (None: `origin`).
    links: Vec<(usize, Option<usize>)>,
    /// Points fixed in the ground frame (spring anchors).
    anchors: Vec<Option<usize>>,
    bodies: Vec<usize>,
    revolute: Vec<usize>,
    names: usize,
}

impl Gen {
    fn name(&mut self, prefix: &str) -> String {
        self.names += 1;
        format!("{prefix}{}", self.names)
    }

    /// A constant in `[lo, hi]`: a decimal inline or a parameter holding it.
    fn constant(&mut self, lo: f64, hi: f64, prefix: &str) -> E {
        let places = 1 + self.rng.below(2);
        let (value, text) = decimal(&mut self.rng, lo, hi, places);
        if self.rng.chance(0.4) {
            let name = self.name(prefix);
            self.m.params.push((name, value, text));
            E::Param(self.m.params.len() - 1)
        } else {
            E::Num(value, text)
        }
    }

    fn value(&self, e: &E) -> f64 {
        let env = super::model::Env {
            params: &self.param_values(),
            q: &[],
            t: 0.0,
            driven: &[],
        };
        e.eval(&env)
    }

    fn param_values(&self) -> Vec<f64> {
        self.m.params.iter().map(|p| p.1).collect()
    }

    fn frame(&mut self, prefix: &str, parent: usize, rotations: Vec<(E, Axis)>) -> usize {
        let name = self.name(prefix);
        self.m.frames.push(Frame {
            name,
            parent,
            rotations,
        });
        self.m.frames.len() - 1
    }

    fn point(&mut self, prefix: &str, base: Option<usize>, terms: Vec<Term>) -> usize {
        let name = self.name(prefix);
        self.m.points.push(Point { name, base, terms });
        self.m.points.len() - 1
    }

    /// Offsets along the frame's axes: x and y in the plane, all three in 3-D.
    fn offsets(&mut self, frame: usize, lo: f64, hi: f64, prefix: &str) -> Vec<Term> {
        self.offsets_up_to(frame, lo, hi, prefix, 3)
    }

    /// [`Gen::offsets`] along the first `limit` axes only.
    fn offsets_up_to(
        &mut self,
        frame: usize,
        lo: f64,
        hi: f64,
        prefix: &str,
        limit: usize,
    ) -> Vec<Term> {
        let axes: &[Axis] = if self.planar {
            &[Axis::X, Axis::Y]
        } else {
            &Axis::ALL
        };
        axes.iter()
            .take(limit)
            .map(|&axis| {
                let sign = if self.rng.chance(0.3) { -1.0 } else { 1.0 };
                let c = self.constant(lo, hi, prefix);
                let coefficient = if sign < 0.0 { negate(c) } else { c };
                Term {
                    coefficient,
                    frame,
                    axis,
                }
            })
            .collect()
    }

    fn rotation_axis(&mut self) -> Axis {
        if self.planar {
            Axis::Z
        } else {
            self.rng.axis()
        }
    }
}

fn negate(e: E) -> E {
    match e {
        E::Num(v, text) => E::Num(-v, format!("-{text}")),
        e => E::Neg(Box::new(e)),
    }
}

/// The model of `seed`.
pub fn model(seed: u64, size: Size) -> Model {
    let mut rng = Rng::new(seed);
    let planar = rng.chance(0.5);
    let mut g = Gen {
        rng,
        m: Model::default(),
        planar,
        links: Vec::new(),
        anchors: vec![None],
        bodies: Vec::new(),
        revolute: Vec::new(),
        names: 0,
    };
    g.m.frames.push(Frame {
        name: "N".into(),
        parent: 0,
        rotations: Vec::new(),
    });
    let ground = ground(&mut g);
    let n = 1 + g.rng.below(size.max_links);
    for i in 0..n {
        let parent = if g.rng.chance(0.6) {
            i
        } else {
            g.rng.below(i + 1)
        };
        link(&mut g, parent);
    }
    let conservative = ground.spinning || (!ground.driven && g.rng.chance(0.5));
    loads(&mut g, &ground, conservative);
    g.m.integral = match (conservative, ground.spinning, ground.driven) {
        (true, true, _) => Some("jacobi"),
        (true, false, false) => Some("energy"),
        _ => None,
    };
    g.m.comment = format!(
        "generated model {seed}: {} {}, {n} links{}{}",
        if planar { "planar" } else { "3-D" },
        if g.m.integral.is_some() {
            "conservative"
        } else {
            "non-conservative"
        },
        if ground.driven { ", driven pivot" } else { "" },
        if ground.spinning {
            ", spinning frame"
        } else {
            ""
        },
    );
    g.m
}

struct Ground {
    frame: usize,
    driven: bool,
    spinning: bool,
}

/// The ground link: `N` at `origin`, a pivot driven along a line, or (3-D) a frame spun at
/// a constant rate about `N.z`.
fn ground(g: &mut Gen) -> Ground {
    let roll = g.rng.unit();
    if roll < 0.2 {
        // A driven pivot: `driven s = A*sin(w*t)`, or the motion written in the point.
        let amplitude = g.constant(0.05, 0.3, "a");
        let (w, text) = decimal(&mut g.rng, 0.5, 3.0, 1);
        let wave = E::Num(w, text).mul(E::Time);
        let wave = if g.rng.chance(0.5) {
            wave.sin()
        } else {
            wave.cos()
        };
        let motion = amplitude.mul(wave);
        let coefficient = if g.rng.chance(0.5) {
            g.m.driven.push(("s".into(), motion));
            E::Driven(0)
        } else {
            motion
        };
        let axis = if g.planar {
            [Axis::X, Axis::Y][g.rng.below(2)]
        } else {
            g.rng.axis()
        };
        let pivot = g.point(
            "O",
            None,
            vec![Term {
                coefficient,
                frame: 0,
                axis,
            }],
        );
        g.links.push((0, Some(pivot)));
        return Ground {
            frame: 0,
            driven: true,
            spinning: false,
        };
    }
    if roll < 0.35 && !g.planar {
        let (rate, text) = decimal(&mut g.rng, 0.3, 1.5, 1);
        g.m.driven
            .push(("psi".into(), E::Num(rate, text).mul(E::Time)));
        let frame = g.frame("R", 0, vec![(E::Driven(0), Axis::Z)]);
        g.links.push((frame, None));
        return Ground {
            frame,
            driven: false,
            spinning: true,
        };
    }
    g.links.push((0, None));
    Ground {
        frame: 0,
        driven: false,
        spinning: false,
    }
}

/// One more link on `parent`: a revolute or sliding joint, its frames, its masses.
fn link(g: &mut Gen, parent: usize) {
    let (parent_frame, parent_origin) = g.links[parent];
    let index = g.m.coords.len();
    let hinge = if g.rng.chance(0.7) {
        // Half the joints sit on an axis of the parent (a plain hinge offset along x).
        let limit = if g.rng.chance(0.5) { 1 } else { 3 };
        let offsets = g.offsets_up_to(parent_frame, 0.3, 1.0, "l", limit);
        Some(g.point("O", parent_origin, offsets))
    } else {
        parent_origin
    };
    let (frame, origin) = if g.rng.chance(0.8) {
        let name = format!("th{}", index + 1);
        g.m.coords.push(name);
        g.revolute.push(index);
        let angle = angle_with_offset(g, E::Coord(index));
        let axis = g.rotation_axis();
        let mut rotations = vec![(angle, axis)];
        if !g.planar && g.rng.chance(0.3) {
            let tilt = g.constant(0.2, 1.4, "be");
            rotations.push((tilt, g.rng.axis()));
        }
        let frame = g.frame("B", parent_frame, rotations);
        (offset_frame(g, frame), hinge)
    } else {
        let name = format!("x{}", index + 1);
        g.m.coords.push(name);
        let axis = if g.planar {
            [Axis::X, Axis::Y][g.rng.below(2)]
        } else {
            g.rng.axis()
        };
        let slide = vec![Term {
            coefficient: E::Coord(index),
            frame: parent_frame,
            axis,
        }];
        let origin = g.point("O", hinge, slide);
        let frame = if g.rng.chance(0.4) {
            let turn = g.constant(0.2, 1.4, "be");
            let axis = g.rotation_axis();
            g.frame("C", parent_frame, vec![(turn, axis)])
        } else {
            parent_frame
        };
        (frame, Some(origin))
    };
    masses(g, frame, origin);
    g.links.push((frame, origin));
}

/// `q`, `q + c`, `c + q` or `q - c` with `c` a decimal or a parameter.
fn angle_with_offset(g: &mut Gen, q: E) -> E {
    if g.rng.chance(0.55) {
        return q;
    }
    let c = g.constant(0.1, 1.5, "al");
    match g.rng.below(3) {
        0 => q.add(c),
        1 => c.add(q),
        _ => q.sub(c),
    }
}

/// Sometimes a frame turned from `frame` by a constant angle (`rotated 1.39 about z`).
fn offset_frame(g: &mut Gen, frame: usize) -> usize {
    if !g.rng.chance(0.3) {
        return frame;
    }
    let angle = g.constant(0.2, 1.5, "ga");
    let axis = g.rotation_axis();
    g.frame("D", frame, vec![(angle, axis)])
}

/// A particle, a body, or both, off the link's axes.
fn masses(g: &mut Gen, frame: usize, origin: Option<usize>) {
    let what = g.rng.below(4);
    if what != 1 {
        let offsets = g.offsets(frame, 0.15, 0.8, "c");
        let point = g.point("P", origin, offsets);
        let mass = g.constant(0.3, 2.0, "m");
        g.m.masses.push(Mass::Particle { point, mass });
    }
    if what != 0 {
        body(g, frame, origin);
    }
}

fn body(g: &mut Gen, frame: usize, origin: Option<usize>) {
    let offsets = g.offsets(frame, 0.1, 0.6, "c");
    let centre: Vec<f64> = offsets.iter().map(|t| g.value(&t.coefficient)).collect();
    let point = g.point("G", origin, offsets);
    let mass = g.constant(0.3, 2.0, "m");
    let mut inertia = [[0.0; 3]; 3];
    let style = g.rng.below(3);
    let text = if style == 0 {
        let moments: Vec<E> = (0..3).map(|_| g.constant(0.05, 0.5, "J")).collect();
        for (i, e) in moments.iter().enumerate() {
            inertia[i][i] = g.value(e);
        }
        let texts: Vec<String> = moments.iter().map(|e| e.text(&g.m)).collect();
        texts.join(", ")
    } else {
        // Diagonally dominant: positive definite whatever the products' signs.
        for (i, row) in inertia.iter_mut().enumerate() {
            row[i] = decimal(&mut g.rng, 0.3, 0.6, 2).0;
        }
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            let p = decimal(&mut g.rng, -0.09, 0.09, 2).0;
            inertia[i][j] = p;
            inertia[j][i] = p;
        }
        if style == 2 && origin.is_some() {
            about_hinge(g, &inertia, &centre, &mass, origin)
        } else {
            components(&inertia, |x| x.to_string())
        }
    };
    let name = g.name("rb");
    g.bodies.push(g.m.masses.len());
    g.m.masses.push(Mass::Body {
        name,
        point,
        frame,
        mass,
        inertia,
        inertia_text: text,
    });
}

fn components(i: &[[f64; 3]; 3], f: impl Fn(f64) -> String) -> String {
    format!(
        "xx = {}, yy = {}, zz = {}, xy = {}, xz = {}, yz = {}",
        f(i[0][0]),
        f(i[1][1]),
        f(i[2][2]),
        f(i[0][1]),
        f(i[0][2]),
        f(i[1][2])
    )
}

/// The tensor about the link's origin (parallel axes: `I_O = I_G + m (|c|² 1 − c cᵀ)`),
/// written `… about O`, so that lagrange moves it back to the centre.
fn about_hinge(
    g: &mut Gen,
    inertia: &[[f64; 3]; 3],
    centre: &[f64],
    mass: &E,
    origin: Option<usize>,
) -> String {
    let m = g.value(mass);
    let c = [0, 1, 2].map(|k| centre.get(k).copied().unwrap_or(0.0));
    let c2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    let mut about = *inertia;
    for i in 0..3 {
        for j in 0..3 {
            about[i][j] += m * (if i == j { c2 } else { 0.0 } - c[i] * c[j]);
        }
    }
    let name = &g.m.points[origin.expect("a named origin")].name;
    format!("{} about {name}", components(&about, |x| x.to_string()))
}

/// Gravity, springs, torsional springs, and for a non-conservative model dampers, forces
/// and couples.
fn loads(g: &mut Gen, ground: &Ground, conservative: bool) {
    if g.rng.chance(0.85) {
        let terms = if ground.spinning {
            // Along the spin axis, so that the Lagrangian does not depend on t.
            vec![Term {
                coefficient: negate(g.constant(5.0, 12.0, "g")),
                frame: 0,
                axis: Axis::Z,
            }]
        } else if g.rng.chance(0.5) {
            let axis = if g.planar { Axis::Y } else { g.rng.axis() };
            vec![Term {
                coefficient: negate(g.constant(5.0, 12.0, "g")),
                frame: 0,
                axis,
            }]
        } else {
            g.offsets(0, 0.5, 9.0, "g")
        };
        g.m.loads.push(Load::Gravity(terms));
    }
    let anchor_frame = ground.frame;
    let points = g.m.points.len();
    for _ in 0..g.rng.below(3) {
        let from = spring_end(g, anchor_frame, points);
        let to = g.rng.below(points);
        if from == Some(to) {
            continue;
        }
        let k = g.constant(0.5, 6.0, "k");
        let rest = if g.rng.chance(0.6) {
            Some(g.constant(0.2, 0.9, "L"))
        } else {
            None
        };
        g.m.loads.push(Load::Spring { k, from, to, rest });
    }
    if g.rng.chance(0.4) {
        let on = coordinate_difference(g);
        let k = g.constant(0.5, 4.0, "kt");
        let rest = if g.rng.chance(0.5) {
            Some(g.constant(0.05, 0.6, "r"))
        } else {
            None
        };
        g.m.loads.push(Load::Torsion { k, on, rest });
    }
    if !conservative {
        non_conservative(g, anchor_frame, points);
    }
}

/// A point for one end of a spring: an existing one, `origin`, or a new anchor.
fn spring_end(g: &mut Gen, frame: usize, points: usize) -> Option<usize> {
    match g.rng.below(3) {
        0 => Some(g.rng.below(points)),
        1 => g.anchors[g.rng.below(g.anchors.len())],
        _ => {
            let offsets = g.offsets(frame, 0.2, 1.2, "h");
            let a = g.point("A", None, offsets);
            g.anchors.push(Some(a));
            Some(a)
        }
    }
}

/// `q_i` or `q_i - q_j`.
fn coordinate_difference(g: &mut Gen) -> E {
    let n = g.m.coords.len();
    let i = g.rng.below(n);
    let j = g.rng.below(n);
    if i == j {
        E::Coord(i)
    } else {
        E::Coord(i).sub(E::Coord(j))
    }
}

fn non_conservative(g: &mut Gen, anchor_frame: usize, points: usize) {
    for _ in 0..1 + g.rng.below(3) {
        match g.rng.below(5) {
            0 => {
                let from = spring_end(g, anchor_frame, points);
                let to = g.rng.below(points);
                if from != Some(to) {
                    let c = g.constant(0.1, 2.0, "cd");
                    g.m.loads.push(Load::Damper { c, from, to });
                }
            }
            1 => {
                let on = coordinate_difference(g);
                let c = g.constant(0.1, 2.0, "cd");
                g.m.loads.push(Load::DamperOn { c, on });
            }
            2 => {
                // A constant force, or a follower force along a link's axes.
                let frame = if g.rng.chance(0.5) {
                    0
                } else {
                    g.links[g.rng.below(g.links.len())].0
                };
                let terms = g.offsets(frame, 0.2, 2.0, "F");
                let at = g.rng.below(points);
                g.m.loads.push(Load::Force { terms, at });
            }
            _ if !g.bodies.is_empty() => {
                let body = g.bodies[g.rng.below(g.bodies.len())];
                let terms = if g.planar {
                    let c = g.constant(0.1, 1.0, "C");
                    vec![Term {
                        coefficient: c,
                        frame: 0,
                        axis: Axis::Z,
                    }]
                } else {
                    g.offsets(0, 0.1, 1.0, "C")
                };
                g.m.loads.push(Load::Couple { terms, body });
            }
            _ => {
                let on = E::Coord(g.rng.below(g.m.coords.len()));
                let c = g.constant(0.1, 2.0, "cd");
                g.m.loads.push(Load::DamperOn { c, on });
            }
        }
    }
}
