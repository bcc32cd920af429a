//! The kinematic tree of a system, read off its symbolic model, for an O(n) evaluation of
//! `q̈` ([`numeric::Articulated`]): [`KinematicTree::of`].
//!
//! Every mass element — a particle's or a body's centre's velocity `v = Σ_i ∂r/∂q_i q̇_i`
//! (inertial components), a body's angular velocity `ω_B = Rᵀω = Σ_i ∂ω_B/∂q̇_i q̇_i` (body
//! axes) — is a sum of columns, one per coordinate it depends on. In a chain written the
//! way people write one (`point P2 = P1 + l sin θ₂ N.x …`, `frame B2 = N rotated a2 …`) the
//! elements below a coordinate share their columns above it: every mass of an n-link pendulum
//! has the column `l_j (cos θ_j, sin θ_j)` at `θ_j`. A *track* is such a shared partial sum:
//! at coordinate `j`, the elements that agree on every column from the root to `j` share one
//! track, which continues its parent's track (`X_j` gathers it) and adds `S_j q̇_j`, `S_j`
//! their common column. With `T = ½ Σ V_jᵀ W_j V_j` (`W_j`: the masses and inertias of the
//! elements whose last coordinate is `j`), Lagrange's equations are `S_jᵀ F_j = τ_j`, the
//! articulated-body form, where
//!
//! | symbol | meaning |
//! |---|---|
//! | `c_j = Ṡ_j q̇_j` | the track's velocity-product acceleration |
//! | `b_j = Σ ω_B × (I ω_B)` | the gyroscopic force of the bodies attached at `j` (Euler's equations) |
//! | `τ_j = Q_j − ∂V/∂q_j` | everything but the kinetic energy's terms |
//!
//! The coordinates' tree takes each coordinate's parent to be the nearest earlier coordinate
//! that some element depends on together with it; when an element's coordinates do not lie on
//! one path of that tree, the declaration order (a chain) is used, which is always valid. The
//! number of tracks a node carries decides the cost: bounded for chains in absolute
//! coordinates, growing with `n` where each element's column at a coordinate differs (relative
//! angles), where the dense route is cheaper; the caller compares.

use std::collections::HashMap;

use cas::{Expr, Symbol};

use crate::{angular_velocity, Equations, System};

/// The tree of a system's kinetic energy (see the module doc). Invariant: `nodes[j]` is
/// coordinate `j`; `motion`, `bias_acceleration` and `bias_force` hold one expression per
/// velocity component, node after node (`Σ d_j` each); `forces` one per coordinate.
#[derive(Clone, Debug)]
pub struct KinematicTree {
    nodes: Vec<TreeNode>,
    motion: Vec<Expr>,
    bias_acceleration: Vec<Expr>,
    bias_force: Vec<Expr>,
    forces: Vec<Expr>,
}

/// One coordinate's node: its parent, which parent component each of its components
/// continues, and `W_j` (row-major, `d_j × d_j`, free of the state).
#[derive(Clone, Debug)]
pub struct TreeNode {
    /// The parent coordinate (an earlier one), `None` at a root.
    pub parent: Option<usize>,
    /// For each velocity component of this node, the parent's component it continues.
    pub source: Vec<Option<usize>>,
    /// `W_j`: masses and inertias of the elements whose last coordinate this is.
    pub inertia: Vec<Expr>,
}

impl KinematicTree {
    /// The tree of `system`'s kinetic energy and `equations`' forces, or `None` where the
    /// articulated form does not hold: constraints kept with multipliers or eliminated,
    /// driven coordinates, positions or rotations that depend on time, a potential that
    /// depends on rates, masses or inertias that depend on the state, or no element at all.
    #[must_use]
    pub fn of(system: &System, equations: &Equations) -> Option<KinematicTree> {
        let names = equations.coordinates();
        let plain = equations.constraint_names().is_empty()
            && equations.eliminated().is_empty()
            && system.driven().is_empty()
            && system.constraints().is_empty()
            && system.coordinates() == names;
        if !plain || names.is_empty() {
            return None;
        }
        let vars = State::of(names)?;
        let forces = forces(equations, &vars)?;
        let elements = elements(system, &vars)?;
        if elements.is_empty() {
            return None;
        }
        let parents = parents(&elements, names.len());
        Some(build(&elements, &parents, &vars, forces))
    }

