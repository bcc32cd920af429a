//! A figure as a PNG image, for documents that cannot include SVG (`pdflatex`). The SVG
//! writer keeps, beside its text, the list of what it drew ([`Shape`]: strokes, fills,
//! circles, labels, in page pixels); this module paints that list with `tiny-skia`
//! (anti-aliased strokes and fills) and the labels with the bundled DejaVu Sans through
//! `ab_glyph`, so the picture is the SVG's, drawn by the same code, at any resolution.

use ab_glyph::{Font, FontRef, OutlineCurve, PxScale, ScaleFont};
use tiny_skia::{
    FillRule, LineCap, Paint as SkiaPaint, PathBuilder, Pixmap, Stroke, StrokeDash, Transform,
};

use crate::svg::Pt;

/// The face the labels are painted in (the SVG asks for DejaVu Sans first): the plots' copy,
/// bundled in `report` with its licence, so the workspace holds the file once.
static FONT: &[u8] = include_bytes!("../../report/assets/fonts/DejaVuSans.ttf");

/// One drawn thing, in page pixels, as the SVG writer wrote it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Shape {
    /// A polyline (closed: a polygon), stroked and/or filled.
    Path {
        /// Its points, or several runs of points (a hatch is many strokes).
        runs: Vec<Vec<Pt>>,
        /// Whether each run is closed.
        closed: bool,
        /// How it is painted.
        paint: Paint,
    },
    /// A circle.
    Circle {
        /// Its centre.
        centre: Pt,
        /// Its radius.
        radius: f64,
        /// How it is painted.
        paint: Paint,
    },
    /// A label: centred on `x`, its baseline at `y`.
    Text {
        /// Where.
        at: Pt,
        /// What.
        text: String,
        /// Its colour.
        colour: Colour,
        /// Slanted, as the SVG's italic (the bundled face has no italic: the upright glyphs'
        /// outlines are sheared, as a browser does for a face without one).
        oblique: bool,
    },
}

/// An RGB colour.
pub(crate) type Colour = [u8; 3];

/// How a path or circle is painted, read off the SVG attributes it was written with.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Paint {
    stroke: Option<Colour>,
    width: f64,
    fill: Option<Colour>,
    dash: Option<Vec<f64>>,
    round: bool,
}

impl Paint {
    /// The paint an SVG element with these attributes gets (`fill` black unless given, as in
    /// SVG; `none` for nothing).
    pub(crate) fn from_attributes(attributes: &str, filled_by_default: bool) -> Paint {
        let value = |key: &str| -> Option<&str> {
            let from = attributes
                .find(&format!(" {key}=\""))
                .map(|i| i + key.len() + 3)
                .or_else(|| {
                    attributes
                        .starts_with(&format!("{key}=\""))
                        .then_some(key.len() + 2)
                })?;
            let rest = &attributes[from..];
            Some(&rest[..rest.find('"')?])
        };
        let fill = match value("fill") {
            Some(v) => colour(v),
            None if filled_by_default => Some([0, 0, 0]),
            None => None,
        };
        Paint {
            stroke: value("stroke").and_then(colour),
            width: value("stroke-width")
                .and_then(|w| w.parse().ok())
                .unwrap_or(1.0),
            fill,
            dash: value("stroke-dasharray").map(|d| {
                d.split_whitespace()
                    .filter_map(|x| x.parse().ok())
                    .collect()
            }),
            round: value("stroke-linecap") == Some("round"),
        }
    }
}

/// `#rgb`, `#rrggbb` or `white`; `None` for `none` or anything else.
pub(crate) fn colour(text: &str) -> Option<Colour> {
    let hex = text.strip_prefix('#');
    match (text, hex.map(str::len)) {
        ("white", _) => Some([255, 255, 255]),
        (_, Some(3)) => {
            let digits: Vec<u8> = hex?
                .chars()
                .map(|c| c.to_digit(16).map(|d| (d * 17) as u8))
                .collect::<Option<_>>()?;
            Some([digits[0], digits[1], digits[2]])
        }
        (_, Some(6)) => {
            let h = hex?;
            let byte = |i: usize| u8::from_str_radix(h.get(i..i + 2)?, 16).ok();
            Some([byte(0)?, byte(2)?, byte(4)?])
        }
        _ => None,
    }
}

