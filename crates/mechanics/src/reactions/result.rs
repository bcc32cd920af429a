//! A computed reaction, the methods that gave it and how they compared.

use cas::Expr;

use super::ReleaseKind;
use crate::system::Vector;

/// A method that gave a reaction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Lagrange's equations of the first kind.
    LagrangeI,
    /// Newton–Euler: momentum equation of the released bodies.
    NewtonEuler,
}

impl Method {
    /// Its name in reports and JSON.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Method::LagrangeI => "lagrange_1",
            Method::NewtonEuler => "newton_euler",
        }
    }
}

/// How the two methods were compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Agreement {
    /// Equal normal forms.
    Exact,
    /// The normal forms differ but the values agree at random states (relative 1e-9).
    Numeric,
    /// They disagree: a bug, reported as such.
    Disagree,
    /// Only one method applies.
    Single,
    /// Newton–Euler cannot attribute every load: the release moves bodies or particles that
    /// it does not name (two particles at one point, a pendulum hanging from the released
    /// body), whose inertia and weight the released bodies' momentum balance does not see.
    /// Lagrange I's value stands alone.
    Unattributed,
}

impl Agreement {
    /// What it means, for people.
    #[must_use]
    pub fn verdict(self) -> &'static str {
        match self {
            Agreement::Exact => "agree exactly (equal normal forms)",
            Agreement::Numeric => "agree numerically at random states",
            Agreement::Disagree => "DISAGREE: this is a bug, please report it",
            Agreement::Single => "one method",
            Agreement::Unattributed => "Lagrange I only: the release also moves bodies it does not name, whose loads Newton–Euler cannot attribute",
        }
    }

    /// Its name in reports and JSON.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Agreement::Exact => "exact",
            Agreement::Numeric => "numeric",
            Agreement::Disagree => "disagree",
            Agreement::Single => "single",
            Agreement::Unattributed => "unattributed",
        }
    }
}

/// A computed reaction, as a function of `(q, q̇, t)` of the constrained system.
#[derive(Clone, Debug)]
pub struct Reaction {
    /// Its name.
    pub name: String,
    /// What it transmits (`None` for a generalized reaction).
    pub kind: Option<ReleaseKind>,
    /// The point's name and position, for a force at a point.
    pub point: Option<(String, Vector)>,
    /// The bodies the force acts on.
    pub members: Vec<String>,
    /// The force on the released bodies, inertial components (Lagrange I).
    pub force: Option<Vector>,
    /// For a clamp: the reaction couple on the released bodies, inertial components.
    pub couple: Option<Vector>,
    /// For a hinge or a rolling contact, which transmit no couple: the couple about the point
    /// that the motion nevertheless needs, when it is not zero. Then other supports built into
    /// the coordinates act on the released bodies (the force is their total with this one), or
    /// the joint transmits a couple (ask for a `clamp`).
    pub unbalanced_couple: Option<Vector>,
    /// For a rolling contact with a normal: the friction force, `R − N n`.
    pub friction: Option<Vector>,
    /// For a contact or rope: the scalar along the given direction (`N`, `T`), and the unit
    /// direction.
    pub along: Option<(Expr, Vector)>,
    /// For a constraint written as an equation: the generalized reaction on each coordinate,
    /// `Q^R_j` (Lagrange I), and the multipliers of its rows.
    pub generalized: Vec<(String, Expr)>,
    /// The multipliers `λ` (`M q̈ + Aᵀλ = f`), for a generalized reaction.
    pub multipliers: Vec<Expr>,
    /// Whether this is the generalized force driving a driven coordinate (in `generalized`).
    pub driving: bool,
    /// The methods that agree.
    pub methods: Vec<Method>,
    /// How they were compared.
    pub agreement: Agreement,
    /// For a force at a point: the released system's equation `E_u − Q_u` of each
    /// displacement and rotation `u` that has one, at `u = u̇ = ü = 0` and before the
    /// constrained motion is put in (the working a solution prints before the result; kept
    /// so that it costs no second derivation of the released system).
    pub released_equations: Vec<(String, Expr)>,
}
