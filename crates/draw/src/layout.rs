//! Placing labels: greedily, in order of importance, each at the first of a fixed list of
//! candidate positions around its anchor (nearest first) whose box meets no label placed
//! before it and no part of the drawing; when every candidate touches the drawing, the one
//! touching least. Labels never overlap each other: past the candidates, a label goes to a
//! free row below the drawing.

/// A rectangle on the page: left, top, width, height (pixels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Left.
    pub x: f64,
    /// Top.
    pub y: f64,
    /// Width.
    pub w: f64,
    /// Height.
    pub h: f64,
}

impl Rect {
    /// Whether the two rectangles share interior points.
    #[must_use]
    pub fn overlaps(&self, other: &Rect) -> bool {
        self.x < other.x + other.w
            && other.x < self.x + self.w
            && self.y < other.y + other.h
            && other.y < self.y + self.h
    }

    fn grown(&self, by: f64) -> Rect {
        Rect {
            x: self.x - by,
            y: self.y - by,
            w: self.w + 2.0 * by,
            h: self.h + 2.0 * by,
        }
    }

    fn contains(&self, (px, py): (f64, f64)) -> bool {
        px >= self.x && px <= self.x + self.w && py >= self.y && py <= self.y + self.h
    }
}

/// Something drawn that labels should keep clear of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Obstacle {
    /// A stroke from one point to another, with its half width.
    Segment((f64, f64), (f64, f64), f64),
    /// A filled disk: centre and radius.
    Circle((f64, f64), f64),
}

impl Obstacle {
    /// Whether the obstacle touches `r`.
    #[must_use]
    pub fn meets(&self, r: &Rect) -> bool {
        match *self {
            Obstacle::Circle((cx, cy), radius) => {
                let dx = cx - cx.clamp(r.x, r.x + r.w);
                let dy = cy - cy.clamp(r.y, r.y + r.h);
                dx * dx + dy * dy < radius * radius
            }
            Obstacle::Segment(a, b, half) => segment_meets(a, b, &r.grown(half)),
        }
    }

    /// The obstacle's bounding box, its stroke's half width included: an obstacle meets no
    /// rectangle its box does not reach.
    fn bounds(&self) -> ((f64, f64), (f64, f64)) {
        match *self {
            Obstacle::Circle((cx, cy), radius) => {
                ((cx - radius, cy - radius), (cx + radius, cy + radius))
            }
            Obstacle::Segment(a, b, half) => (
                (a.0.min(b.0) - half, a.1.min(b.1) - half),
                (a.0.max(b.0) + half, a.1.max(b.1) + half),
            ),
        }
    }
}

/// Whether the box `(lo, hi)` reaches `r` (edges included).
fn reaches((lo, hi): ((f64, f64), (f64, f64)), r: &Rect) -> bool {
    lo.0 <= r.x + r.w && r.x <= hi.0 && lo.1 <= r.y + r.h && r.y <= hi.1
}

/// Whether segment `a`–`b` meets rectangle `r` (Liang–Barsky clipping).
fn segment_meets(a: (f64, f64), b: (f64, f64), r: &Rect) -> bool {
    if r.contains(a) || r.contains(b) {
        return true;
    }
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [
        (-dx, a.0 - r.x),
        (dx, r.x + r.w - a.0),
        (-dy, a.1 - r.y),
        (dy, r.y + r.h - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    t0 <= t1
}

/// A label to place: its text's size and the point it belongs to.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    /// Width and height of its box.
    pub size: (f64, f64),
    /// The point it labels.
    pub anchor: (f64, f64),
}

/// Places every request; returns one box per request, in order.
#[must_use]
pub fn place(requests: &[Request], obstacles: &[Obstacle]) -> Vec<Rect> {
    let mut placed: Vec<Rect> = Vec::with_capacity(requests.len());
    let directions = directions();
    let bottom = obstacles
        .iter()
        .map(|o| match *o {
            Obstacle::Segment(a, b, h) => a.1.max(b.1) + h,
            Obstacle::Circle(c, r) => c.1 + r,
        })
        .fold(0.0, f64::max);
    let mut grid = Grid::new(obstacles);
    for request in requests {
        // The first candidate touching fewest obstacles; a clear one ends the search.
        let mut best: Option<(usize, Rect)> = None;
        for r in candidates(request, &directions).filter(|r| !placed.iter().any(|p| p.overlaps(r)))
        {
            // Counted only as far as the fewest so far: a candidate that reaches it is not
            // taken, so the rest of its count would change nothing.
            let enough = best.map_or(usize::MAX, |(fewest, _)| fewest);
            let hits = grid.hits(&r, enough);
            if best.is_none_or(|(fewest, _)| hits < fewest) {
                best = Some((hits, r));
            }
            if hits == 0 {
                break;
            }
        }
        let rect = match best {
            Some((_, r)) => r,
            None => free_row(request, &placed, bottom),
        };
        placed.push(rect);
    }
    placed
}

/// The obstacles sorted into square cells of the page by their bounding boxes, so that a
/// candidate box is tested only against the obstacles in the cells it covers (a drawing has
/// hundreds of strokes; a label's box is near a few).
struct Grid<'o> {
    obstacles: &'o [Obstacle],
    bounds: Vec<((f64, f64), (f64, f64))>,
    /// The page position of the first cell's corner, and a cell's side.
    origin: (f64, f64),
    side: f64,
    columns: usize,
    rows: usize,
    /// The obstacles (indices) whose box reaches each cell, row by row.
    cells: Vec<Vec<usize>>,
    /// Obstacles without a finite box (tested against every candidate).
    loose: Vec<usize>,
    /// The query that last counted each obstacle, so that one met in several cells counts
    /// once.
    seen: Vec<u32>,
    query: u32,
}

