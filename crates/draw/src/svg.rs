//! Writing a projected scene as SVG text: every symbol in page pixels, then the labels placed
//! by [`crate::layout`]. The text is deterministic (fixed number formatting, no dates) and
//! self-contained (no fonts, scripts or links). Named points carry `id="point-NAME"` and the
//! root carries the projection (`data-scale`, `data-origin`, `data-u`, `data-v`), so a
//! program can check a drawn position against the model; labels carry their box
//! (`data-box="x y w h"`).

use std::fmt::Write;

use crate::layout::{place, Obstacle, Rect, Request};
use crate::raster::{Paint, Shape};
use crate::sample::{add, norm, sub};
use crate::scene::{ArcKind, ArrowKind, Item, Scene, P3};
use crate::view::View;

pub(crate) type Pt = (f64, f64);

const FONT: f64 = 14.0;
const INK: &str = "#222";
const FORCE: &str = "#b03a2e";
const COORDINATE: &str = "#1f5fa8";
const AXIS: &str = "#666";

/// A label waiting for its place.
struct Label {
    id: String,
    text: String,
    class: &'static str,
    anchor: Pt,
}

/// What the writer gives: the SVG text, each label's id and box (in the order written), and
/// the ids of the labels that found no place clear of the drawing.
pub(crate) struct Written {
    pub svg: String,
    pub labels: Vec<(String, Rect)>,
    pub touching: Vec<String>,
    /// The drawing and its labels without the `<svg>` root (for an animation's frames).
    pub inner: String,
    /// The page box around the drawing and its labels, margin included.
    pub bounds: (Pt, Pt),
    /// What was drawn, in order, for a raster ([`crate::raster`]).
    pub shapes: Vec<Shape>,
}

/// The style sheet of the figures.
pub(crate) fn style() -> &'static str {
    STYLE
}

/// A page coordinate as the SVG writes it.
pub(crate) fn number(x: f64) -> String {
    f(x).to_string()
}

/// The SVG of `scene` in `view`.
pub(crate) fn write(scene: &Scene, view: &View) -> Written {
    written(scene, view, true)
}

/// An animation's frame: [`Written::inner`], the labels and the bounds of `scene` in `view`,
/// as [`write`] gives them, without the whole SVG's text, the shapes of a raster or the
/// labels that touch the drawing.
pub(crate) fn frame(scene: &Scene, view: &View) -> Written {
    written(scene, view, false)
}

fn written(scene: &Scene, view: &View, whole: bool) -> Written {
    let mut w = Writer {
        view,
        body: String::new(),
        obstacles: Vec::new(),
        labels: Vec::new(),
        ids: Vec::new(),
        size: scene.size,
        shapes: Vec::new(),
        raster: whole,
    };
    for item in &scene.items {
        w.item(item);
    }
    w.gravity(scene);
    let requests: Vec<Request> = w
        .labels
        .iter()
        .map(|l| Request {
            size: text_size(&l.text),
            anchor: l.anchor,
        })
        .collect();
    let rects = place(&requests, &w.obstacles);
    let mut text = String::new();
    let mut boxes = Vec::new();
    let mut touching = Vec::new();
    for (label, r) in w.labels.iter().zip(&rects) {
        let _ = writeln!(
            text,
            r#"<text id="{}" class="{}" x="{}" y="{}" data-box="{} {} {} {}">{}</text>"#,
            label.id,
            label.class,
            f(r.x + 0.5 * r.w),
            f(r.y + r.h - 0.25 * FONT),
            f(r.x),
            f(r.y),
            f(r.w),
            f(r.h),
            escape(&label.text)
        );
        if w.raster {
            w.shapes.push(Shape::Text {
                at: (r.x + 0.5 * r.w, r.y + r.h - 0.25 * FONT),
                text: label.text.clone(),
                colour: class_colour(label.class),
                // The style sheet sets coordinates in italics.
                oblique: label.class == "coordinate",
            });
        }
        boxes.push((label.id.clone(), *r));
        // Only a figure reports the labels that touch its drawing.
        if whole && w.obstacles.iter().any(|o| o.meets(r)) {
            touching.push(label.id.clone());
        }
    }
    let (lo, hi) = extent(&w.obstacles, &rects);
    let svg = if whole {
        root(view, (lo, hi), &w.body, &text)
    } else {
        String::new()
    };
    Written {
        inner: format!("{}{}", w.body, text),
        svg,
        labels: boxes,
        touching,
        bounds: (lo, hi),
        shapes: w.shapes,
    }
}

