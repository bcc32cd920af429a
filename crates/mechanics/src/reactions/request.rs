//! What a reaction request says: the kind of joint released, the released system with its
//! redundant displacements, or a constraint or driven coordinate whose generalized reaction is
//! wanted.

use cas::Expr;

use crate::system::{System, Vector};

/// What a reaction transmits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ReleaseKind {
    /// A pin: a force, all components.
    Hinge,
    /// A contact: the normal force only, unilateral (push only, `N ≥ 0`).
    Contact,
    /// A rope: the tension along the rope only, unilateral (pull only, `T ≥ 0`).
    Rope,
    /// A rolling contact: normal force and friction.
    Rolling,
    /// A clamp (a weld): a force and a couple.
    Clamp,
}

impl ReleaseKind {
    /// The word of the model language.
    #[must_use]
    pub fn word(self) -> &'static str {
        match self {
            ReleaseKind::Hinge => "hinge",
            ReleaseKind::Contact => "contact",
            ReleaseKind::Rope => "rope",
            ReleaseKind::Rolling => "rolling",
            ReleaseKind::Clamp => "clamp",
        }
    }

    /// Whether the constraint can only push (or only pull).
    #[must_use]
    pub fn is_unilateral(self) -> bool {
        matches!(self, ReleaseKind::Contact | ReleaseKind::Rope)
    }
}

/// A constraint released at a point: the system lowered again with redundant displacements.
#[derive(Clone, Debug)]
pub struct Release {
    /// The reaction's name.
    pub name: String,
    /// What it transmits.
    pub kind: ReleaseKind,
    /// The point's name and position (constrained system).
    pub point: (String, Vector),
    /// The released bodies' and particles' names (for reports).
    pub members: Vec<String>,
    /// The released system: the displacements are extra coordinates, the constraint (if it
    /// was written as one) is dropped.
    pub system: System,
    /// The displacement coordinates with the (unit) direction each moves the members along.
    pub displacements: Vec<(String, Vector)>,
    /// For a clamp (and, to check that no couple is needed, a hinge or a rolling contact):
    /// the small-rotation coordinates, with the axis each turns the members about (through the
    /// point). Empty otherwise.
    pub rotations: Vec<(String, Vector)>,
    /// For a rolling contact: the unit normal (into the body) that splits the force into the
    /// normal force, which can only push, and friction.
    pub normal: Option<Vector>,
    /// Indices of the released particles in the system (same in both systems).
    pub particles: Vec<usize>,
    /// Indices of the released rigid bodies.
    pub bodies: Vec<usize>,
}

/// A reaction asked for.
#[derive(Clone, Debug)]
pub enum ReactionRequest {
    /// A force at a point, by release.
    Release(Release),
    /// The generalized reaction of a constraint written as an equation (or a gear): its
    /// multipliers. `without` is the system with that constraint dropped.
    Constraint {
        /// The constraint's name.
        name: String,
        /// The system with the constraint dropped.
        without: System,
    },
    /// The generalized force that drives a driven coordinate `q = f(t)`: `E_q − Q_q` of the
    /// system in which `q` is free, on the motion.
    Driven {
        /// The coordinate.
        name: String,
        /// The system with the coordinate free.
        without: System,
        /// Its prescribed motion `f(t)`.
        motion: Expr,
    },
}