/// Why a PNG could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RasterError {
    /// The picture at this resolution is empty or larger than a raster can be.
    #[error("a picture of {width} × {height} pixels cannot be made")]
    Size {
        /// Pixels across.
        width: f64,
        /// Pixels down.
        height: f64,
    },
    /// The PNG encoder failed.
    #[error("the PNG could not be encoded: {0}")]
    Encode(String),
}

/// The largest side of a raster, in pixels.
const LARGEST: f64 = 16_384.0;

/// Paints `shapes` on white, the page box `(lo, hi)` at `scale` pixels per page pixel, as PNG.
pub(crate) fn png(
    shapes: &[Shape],
    (lo, hi): (Pt, Pt),
    scale: f64,
) -> Result<Vec<u8>, RasterError> {
    let (width, height) = ((hi.0 - lo.0) * scale, (hi.1 - lo.1) * scale);
    let size_error = RasterError::Size { width, height };
    if !(width >= 1.0 && height >= 1.0 && width <= LARGEST && height <= LARGEST) {
        return Err(size_error);
    }
    // Within 1..=LARGEST, checked above.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let mut pixmap = Pixmap::new(width.ceil() as u32, height.ceil() as u32).ok_or(size_error)?;
    pixmap.fill(tiny_skia::Color::WHITE);
    let transform = Transform::from_row(
        scale as f32,
        0.0,
        0.0,
        scale as f32,
        (-lo.0 * scale) as f32,
        (-lo.1 * scale) as f32,
    );
    let font = FontRef::try_from_slice(FONT).map_err(|e| RasterError::Encode(e.to_string()))?;
    for shape in shapes {
        match shape {
            Shape::Path {
                runs,
                closed,
                paint,
            } => {
                let mut builder = PathBuilder::new();
                for run in runs {
                    trace(&mut builder, run, *closed);
                }
                if let Some(path) = builder.finish() {
                    draw(&mut pixmap, &path, paint, transform);
                }
            }
            Shape::Circle {
                centre,
                radius,
                paint,
            } => {
                if let Some(path) =
                    PathBuilder::from_circle(centre.0 as f32, centre.1 as f32, *radius as f32)
                {
                    draw(&mut pixmap, &path, paint, transform);
                }
            }
            Shape::Text {
                at,
                text,
                colour,
                oblique,
            } => {
                let at = ((at.0 - lo.0) * scale, (at.1 - lo.1) * scale);
                if *oblique {
                    slanted(&mut pixmap, &font, at, text, *colour, 14.0 * scale);
                } else {
                    label(&mut pixmap, &font, at, text, *colour, 14.0 * scale);
                }
            }
        }
    }
    pixmap
        .encode_png()
        .map_err(|e| RasterError::Encode(e.to_string()))
}

fn trace(builder: &mut PathBuilder, run: &[Pt], closed: bool) {
    for (k, p) in run.iter().enumerate() {
        if k == 0 {
            builder.move_to(p.0 as f32, p.1 as f32);
        } else {
            builder.line_to(p.0 as f32, p.1 as f32);
        }
    }
    if closed {
        builder.close();
    }
}

fn draw(pixmap: &mut Pixmap, path: &tiny_skia::Path, paint: &Paint, transform: Transform) {
    let solid = |c: Colour| {
        let mut p = SkiaPaint::default();
        p.set_color_rgba8(c[0], c[1], c[2], 255);
        p.anti_alias = true;
        p
    };
    if let Some(fill) = paint.fill {
        pixmap.fill_path(path, &solid(fill), FillRule::Winding, transform, None);
    }
    if let Some(colour) = paint.stroke {
        let stroke = Stroke {
            width: paint.width as f32,
            line_cap: if paint.round {
                LineCap::Round
            } else {
                LineCap::Butt
            },
            dash: paint
                .dash
                .as_ref()
                .and_then(|d| StrokeDash::new(d.iter().map(|x| *x as f32).collect(), 0.0)),
            ..Stroke::default()
        };
        pixmap.stroke_path(path, &solid(colour), &stroke, transform, None);
    }
}