/// The whole SVG: the root (with the projection), the style sheet, white paper over the box
/// `(lo, hi)`, the drawing and its labels.
fn root(view: &View, (lo, hi): (Pt, Pt), body: &str, text: &str) -> String {
    format!(
        concat!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="{} {} {} {}" width="{}" height="{}" "#,
            r#"data-scale="{}" data-origin="{} {}" data-u="{} {} {}" data-v="{} {} {}">"#,
            "\n<style>{}</style>\n",
            r#"<rect x="{}" y="{}" width="{}" height="{}" fill="white"/>"#,
            "\n{}{}</svg>\n"
        ),
        f(lo.0),
        f(lo.1),
        f(hi.0 - lo.0),
        f(hi.1 - lo.1),
        f(hi.0 - lo.0),
        f(hi.1 - lo.1),
        view.scale,
        view.origin.0,
        view.origin.1,
        view.u[0],
        view.u[1],
        view.u[2],
        view.v[0],
        view.v[1],
        view.v[2],
        STYLE,
        f(lo.0),
        f(lo.1),
        f(hi.0 - lo.0),
        f(hi.1 - lo.1),
        body,
        text
    )
}

/// The colour the style sheet gives a label of this class.
fn class_colour(class: &str) -> crate::raster::Colour {
    let colour = match class {
        "coordinate" => COORDINATE,
        "force" => FORCE,
        "body" => "#555",
        "axis" => AXIS,
        _ => INK,
    };
    crate::raster::colour(colour).unwrap_or([0x22, 0x22, 0x22])
}

const STYLE: &str = concat!(
    "text{font-family:'DejaVu Sans',Arial,sans-serif;font-size:14px;text-anchor:middle;fill:#222}",
    "text.coordinate{fill:#1f5fa8;font-style:italic}text.force{fill:#b03a2e}text.body{fill:#555}",
    "text.axis{fill:#666}"
);

/// The page box around the drawing and its labels, with a margin.
fn extent(obstacles: &[Obstacle], rects: &[Rect]) -> (Pt, Pt) {
    let mut lo = (f64::INFINITY, f64::INFINITY);
    let mut hi = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut take = |x: f64, y: f64| {
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    };
    for o in obstacles {
        match *o {
            Obstacle::Segment(a, b, h) => {
                take(a.0 - h, a.1 - h);
                take(b.0 + h, b.1 + h);
                take(a.0 + h, a.1 + h);
                take(b.0 - h, b.1 - h);
            }
            Obstacle::Circle(c, r) => {
                take(c.0 - r, c.1 - r);
                take(c.0 + r, c.1 + r);
            }
        }
    }
    for r in rects {
        take(r.x, r.y);
        take(r.x + r.w, r.y + r.h);
    }
    if !lo.0.is_finite() {
        return ((0.0, 0.0), (100.0, 100.0));
    }
    let m = 12.0;
    ((lo.0 - m, lo.1 - m), (hi.0 + m, hi.1 + m))
}

/// A number as written: two decimals, no `-0`.
fn f(x: f64) -> Number {
    Number(x)
}

/// A page coordinate written with two decimals, `-0.00` as `0.00`, straight into the text
/// (no string of its own: an animation writes hundreds of thousands of them).
#[derive(Clone, Copy)]
struct Number(f64);

impl std::fmt::Display for Number {
    fn fmt(&self, out: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let Some((negative, n)) = fixed(self.0, 100) {
            return out.write_str(decimal(&mut [0; 24], negative && n > 0, n, 2));
        }
        // A negative number whose magnitude is under 0.005 (the double nearest 0.005 is just
        // above it, so it rounds up) would print as `-0.00`.
        if self.0.is_sign_negative() && -self.0 < 0.005 {
            out.write_str("0.00")
        } else {
            write!(out, "{:.2}", self.0)
        }
    }
}