impl<'o> Grid<'o> {
    /// Cells of at least 24 pixels, at most 128 a side.
    fn new(obstacles: &'o [Obstacle]) -> Grid<'o> {
        let bounds: Vec<_> = obstacles.iter().map(Obstacle::bounds).collect();
        let finite = |b: &((f64, f64), (f64, f64))| {
            [b.0 .0, b.0 .1, b.1 .0, b.1 .1]
                .iter()
                .all(|x| x.is_finite())
        };
        let (mut lo, mut hi) = (
            (f64::INFINITY, f64::INFINITY),
            (f64::NEG_INFINITY, f64::NEG_INFINITY),
        );
        for b in bounds.iter().filter(|b| finite(b)) {
            lo = (lo.0.min(b.0 .0), lo.1.min(b.0 .1));
            hi = (hi.0.max(b.1 .0), hi.1.max(b.1 .1));
        }
        let extent = if lo.0.is_finite() {
            (hi.0 - lo.0).max(hi.1 - lo.1)
        } else {
            0.0
        };
        let side = (extent / 128.0).max(24.0);
        let origin = if lo.0.is_finite() { lo } else { (0.0, 0.0) };
        let count = |span: f64| cell(span, side) + 1;
        let (columns, rows) = if lo.0.is_finite() {
            (count(hi.0 - lo.0), count(hi.1 - lo.1))
        } else {
            (1, 1)
        };
        let mut grid = Grid {
            obstacles,
            bounds,
            origin,
            side,
            columns,
            rows,
            cells: vec![Vec::new(); columns * rows],
            loose: Vec::new(),
            seen: vec![0; obstacles.len()],
            query: 0,
        };
        for i in 0..obstacles.len() {
            let b = grid.bounds[i];
            if finite(&b) {
                let ((c0, c1), (r0, r1)) = grid.span(b.0, b.1);
                for row in r0..=r1 {
                    for column in c0..=c1 {
                        grid.cells[row * grid.columns + column].push(i);
                    }
                }
            } else {
                grid.loose.push(i);
            }
        }
        grid
    }

    /// The columns and rows (first and last) that the box `lo`–`hi` covers, clamped to the
    /// grid.
    fn span(&self, lo: (f64, f64), hi: (f64, f64)) -> ((usize, usize), (usize, usize)) {
        let at = |x: f64, o: f64, n: usize| cell(x - o, self.side).min(n - 1);
        (
            (
                at(lo.0, self.origin.0, self.columns),
                at(hi.0, self.origin.0, self.columns),
            ),
            (
                at(lo.1, self.origin.1, self.rows),
                at(hi.1, self.origin.1, self.rows),
            ),
        )
    }

    /// How many obstacles touch `r`, counted up to `enough`.
    fn hits(&mut self, r: &Rect, enough: usize) -> usize {
        self.query = self.query.wrapping_add(1);
        if self.query == 0 {
            self.seen.fill(0);
            self.query = 1;
        }
        let mut hits = 0;
        let touches =
            |grid: &Grid<'_>, i: usize| reaches(grid.bounds[i], r) && grid.obstacles[i].meets(r);
        for k in 0..self.loose.len() {
            if hits >= enough {
                return hits;
            }
            if touches(self, self.loose[k]) {
                hits += 1;
            }
        }
        let (lo, hi) = ((r.x, r.y), (r.x + r.w, r.y + r.h));
        // A box wholly beyond the grid's edge meets no obstacle with a finite box.
        let outside =
            hi.0 < self.origin.0 || hi.1 < self.origin.1 || lo.0.is_nan() || lo.1.is_nan();
        if outside {
            return hits;
        }
        let ((c0, c1), (r0, r1)) = self.span(lo, hi);
        for row in r0..=r1 {
            for column in c0..=c1 {
                for k in 0..self.cells[row * self.columns + column].len() {
                    if hits >= enough {
                        return hits;
                    }
                    let i = self.cells[row * self.columns + column][k];
                    if self.seen[i] != self.query {
                        self.seen[i] = self.query;
                        if touches(self, i) {
                            hits += 1;
                        }
                    }
                }
            }
        }
        hits
    }
}

/// The cell a distance `d` from the grid's origin falls in (0 before it).
fn cell(d: f64, side: f64) -> usize {
    // Not negative and bounded (a NaN converts to 0).
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let k = (d / side).floor().clamp(0.0, 1e6) as usize;
    k
}

/// The sines and cosines of the 16 directions of [`candidates`], from the upper right
/// clockwise (computed once per [`place`], not once per candidate).
type Directions = [(f64, f64); 16];

fn directions() -> Directions {
    let mut table = [(0.0, 0.0); 16];
    for (k, slot) in table.iter_mut().enumerate() {
        let angle = std::f64::consts::FRAC_PI_4 - k as f64 * std::f64::consts::PI / 8.0;
        *slot = angle.sin_cos();
    }
    table
}

/// Candidate boxes around the anchor: rings of growing distance, 16 directions each, the
/// upper right first (where textbooks put a point's name). The first without any obstacle
/// wins, so the nearest clear place is taken.
fn candidates<'a>(
    request: &'a Request,
    directions: &'a Directions,
) -> impl Iterator<Item = Rect> + 'a {
    const RINGS: [f64; 9] = [6.0, 12.0, 20.0, 30.0, 44.0, 62.0, 86.0, 116.0, 150.0];
    let (w, h) = request.size;
    let (ax, ay) = request.anchor;
    RINGS.iter().flat_map(move |&d| {
        directions.iter().map(move |&(s, c)| {
            // The box's nearest edge point lies on the ray at distance d.
            let cx = ax + c * (d + 0.5 * w * c.abs());
            let cy = ay - s * (d + 0.5 * h * s.abs());
            Rect {
                x: cx - 0.5 * w,
                y: cy - 0.5 * h,
                w,
                h,
            }
        })
    })
}