    /// The nodes, one per coordinate.
    #[must_use]
    pub fn nodes(&self) -> &[TreeNode] {
        &self.nodes
    }

    /// `S`: each node's column of its tracks, node after node.
    #[must_use]
    pub fn motion(&self) -> &[Expr] {
        &self.motion
    }

    /// `c = Ṡ q̇`, laid out as [`KinematicTree::motion`].
    #[must_use]
    pub fn bias_acceleration(&self) -> &[Expr] {
        &self.bias_acceleration
    }

    /// `b`, the gyroscopic forces, laid out as [`KinematicTree::motion`].
    #[must_use]
    pub fn bias_force(&self) -> &[Expr] {
        &self.bias_force
    }

    /// `τ_j = Q_j − ∂V/∂q_j`, one per coordinate.
    #[must_use]
    pub fn forces(&self) -> &[Expr] {
        &self.forces
    }

    /// `Σ d_j²`, the work of one elimination in multiply–adds (within a small factor).
    #[must_use]
    pub fn cost(&self) -> usize {
        self.nodes.iter().map(|n| n.source.len().pow(2)).sum()
    }
}

/// The state's symbols: coordinates, rates, time.
struct State {
    q: Vec<Symbol>,
    qd: Vec<Symbol>,
    qd_expr: Vec<Expr>,
    time: Symbol,
}

impl State {
    fn of(names: &[String]) -> Option<State> {
        let q = names
            .iter()
            .map(|x| Expr::coordinate(x).as_symbol())
            .collect::<Option<Vec<_>>>()?;
        let qd_expr: Vec<Expr> = names.iter().map(|x| Expr::rate(x, 1)).collect();
        let qd = qd_expr
            .iter()
            .map(|x| x.as_symbol())
            .collect::<Option<Vec<_>>>()?;
        Some(State {
            q,
            qd,
            qd_expr,
            time: Expr::time().as_symbol()?,
        })
    }

    fn depends_on_state(&self, e: Expr) -> bool {
        self.q
            .iter()
            .chain(&self.qd)
            .chain(std::iter::once(&self.time))
            .any(|s| !e.diff(*s).is_zero())
    }
}

/// Whether an element's velocity is a translation (inertial axes) or a rotation (body axes):
/// tracks of different kinds never merge.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
enum Kind {
    Translation,
    Rotation,
}

/// A mass element: its columns (one per coordinate, three components each), its inertia
/// (3×3) and its gyroscopic force (rotations only).
struct Element {
    kind: Kind,
    columns: Vec<[Expr; 3]>,
    inertia: [[Expr; 3]; 3],
    bias: Option<[Expr; 3]>,
}

impl Element {
    fn last(&self) -> Option<usize> {
        self.columns.iter().rposition(|c| !is_zero(c))
    }
}

fn is_zero(column: &[Expr]) -> bool {
    column.iter().all(|x| x.is_zero())
}

/// `τ_j = Q_j − ∂V/∂q_j`; `None` when `V` depends on the rates.
fn forces(equations: &Equations, vars: &State) -> Option<Vec<Expr>> {
    let potential = equations.potential_energy();
    if vars.qd.iter().any(|s| !potential.diff(*s).is_zero()) {
        return None;
    }
    Some(
        equations
            .generalized_forces()
            .iter()
            .zip(&vars.q)
            .map(|(force, q)| (*force - potential.diff(*q)).normal())
            .collect(),
    )
}