/// The text of `steps / 10^decimals` with `decimals` digits after the point (none and no point
/// for 0), a minus sign first when `negative`, written into the end of `buffer`.
pub(crate) fn decimal(buffer: &mut [u8; 24], negative: bool, steps: u64, decimals: usize) -> &str {
    let mut at = buffer.len();
    let mut rest = steps;
    let mut count = 0;
    while count <= decimals || rest > 0 {
        if count == decimals && decimals > 0 {
            at -= 1;
            buffer[at] = b'.';
        }
        at -= 1;
        // A single decimal digit.
        #[allow(clippy::cast_possible_truncation)]
        let digit = (rest % 10) as u8;
        buffer[at] = b'0' + digit;
        rest /= 10;
        count += 1;
    }
    if negative {
        at -= 1;
        buffer[at] = b'-';
    }
    // Only ASCII digits, a point and a minus sign were written.
    std::str::from_utf8(&buffer[at..]).unwrap_or_default()
}

/// `|x|` rounded to a multiple of `1/per_unit` (`per_unit` a power of ten), as the count of
/// those steps, with the sign of `x` — exactly what `format!("{x:.N}")` rounds to (the
/// nearest, from `x`'s exact binary value), found by integer arithmetic. `None` when that
/// cannot be told that way (then let `format!` do it): `x` is not finite, or not below 10⁶
/// in magnitude, or `|x| · per_unit` lies within 10⁻⁶ of a half step, where the product's
/// rounding (at most about 10⁻⁸ here) could decide the way. Formatting a float exactly is
/// most of the cost of writing an animation's frames; this is a few multiplications.
pub(crate) fn fixed(x: f64, per_unit: u32) -> Option<(bool, u64)> {
    let magnitude = x.abs();
    if magnitude.is_nan() || magnitude >= 1e6 {
        return None;
    }
    let scaled = magnitude * f64::from(per_unit);
    if (scaled.fract() - 0.5).abs() < 1e-6 {
        return None;
    }
    // Below 10⁶ · 100 and not negative: the conversion is exact.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let steps = scaled.round() as u64;
    Some((x.is_sign_negative(), steps))
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The box of a label's text: widths per character of a sans-serif face, generous.
fn text_size(text: &str) -> (f64, f64) {
    let width: f64 = text
        .chars()
        .map(|c| match c {
            '\u{2009}' => 0.2,
            'i' | 'l' | 'j' | '.' | ',' | '\'' | '(' | ')' | '|' => 0.35,
            '₀'..='₉' => 0.45,
            'm' | 'w' | 'M' | 'W' => 0.95,
            c if c.is_uppercase() => 0.75,
            _ => 0.62,
        })
        .sum();
    (width * FONT + 4.0, FONT * 1.25)
}

struct Writer<'v> {
    view: &'v View,
    body: String,
    obstacles: Vec<Obstacle>,
    labels: Vec<Label>,
    ids: Vec<String>,
    size: f64,
    shapes: Vec<Shape>,
    /// Whether to keep [`Writer::shapes`] (a figure's PNG needs them; an animation's frames
    /// do not).
    raster: bool,
}