/// A place below the drawing that no label takes yet.
fn free_row(request: &Request, placed: &[Rect], bottom: f64) -> Rect {
    let (w, h) = request.size;
    let mut y = bottom + 8.0;
    loop {
        let r = Rect {
            x: request.anchor.0 - 0.5 * w,
            y,
            w,
            h,
        };
        if !placed.iter().any(|p| p.overlaps(&r)) {
            return r;
        }
        y += h + 2.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_avoid_each_other_and_the_drawing() {
        let line = Obstacle::Segment((0.0, 50.0), (200.0, 50.0), 2.0);
        let requests: Vec<Request> = (0..12)
            .map(|_| Request {
                size: (20.0, 14.0),
                anchor: (100.0, 50.0),
            })
            .collect();
        let rects = place(&requests, &[line]);
        for (i, a) in rects.iter().enumerate() {
            assert!(!line.meets(a), "label {i} on the line: {a:?}");
            for b in &rects[i + 1..] {
                assert!(!a.overlaps(b), "{a:?} and {b:?} overlap");
            }
        }
    }

    #[test]
    fn a_segment_through_a_box_meets_it() {
        let r = Rect {
            x: 0.0,
            y: 0.0,
            w: 10.0,
            h: 10.0,
        };
        assert!(segment_meets((-5.0, 5.0), (15.0, 5.0), &r));
        assert!(!segment_meets((-5.0, 15.0), (15.0, 15.0), &r));
        assert!(!segment_meets((-5.0, 5.0), (-1.0, 20.0), &r));
    }
}