/// The particles' and bodies' mass elements; `None` when one cannot be put in the form.
fn elements(system: &System, vars: &State) -> Option<Vec<Element>> {
    let mut out = Vec::new();
    let scalar = |m: Expr| {
        let z = Expr::zero();
        [[m, z, z], [z, m, z], [z, z, m]]
    };
    let translation = |position: &[Expr; 3], mass: Expr| -> Option<Element> {
        if position.iter().any(|x| !x.diff(vars.time).is_zero()) {
            return None;
        }
        let columns = vars
            .q
            .iter()
            .map(|q| position.map(|x| x.diff(*q).normal()))
            .collect();
        Some(Element {
            kind: Kind::Translation,
            columns,
            inertia: scalar(mass),
            bias: None,
        })
    };
    for p in system.particles() {
        if !p.mass.is_zero() {
            out.push(translation(&p.position, p.mass)?);
        }
    }
    for body in system.bodies() {
        if !body.mass.is_zero() {
            out.push(translation(&body.centre, body.mass)?);
        }
        if body.inertia.iter().flatten().all(|x| x.is_zero()) {
            continue;
        }
        out.push(rotation(&body.rotation, &body.inertia, vars)?);
    }
    let constant = |e: &Element| {
        e.inertia
            .iter()
            .flatten()
            .all(|x| !vars.depends_on_state(*x))
    };
    out.iter().all(constant).then_some(out)
}

/// A body's rotation: `ω_B = Rᵀω` by columns `∂ω_B/∂q̇_i`, and `ω_B × (I ω_B)`.
fn rotation(r: &[[Expr; 3]; 3], inertia: &[[Expr; 3]; 3], vars: &State) -> Option<Element> {
    if r.iter().flatten().any(|x| !x.diff(vars.time).is_zero()) {
        return None;
    }
    let w = angular_velocity(r);
    let wb: [Expr; 3] =
        std::array::from_fn(|i| (0..3).map(|k| r[k][i] * w[k]).sum::<Expr>().normal());
    let columns = vars
        .qd
        .iter()
        .map(|s| wb.map(|x| x.diff(*s).normal()))
        .collect();
    let iw: [Expr; 3] =
        std::array::from_fn(|i| (0..3).map(|k| inertia[i][k] * wb[k]).sum::<Expr>());
    let bias = [
        (wb[1] * iw[2] - wb[2] * iw[1]).normal(),
        (wb[2] * iw[0] - wb[0] * iw[2]).normal(),
        (wb[0] * iw[1] - wb[1] * iw[0]).normal(),
    ];
    Some(Element {
        kind: Kind::Rotation,
        columns,
        inertia: *inertia,
        bias: Some(bias),
    })
}

/// Each coordinate's parent: the nearest earlier coordinate some element depends on together
/// with it, if every element's coordinates then lie on one root path; else the chain in
/// declaration order.
fn parents(elements: &[Element], n: usize) -> Vec<Option<usize>> {
    let supports: Vec<Vec<usize>> = elements
        .iter()
        .map(|e| (0..n).filter(|&i| !is_zero(&e.columns[i])).collect())
        .collect();
    let mut parent: Vec<Option<usize>> = vec![None; n];
    for support in &supports {
        for pair in support.windows(2) {
            let (i, j) = (pair[0], pair[1]);
            parent[j] = parent[j].max(Some(i));
        }
    }
    let on_one_path = |support: &Vec<usize>| {
        let Some(&last) = support.last() else {
            return true;
        };
        let mut path = vec![last];
        while let Some(p) = parent[path[path.len() - 1]] {
            path.push(p);
        }
        support.iter().all(|i| path.contains(i))
    };
    if supports.iter().all(on_one_path) {
        parent
    } else {
        (0..n).map(|j| j.checked_sub(1)).collect()
    }
}

/// A track: its node, kind, parent track and column (kept components).
struct Track {
    node: usize,
    parent: Option<usize>,
    column: Vec<Expr>,
    inertia: Vec<Expr>,
    bias: Vec<Expr>,
}