/// The shear of the slanted labels: x moves right by this much per unit of height, about
/// 11°, the slant of DejaVu Sans Oblique (which a browser uses for the SVG's italic when it
/// has it).
const SLANT: f32 = 0.2;

/// Each glyph of `text` in the face at `scaled`, with its pen position from the left (kerning
/// included), and the whole advance.
fn glyphs<F: Font, S: ScaleFont<F>>(
    scaled: &S,
    text: &str,
) -> (Vec<(ab_glyph::GlyphId, f32)>, f32) {
    let mut advance = 0.0f32;
    let mut glyphs = Vec::with_capacity(text.len());
    let mut previous = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = previous {
            advance += scaled.kern(p, id);
        }
        glyphs.push((id, advance));
        advance += scaled.h_advance(id);
        previous = Some(id);
    }
    (glyphs, advance)
}

/// Paints `text` as [`label`] does, its glyphs' outlines sheared by [`SLANT`] about the
/// baseline and filled anti-aliased (non-zero winding, as TrueType outlines are drawn).
fn slanted(pixmap: &mut Pixmap, font: &FontRef<'_>, at: Pt, text: &str, colour: Colour, size: f64) {
    let scaled = font.as_scaled(PxScale::from(size as f32));
    let (glyphs, advance) = glyphs(&scaled, text);
    let (h, v) = (scaled.h_scale_factor(), scaled.v_scale_factor());
    let (left, baseline) = (at.0 as f32 - advance / 2.0, at.1 as f32);
    let mut builder = PathBuilder::new();
    for (id, x) in glyphs {
        let Some(outline) = font.outline(id) else {
            continue;
        };
        // Font units, y up, to page pixels, y down, sheared to the right with height.
        let page = |p: ab_glyph::Point| (left + x + h * p.x + SLANT * v * p.y, baseline - v * p.y);
        let mut end: Option<ab_glyph::Point> = None;
        for curve in &outline.curves {
            let (first, last) = match curve {
                OutlineCurve::Line(a, b)
                | OutlineCurve::Quad(a, _, b)
                | OutlineCurve::Cubic(a, _, _, b) => (*a, *b),
            };
            if end != Some(first) {
                if end.is_some() {
                    builder.close();
                }
                let (x0, y0) = page(first);
                builder.move_to(x0, y0);
            }
            match curve {
                OutlineCurve::Line(_, b) => {
                    let (x1, y1) = page(*b);
                    builder.line_to(x1, y1);
                }
                OutlineCurve::Quad(_, c, b) => {
                    let ((cx, cy), (x1, y1)) = (page(*c), page(*b));
                    builder.quad_to(cx, cy, x1, y1);
                }
                OutlineCurve::Cubic(_, c, d, b) => {
                    let ((cx, cy), (dx, dy), (x1, y1)) = (page(*c), page(*d), page(*b));
                    builder.cubic_to(cx, cy, dx, dy, x1, y1);
                }
            }
            end = Some(last);
        }
        if end.is_some() {
            builder.close();
        }
    }
    if let Some(path) = builder.finish() {
        let mut paint = SkiaPaint::default();
        paint.set_color_rgba8(colour[0], colour[1], colour[2], 255);
        paint.anti_alias = true;
        pixmap.fill_path(
            &path,
            &paint,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
    }
}

/// Paints `text` centred on `at.0` with its baseline at `at.1`, blending each glyph's coverage.
fn label(pixmap: &mut Pixmap, font: &FontRef<'_>, at: Pt, text: &str, colour: Colour, size: f64) {
    let scaled = font.as_scaled(PxScale::from(size as f32));
    let (glyphs, advance) = glyphs(&scaled, text);
    let left = at.0 as f32 - advance / 2.0;
    let (width, height) = (pixmap.width(), pixmap.height());
    let data = pixmap.data_mut();
    for (id, x) in glyphs {
        let glyph =
            id.with_scale_and_position(scaled.scale(), ab_glyph::point(left + x, at.1 as f32));
        let Some(outlined) = font.outline_glyph(glyph) else {
            continue;
        };
        let bounds = outlined.px_bounds();
        outlined.draw(|gx, gy, coverage| {
            let px = bounds.min.x as i64 + i64::from(gx);
            let py = bounds.min.y as i64 + i64::from(gy);
            if px < 0 || py < 0 || px >= i64::from(width) || py >= i64::from(height) {
                return;
            }
            // In bounds, checked above.
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let i = 4 * (py as usize * width as usize + px as usize);
            let a = coverage.clamp(0.0, 1.0);
            for (channel, ink) in colour.iter().enumerate() {
                let old = f32::from(data[i + channel]);
                data[i + channel] = (old + (f32::from(*ink) - old) * a).round() as u8;
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ink's mean x in the rows `rows` of a pixmap painted black on white.
    fn ink_x(pixmap: &Pixmap, rows: std::ops::Range<u32>) -> f64 {
        let (mut sum, mut weight) = (0.0, 0.0);
        for y in rows {
            for x in 0..pixmap.width() {
                let i = 4 * (y * pixmap.width() + x) as usize;
                let ink = 1.0 - f64::from(pixmap.data()[i]) / 255.0;
                sum += ink * f64::from(x);
                weight += ink;
            }
        }
        assert!(weight > 1.0, "ink in the rows");
        sum / weight
    }

    #[test]
    fn a_slanted_label_leans_right_by_its_slant() {
        // An `l` is a vertical bar from the baseline (y = 60) up about 0.76 em (53 px at
        // 70 px): upright its ink is straight, slanted its top is further right than its
        // bottom by the slant times the height between them.
        let font = FontRef::try_from_slice(FONT).expect("the bundled face");
        let paint = |slant: bool| {
            let mut pixmap = Pixmap::new(80, 80).expect("a pixmap");
            pixmap.fill(tiny_skia::Color::WHITE);
            if slant {
                slanted(&mut pixmap, &font, (40.0, 60.0), "l", [0, 0, 0], 70.0);
            } else {
                label(&mut pixmap, &font, (40.0, 60.0), "l", [0, 0, 0], 70.0);
            }
            pixmap
        };
        let upright = paint(false);
        let lean = ink_x(&upright, 15..20) - ink_x(&upright, 52..57);
        assert!(lean.abs() < 0.5, "upright: {lean}");
        let slanted = paint(true);
        let lean = ink_x(&slanted, 15..20) - ink_x(&slanted, 52..57);
        let expected = f64::from(SLANT) * 37.0;
        assert!(
            (lean - expected).abs() < 1.0,
            "slanted: {lean} against {expected}"
        );
    }

    #[test]
    fn attributes_are_read_as_the_svg_writes_them() {
        let p = Paint::from_attributes(
            r##"class="rod" stroke="#222" stroke-width="4" stroke-linecap="round""##,
            false,
        );
        assert_eq!(p.stroke, Some([0x22, 0x22, 0x22]));
        assert_eq!((p.width, p.fill, p.round), (4.0, None, true));
        let p = Paint::from_attributes(r##"fill="white" stroke="#b03a2e""##, true);
        assert_eq!(p.fill, Some([255, 255, 255]));
        assert_eq!(p.stroke, Some([0xb0, 0x3a, 0x2e]));
        let p = Paint::from_attributes(r#"stroke-dasharray="5 4""#, true);
        assert_eq!((p.fill, p.dash), (Some([0, 0, 0]), Some(vec![5.0, 4.0])));
    }
}