impl Writer<'_> {
    /// Keeps what was drawn for the raster, when one is wanted.
    fn shape(&mut self, make: impl FnOnce() -> Shape) {
        if self.raster {
            self.shapes.push(make());
        }
    }

    fn p(&self, p: P3) -> Pt {
        self.view.page(p)
    }

    /// A unique id from a base (names may repeat across kinds).
    fn id(&mut self, base: String) -> String {
        let mut id = base.clone();
        let mut n = 1;
        while self.ids.contains(&id) {
            n += 1;
            id = format!("{base}-{n}");
        }
        self.ids.push(id.clone());
        id
    }

    fn label(&mut self, id: &str, text: &str, class: &'static str, anchor: Pt) {
        let id = self.id(format!("label-{id}"));
        self.labels.push(Label {
            id,
            text: text.to_owned(),
            class,
            anchor,
        });
    }

    fn line(&mut self, a: Pt, b: Pt, attrs: &str, half: f64) {
        let _ = writeln!(
            self.body,
            r#"<line x1="{}" y1="{}" x2="{}" y2="{}" {attrs}/>"#,
            f(a.0),
            f(a.1),
            f(b.0),
            f(b.1)
        );
        self.shape(|| Shape::Path {
            runs: vec![vec![a, b]],
            closed: false,
            paint: Paint::from_attributes(attrs, false),
        });
        self.obstacles.push(Obstacle::Segment(a, b, half));
    }

    fn polyline(&mut self, points: &[Pt], attrs: &str, half: f64) {
        let mut d = String::new();
        for (k, p) in points.iter().enumerate() {
            let _ = write!(d, "{}{} {}", if k == 0 { "" } else { " " }, f(p.0), f(p.1));
        }
        let _ = writeln!(self.body, r#"<polyline points="{d}" fill="none" {attrs}/>"#);
        self.shape(|| Shape::Path {
            runs: vec![points.to_vec()],
            closed: false,
            paint: Paint::from_attributes(attrs, false),
        });
        for pair in points.windows(2) {
            self.obstacles
                .push(Obstacle::Segment(pair[0], pair[1], half));
        }
    }

    fn polygon(&mut self, points: &[Pt], attrs: &str) {
        let mut d = String::new();
        for (k, p) in points.iter().enumerate() {
            let _ = write!(d, "{}{} {}", if k == 0 { "" } else { " " }, f(p.0), f(p.1));
        }
        let _ = writeln!(self.body, r#"<polygon points="{d}" {attrs}/>"#);
        self.shape(|| Shape::Path {
            runs: vec![points.to_vec()],
            closed: true,
            paint: Paint::from_attributes(attrs, true),
        });
        let n = points.len();
        for k in 0..n {
            self.obstacles
                .push(Obstacle::Segment(points[k], points[(k + 1) % n], 1.5));
        }
    }

    fn circle(&mut self, c: Pt, r: f64, attrs: &str) {
        let _ = writeln!(
            self.body,
            r#"<circle cx="{}" cy="{}" r="{}" {attrs}/>"#,
            f(c.0),
            f(c.1),
            f(r)
        );
        self.shape(|| Shape::Circle {
            centre: c,
            radius: r,
            paint: Paint::from_attributes(attrs, true),
        });
    }

    fn item(&mut self, item: &Item) {
        match item {
            Item::Rod { a, b } => {
                let (a, b) = (self.p(*a), self.p(*b));
                self.line(
                    a,
                    b,
                    &format!(
                        r#"class="rod" stroke="{INK}" stroke-width="4" stroke-linecap="round""#
                    ),
                    2.5,
                );
            }
            Item::Disk {
                name,
                centre,
                normal,
                radius,
                marker,
            } => self.disk(name, *centre, *normal, *radius, *marker),
            Item::Block {
                name,
                centre,
                along,
                size,
            } => self.block(name, *centre, *along, *size),
            Item::Track { a, b, side } => self.track(*a, *b, *side),
            Item::Sphere { centre, radius } => {
                let c = self.p(*centre);
                let r = radius * self.view.scale;
                self.circle(
                    c,
                    r,
                    &format!(
                        r##"class="surface" fill="#dcdcdc" stroke="{INK}" stroke-width="1.5""##
                    ),
                );
                self.ring(c, r);
            }
            Item::Support { at, down } => self.support(*at, *down),
            Item::Wall { at, normal } => self.wall(*at, *normal),
            Item::Hinge { at } => {
                let c = self.p(*at);
                self.circle(
                    c,
                    4.0,
                    &format!(r#"class="hinge" fill="white" stroke="{INK}" stroke-width="1.5""#),
                );
                self.obstacles.push(Obstacle::Circle(c, 5.0));
            }
            Item::Particle { name, at } => {
                let c = self.p(*at);
                let id = self.id(format!("point-{name}"));
                self.circle(
                    c,
                    6.0,
                    &format!(r#"id="{id}" class="particle" fill="{INK}""#),
                );
                self.obstacles.push(Obstacle::Circle(c, 7.0));
                self.label(name, name, "point", c);
            }
            Item::Spring { a, b } => {
                let (a, b) = (self.p(*a), self.p(*b));
                self.spring(a, b);
            }
            Item::Coil { at, radius, .. } => self.coil(*at, *radius),
            Item::Damper { a, b } => {
                let (a, b) = (self.p(*a), self.p(*b));
                self.damper(a, b);
            }
            Item::Arrow { kind, from, to } => self.arrow(kind, *from, *to),
            Item::Arc { kind, points } => self.arc(kind, points),
            Item::Reference { a, b } => {
                let (a, b) = (self.p(*a), self.p(*b));
                self.line(a, b, &format!(r#"class="reference" stroke="{AXIS}" stroke-width="1" stroke-dasharray="5 4""#), 0.5);
            }
            Item::Point { name, at } => {
                let c = self.p(*at);
                let id = self.id(format!("point-{name}"));
                self.circle(c, 2.0, &format!(r#"id="{id}" class="point" fill="{INK}""#));
                self.obstacles.push(Obstacle::Circle(c, 3.0));
                self.label(name, name, "point", c);
            }
            Item::Gravity { .. } => {}
        }
    }

    fn disk(&mut self, name: &str, centre: P3, normal: P3, radius: f64, marker: P3) {
        let c = self.p(centre);
        let id = self.id(format!("body-{name}"));
        let facing = self.view.planar
            || norm(crate::sample::cross(
                normal,
                crate::sample::cross(self.view.u, self.view.v),
            )) < 1e-9;
        let attrs =
            format!(r##"id="{id}" class="disk" fill="#e8eef6" stroke="{INK}" stroke-width="2""##);
        if facing {
            let r = radius * self.view.scale;
            self.circle(c, r, &attrs);
            self.ring(c, r);
        } else {
            let start = sub(marker, centre);
            let points: Vec<Pt> = (0..48)
                .map(|k| {
                    let t = std::f64::consts::TAU * f64::from(k) / 48.0;
                    self.p(add(centre, crate::sample::rotate(start, normal, t)))
                })
                .collect();
            self.polygon(&points, &attrs);
        }
        let m = self.p(marker);
        self.line(
            c,
            m,
            &format!(r#"class="radius" stroke="{INK}" stroke-width="1.5""#),
            1.0,
        );
        let r = radius * self.view.scale;
        self.label(name, name, "body", (c.0 + 0.7 * r, c.1 - 0.7 * r));
    }

    /// A circle's rim as an obstacle (labels may sit inside a disk, clear of its rim).
    fn ring(&mut self, c: Pt, r: f64) {
        let ring: Vec<Pt> = (0..=32)
            .map(|k| {
                let t = std::f64::consts::TAU * f64::from(k) / 32.0;
                (c.0 + r * t.cos(), c.1 + r * t.sin())
            })
            .collect();
        for pair in ring.windows(2) {
            self.obstacles
                .push(Obstacle::Segment(pair[0], pair[1], 1.0));
        }
    }

    fn block(&mut self, name: &str, centre: P3, along: P3, size: f64) {
        let c = self.p(centre);
        let d = self.view.direction(along);
        let len = (d.0 * d.0 + d.1 * d.1).sqrt();
        let (ux, uy) = if len > 1e-9 {
            (d.0 / len, d.1 / len)
        } else {
            (1.0, 0.0)
        };
        let (vx, vy) = (-uy, ux);
        let h = 0.5 * size * self.view.scale;
        let corners: Vec<Pt> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .map(|(a, b)| (c.0 + h * (a * ux + b * vx), c.1 + h * (a * uy + b * vy)))
            .collect();
        let id = self.id(format!("block-{name}"));
        self.polygon(
            &corners,
            &format!(r##"id="{id}" class="block" fill="#f3efe6" stroke="{INK}" stroke-width="2""##),
        );
        self.obstacles.push(Obstacle::Circle(c, 0.9 * h));
        let id = self.id(format!("point-{name}"));
        self.circle(c, 2.5, &format!(r#"id="{id}" class="point" fill="{INK}""#));
        self.label(name, name, "point", c);
    }

    fn hatch(&mut self, a: Pt, b: Pt, side: Pt) {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = (dx * dx + dy * dy).sqrt();
        if len < 1e-9 {
            return;
        }
        let (ux, uy) = (dx / len, dy / len);
        // Counted from the length to a hundredth of a pixel: equal lengths in two frames of an
        // animation give equal counts despite rounding.
        let n = ((len * 100.0).round() / 800.0).floor() as usize;
        let mut d = String::new();
        let mut runs = Vec::with_capacity(n + 1);
        for k in 0..=n {
            let s = k as f64 * len / n.max(1) as f64;
            let p = (a.0 + ux * s, a.1 + uy * s);
            let q = (p.0 + 7.0 * side.0 - 5.0 * ux, p.1 + 7.0 * side.1 - 5.0 * uy);
            let _ = write!(d, "M{} {}L{} {}", f(p.0), f(p.1), f(q.0), f(q.1));
            runs.push(vec![p, q]);
        }
        self.shape(|| Shape::Path {
            runs,
            closed: false,
            paint: Paint::from_attributes(&format!(r#"stroke="{INK}" stroke-width="1""#), false),
        });
        let _ = writeln!(
            self.body,
            r#"<path d="{d}" class="hatch" stroke="{INK}" stroke-width="1"/>"#
        );
        let shift = |p: Pt| (p.0 + 4.0 * side.0, p.1 + 4.0 * side.1);
        self.obstacles
            .push(Obstacle::Segment(shift(a), shift(b), 4.5));
    }

    fn page_unit(&self, d: P3) -> Pt {
        let (x, y) = self.view.direction(d);
        let len = (x * x + y * y).sqrt();
        if len > 1e-9 {
            (x / len, y / len)
        } else {
            (0.0, 1.0)
        }
    }

    fn track(&mut self, a: P3, b: P3, side: P3) {
        let (a, b) = (self.p(a), self.p(b));
        let s = self.page_unit(side);
        self.line(
            a,
            b,
            &format!(r#"class="ground" stroke="{INK}" stroke-width="1.5""#),
            1.0,
        );
        self.hatch(a, b, s);
    }

    fn support(&mut self, at: P3, down: P3) {
        let c = self.p(at);
        let d = self.page_unit(down);
        let n = (-d.1, d.0);
        let base = (c.0 + 16.0 * d.0, c.1 + 16.0 * d.1);
        let l = (base.0 - 10.0 * n.0, base.1 - 10.0 * n.1);
        let r = (base.0 + 10.0 * n.0, base.1 + 10.0 * n.1);
        self.polygon(
            &[c, l, r],
            &format!(r#"class="support" fill="white" stroke="{INK}" stroke-width="1.5""#),
        );
        let gl = (base.0 - 16.0 * n.0, base.1 - 16.0 * n.1);
        let gr = (base.0 + 16.0 * n.0, base.1 + 16.0 * n.1);
        self.line(
            gl,
            gr,
            &format!(r#"class="ground" stroke="{INK}" stroke-width="1.5""#),
            1.0,
        );
        self.hatch(gl, gr, d);
    }

    fn wall(&mut self, at: P3, normal: P3) {
        let c = self.p(at);
        let d = self.page_unit(normal);
        let t = (-d.1, d.0);
        let half = (0.8 * self.size * 0.12 * self.view.scale).clamp(12.0, 40.0);
        let a = (c.0 - half * t.0, c.1 - half * t.1);
        let b = (c.0 + half * t.0, c.1 + half * t.1);
        self.line(
            a,
            b,
            &format!(r#"class="ground" stroke="{INK}" stroke-width="1.5""#),
            1.0,
        );
        self.hatch(a, b, (-d.0, -d.1));
    }

    fn spring(&mut self, a: Pt, b: Pt) {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = (dx * dx + dy * dy).sqrt();
        if len < 1e-9 {
            return;
        }
        let (ux, uy) = (dx / len, dy / len);
        let (nx, ny) = (-uy, ux);
        let lead = 0.15 * len;
        let zigs = 10;
        let amplitude = (0.12 * len).clamp(3.0, 7.0);
        let mut points = vec![a, (a.0 + lead * ux, a.1 + lead * uy)];
        for k in 0..zigs {
            let s = lead + (len - 2.0 * lead) * (k as f64 + 0.5) / zigs as f64;
            let side = if k % 2 == 0 { amplitude } else { -amplitude };
            points.push((a.0 + s * ux + side * nx, a.1 + s * uy + side * ny));
        }
        points.push((b.0 - lead * ux, b.1 - lead * uy));
        points.push(b);
        self.polyline(
            &points,
            &format!(r#"class="spring" stroke="{INK}" stroke-width="1.5""#),
            amplitude,
        );
    }

    fn coil(&mut self, at: P3, radius: f64) {
        let c = self.p(at);
        let r = (radius * self.view.scale).max(10.0);
        let turns = 2.5;
        let points: Vec<Pt> = (0..=60)
            .map(|k| {
                let s = f64::from(k) / 60.0;
                let t = std::f64::consts::TAU * turns * s;
                let rr = r * (0.3 + 0.7 * s);
                (c.0 + rr * t.cos(), c.1 + rr * t.sin())
            })
            .collect();
        self.polyline(
            &points,
            &format!(r#"class="coil" stroke="{INK}" stroke-width="1.2""#),
            1.0,
        );
    }

    fn damper(&mut self, a: Pt, b: Pt) {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = (dx * dx + dy * dy).sqrt();
        if len < 1e-9 {
            return;
        }
        let (ux, uy) = (dx / len, dy / len);
        let (nx, ny) = (-uy, ux);
        let at = |s: f64, o: f64| (a.0 + s * ux + o * nx, a.1 + s * uy + o * ny);
        let w = 6.0;
        let (c0, c1) = (0.35 * len, 0.7 * len);
        let style = format!(r#"class="damper" stroke="{INK}" stroke-width="1.5""#);
        self.line(a, at(c0, 0.0), &style, 1.0);
        self.polyline(&[at(c1, -w), at(c0, -w), at(c0, w), at(c1, w)], &style, 1.0);
        self.line(
            at(0.55 * len, -0.7 * w),
            at(0.55 * len, 0.7 * w),
            &style,
            1.0,
        );
        self.line(at(0.55 * len, 0.0), b, &style, 1.0);
    }

    /// An arrowhead at `tip` coming from `from`; when they coincide (an angle at zero) it
    /// shrinks to the tip but is still written, so that an animation's frames share markup.
    fn head(&mut self, tip: Pt, from: Pt, colour: &str) {
        let (dx, dy) = (tip.0 - from.0, tip.1 - from.1);
        let len = (dx * dx + dy * dy).sqrt();
        let (ux, uy) = if len < 1e-9 {
            (0.0, 0.0)
        } else {
            (dx / len, dy / len)
        };
        let back = (tip.0 - 10.0 * ux, tip.1 - 10.0 * uy);
        let l = (back.0 - 4.0 * uy, back.1 + 4.0 * ux);
        let r = (back.0 + 4.0 * uy, back.1 - 4.0 * ux);
        let _ = writeln!(
            self.body,
            r#"<polygon points="{} {} {} {} {} {}" fill="{colour}"/>"#,
            f(tip.0),
            f(tip.1),
            f(l.0),
            f(l.1),
            f(r.0),
            f(r.1)
        );
        self.shape(|| Shape::Path {
            runs: vec![vec![tip, l, r]],
            closed: true,
            paint: Paint::from_attributes(&format!(r#"fill="{colour}""#), true),
        });
        self.obstacles.push(Obstacle::Segment(back, tip, 4.0));
    }

    fn arrow(&mut self, kind: &ArrowKind, from: P3, to: P3) {
        let (a, b) = (self.p(from), self.p(to));
        let (text, colour, class, id, anchor) = match kind {
            ArrowKind::Force(t) => (t.as_str(), FORCE, "force", "force", b),
            ArrowKind::Coordinate(t) => (
                t.as_str(),
                COORDINATE,
                "coordinate",
                "coordinate",
                mid(a, b),
            ),
            ArrowKind::Axis(t) => (t.as_str(), AXIS, "axis", "axis", b),
        };
        self.line(
            a,
            b,
            &format!(r#"class="{class}" stroke="{colour}" stroke-width="1.8""#),
            1.5,
        );
        self.head(b, a, colour);
        self.label(&format!("{id}-{text}"), text, class, anchor);
    }

    fn arc(&mut self, kind: &ArcKind, points: &[P3]) {
        let page: Vec<Pt> = points.iter().map(|p| self.p(*p)).collect();
        let (text, colour, class, id) = match kind {
            ArcKind::Coordinate(t) => (t.as_str(), COORDINATE, "coordinate", "coordinate"),
            ArcKind::Couple(t) => (t.as_str(), FORCE, "force", "couple"),
        };
        if page.len() >= 2 {
            self.polyline(
                &page,
                &format!(r#"class="{class}" stroke="{colour}" stroke-width="1.5""#),
                1.0,
            );
            let n = page.len();
            let back = page[n.saturating_sub(3)];
            self.head(page[n - 1], back, colour);
        }
        let anchor = page.get(page.len() / 2).copied().unwrap_or((0.0, 0.0));
        self.label(&format!("{id}-{text}"), text, class, anchor);
    }

    /// Gravity: an arrow beside the drawing, at its upper right.
    fn gravity(&mut self, scene: &Scene) {
        for item in &scene.items {
            let Item::Gravity { direction, label } = item else {
                continue;
            };
            let d = self.page_unit(*direction);
            let right = self
                .obstacles
                .iter()
                .map(|o| match *o {
                    Obstacle::Segment(a, b, h) => a.0.max(b.0) + h,
                    Obstacle::Circle(c, r) => c.0 + r,
                })
                .fold(f64::NEG_INFINITY, f64::max);
            let top = self
                .obstacles
                .iter()
                .map(|o| match *o {
                    Obstacle::Segment(a, b, h) => a.1.min(b.1) - h,
                    Obstacle::Circle(c, r) => c.1 - r,
                })
                .fold(f64::INFINITY, f64::min);
            let (right, top) = if right.is_finite() {
                (right, top)
            } else {
                (0.0, 0.0)
            };
            let centre = (right + 40.0, top + 30.0);
            let a = (centre.0 - 20.0 * d.0, centre.1 - 20.0 * d.1);
            let b = (centre.0 + 20.0 * d.0, centre.1 + 20.0 * d.1);
            self.line(
                a,
                b,
                &format!(r#"id="gravity" class="gravity" stroke="{INK}" stroke-width="1.8""#),
                1.5,
            );
            self.head(b, a, INK);
            self.label("gravity", label, "gravity", centre);
        }
    }
}

fn mid(a: Pt, b: Pt) -> Pt {
    (0.5 * (a.0 + b.0), 0.5 * (a.1 + b.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What `format!` writes, `-0.00` as `0.00`: the definition [`Number`] must follow.
    fn reference(x: f64) -> String {
        let s = format!("{x:.2}");
        if s == "-0.00" {
            "0.00".to_owned()
        } else {
            s
        }
    }

    #[test]
    fn numbers_are_written_as_format_writes_them() {
        // Halves of a cent that are and are not exact in binary, numbers next to them, zeros
        // of both signs, large and odd values, and a dense irregular sweep.
        let mut values = vec![
            0.0,
            -0.0,
            0.005,
            -0.005,
            0.125,
            -0.125,
            0.375,
            2.675,
            1.005,
            1.015,
            1e6,
            1e9,
            123_456.785,
            -999_999.995,
            0.004_999_999,
            f64::NAN,
            f64::INFINITY,
        ];
        for &x in &values.clone() {
            values.push(f64::from_bits(x.to_bits() + 1));
            values.push(f64::from_bits(x.to_bits().saturating_sub(1)));
        }
        let mut x = -700.0;
        while x < 700.0 {
            values.push(x);
            x += 0.000_731_7;
        }
        for k in 0..200_000 {
            values.push(f64::from(k) / 200.0 - 500.0);
            values.push(f64::from(k) / 100.0);
        }
        for x in values {
            assert_eq!(Number(x).to_string(), reference(x), "{x:e}");
        }
    }
}