/// The tracks of every element, the node layout, and the expressions of each component.
fn build(
    elements: &[Element],
    parents: &[Option<usize>],
    vars: &State,
    forces: Vec<Expr>,
) -> KinematicTree {
    let kept = kept_components(elements);
    let mut tracks: Vec<Track> = Vec::new();
    let mut index: HashMap<(usize, Option<usize>, Kind, Vec<Expr>), usize> = HashMap::new();
    for element in elements {
        let Some(last) = element.last() else {
            continue;
        };
        let components = &kept[usize::from(element.kind == Kind::Rotation)];
        let mut path = vec![last];
        while let Some(p) = parents[path[path.len() - 1]] {
            path.push(p);
        }
        let mut current: Option<usize> = None;
        for &j in path.iter().rev() {
            let column: Vec<Expr> = components.iter().map(|&k| element.columns[j][k]).collect();
            if current.is_none() && is_zero(&column) {
                continue;
            }
            let key = (j, current, element.kind, column.clone());
            let id = *index.entry(key).or_insert_with(|| {
                tracks.push(Track {
                    node: j,
                    parent: current,
                    column,
                    inertia: vec![Expr::zero(); components.len().pow(2)],
                    bias: vec![Expr::zero(); components.len()],
                });
                tracks.len() - 1
            });
            current = Some(id);
        }
        if let Some(id) = current {
            attach(&mut tracks[id], element, components);
        }
    }
    layout(&tracks, parents, vars, forces)
}

/// Adds an element's inertia and gyroscopic force to the track it ends on.
fn attach(track: &mut Track, element: &Element, components: &[usize]) {
    let d = components.len();
    for (r, &a) in components.iter().enumerate() {
        for (k, &b) in components.iter().enumerate() {
            track.inertia[r * d + k] = (track.inertia[r * d + k] + element.inertia[a][b]).normal();
        }
        if let Some(bias) = &element.bias {
            track.bias[r] = (track.bias[r] + bias[a]).normal();
        }
    }
}

/// The components (of three) that some element of each kind moves along: translations, then
/// rotations. A component no column ever has stays zero and is left out (a planar model's z).
fn kept_components(elements: &[Element]) -> [Vec<usize>; 2] {
    let of = |kind: Kind| -> Vec<usize> {
        (0..3)
            .filter(|&k| {
                elements
                    .iter()
                    .filter(|e| e.kind == kind)
                    .any(|e| e.columns.iter().any(|c| !c[k].is_zero()))
            })
            .collect()
    };
    [of(Kind::Translation), of(Kind::Rotation)]
}

/// Lays the tracks out node after node: each node's components, their sources in the parent,
/// its block-diagonal `W_j`, and the expressions of `S`, `c` and `b`.
fn layout(
    tracks: &[Track],
    parents: &[Option<usize>],
    vars: &State,
    forces: Vec<Expr>,
) -> KinematicTree {
    let n = parents.len();
    let mut at: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (id, track) in tracks.iter().enumerate() {
        at[track.node].push(id);
    }
    // Where each track's components start within its node's vector.
    let mut start = vec![0; tracks.len()];
    for ids in &at {
        let mut offset = 0;
        for &id in ids {
            start[id] = offset;
            offset += tracks[id].column.len();
        }
    }
    let mut tree = KinematicTree {
        nodes: Vec::with_capacity(n),
        motion: Vec::new(),
        bias_acceleration: Vec::new(),
        bias_force: Vec::new(),
        forces,
    };
    for (j, ids) in at.iter().enumerate() {
        let d: usize = ids.iter().map(|&id| tracks[id].column.len()).sum();
        let mut node = TreeNode {
            parent: parents[j],
            source: Vec::with_capacity(d),
            inertia: vec![Expr::zero(); d * d],
        };
        for &id in ids {
            let track = &tracks[id];
            let k = track.column.len();
            for r in 0..k {
                node.source.push(track.parent.map(|p| start[p] + r));
                for c in 0..k {
                    node.inertia[(start[id] + r) * d + start[id] + c] = track.inertia[r * k + c];
                }
                tree.motion.push(track.column[r]);
                tree.bias_acceleration
                    .push((track.column[r].dt() * vars.qd_expr[j]).normal());
                tree.bias_force.push(track.bias[r]);
            }
        }
        tree.nodes.push(node);
    }
    tree
}
