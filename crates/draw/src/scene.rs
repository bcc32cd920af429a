//! The scene: what a figure shows, in world coordinates (metres, inertial axes), before it is
//! projected. Building it ([`crate::build`]) decides *what* to draw; the projection and the
//! SVG writer decide only *how*.

/// A point of 3-space, inertial components.
pub type P3 = [f64; 3];

/// One thing to draw.
#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    /// A rigid link or a slender body between two points.
    Rod {
        /// One end.
        a: P3,
        /// The other end.
        b: P3,
    },
    /// A disk, gear or pulley: a circle of `radius` about `centre` in the plane normal to
    /// `normal`, with a radius line towards `marker` (so that its turning shows).
    Disk {
        /// Its name (the body's).
        name: String,
        /// The centre.
        centre: P3,
        /// The unit normal of its plane.
        normal: P3,
        /// The radius.
        radius: f64,
        /// A rim point the radius line goes to.
        marker: P3,
    },
    /// A block (a cart, a sliding or hanging mass) centred on `centre`, sides along `along`.
    Block {
        /// Its name.
        name: String,
        /// The centre.
        centre: P3,
        /// A unit vector along one of its sides (the direction it slides in).
        along: P3,
        /// Its side.
        size: f64,
    },
    /// A track the block slides on: a hatched line from `a` to `b`, hatched towards `side`.
    Track {
        /// One end.
        a: P3,
        /// The other end.
        b: P3,
        /// The unit vector pointing into the ground.
        side: P3,
    },
    /// A fixed round surface a point slides on (a sphere, a cylinder), seen as a circle.
    Sphere {
        /// Its centre.
        centre: P3,
        /// Its radius.
        radius: f64,
    },
    /// A fixed support at a pivot: a triangle on hatched ground, pointing away from `down`.
    Support {
        /// The pivot.
        at: P3,
        /// The unit vector towards the ground.
        down: P3,
    },
    /// A wall a spring or damper is anchored to, normal along `normal`.
    Wall {
        /// The anchor.
        at: P3,
        /// The unit vector from the wall into the free side.
        normal: P3,
    },
    /// A hinge: a small open circle.
    Hinge {
        /// Where.
        at: P3,
    },
    /// A particle: a filled dot with the point's name.
    Particle {
        /// The point's name.
        name: String,
        /// Where.
        at: P3,
    },
    /// A linear spring (a zigzag).
    Spring {
        /// One end.
        a: P3,
        /// The other end.
        b: P3,
    },
    /// A torsional spring: a coil about a pivot.
    Coil {
        /// The pivot.
        at: P3,
        /// The plane's unit normal.
        normal: P3,
        /// The outer radius.
        radius: f64,
    },
    /// A linear damper (a dashpot).
    Damper {
        /// One end.
        a: P3,
        /// The other end.
        b: P3,
    },
    /// An arrow: a force, gravity, a frame axis or a displacement.
    Arrow {
        /// What it shows.
        kind: ArrowKind,
        /// Its tail.
        from: P3,
        /// Its head.
        to: P3,
    },
    /// A curved arrow or an arc: an angle coordinate from its reference line, or a couple.
    Arc {
        /// What it shows.
        kind: ArcKind,
        /// The points of the arc, in order (the head is at the last one).
        points: Vec<P3>,
    },
    /// A dashed reference line (the zero of an angle or of a displacement).
    Reference {
        /// One end.
        a: P3,
        /// The other end.
        b: P3,
    },
    /// Uniform gravity: an arrow placed beside the drawing.
    Gravity {
        /// Its direction (unit).
        direction: P3,
        /// Its label.
        label: String,
    },
    /// A named point of the model (its label).
    Point {
        /// The name.
        name: String,
        /// Where.
        at: P3,
    },
}

/// What an arrow shows.
#[derive(Clone, Debug, PartialEq)]
pub enum ArrowKind {
    /// An applied force, labelled with its magnitude's expression.
    Force(String),
    /// A generalized coordinate measured as a displacement.
    Coordinate(String),
    /// An axis of a frame (`N.x`), labelled.
    Axis(String),
}

/// What an arc shows.
#[derive(Clone, Debug, PartialEq)]
pub enum ArcKind {
    /// A generalized coordinate measured as an angle.
    Coordinate(String),
    /// A couple, labelled.
    Couple(String),
}

/// Everything a figure shows, and a typical length for the sizes of symbols.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// The items, in drawing order (later on top).
    pub items: Vec<Item>,
    /// A length typical of the system (its extent), in metres: symbols scale with it.
    pub size: f64,
    /// Coordinates that no element of the drawing shows (a precession angle, …).
    pub unmarked: Vec<String>,
}
