//! `M q̈ = f` solved in O(n) for a kinetic energy with the structure of a tree: the
//! articulated-body elimination (Featherstone's ABA, in the general form of Rodriguez, Jain and
//! Kreutz-Delgado's innovations factorization of `M`), with nodes that carry any number of
//! velocity components. [`Articulated`] holds the tree and its buffers; what it eliminates is
//! given anew at each evaluation.
//!
//! | symbol | meaning | shape |
//! |---|---|---|
//! | `j`, `π(j)` | a node (one per coordinate) and its parent (`π(j) < j`) | |
//! | `V_j = X_j V_π(j) + S_j q̇_j` | the node's velocity components; `X_j` gathers parent components | `d_j` |
//! | `T = ½ Σ V_jᵀ W_j V_j` | kinetic energy, `W_j` constant and symmetric | `d_j × d_j` |
//! | `a_j = X_j a_π(j) + S_j q̈_j + c_j` | accelerations, `c_j = Ṡ_j q̇_j` | `d_j` |
//! | `F_j = W_j a_j + b_j + Σ_children X_cᵀ F_c` | forces carried back to node `j`; `b_j` velocity-dependent (gyroscopic) | `d_j` |
//! | `S_jᵀ F_j = τ_j` | the equation of motion of coordinate `j` | scalar |
//!
//! Backward (leaves to root), with `Iᴬ_j = W_j + Σ X_cᵀ Iᵃ_c X_c` and `pᴬ_j = b_j + Σ X_cᵀ pᵃ_c`:
//! `U = Iᴬ S`, `D = Sᵀ U`, `u = τ − Sᵀ pᴬ − Uᵀ c`, `Iᵃ = Iᴬ − U Uᵀ / D`,
//! `pᵃ = pᴬ + Iᴬ c + U u / D`. Forward (root to leaves): `q̈_j = (u − Uᵀ X a_π) / D`,
//! `a_j = X a_π + S q̈_j + c`. Each node costs O(d_j²), so a chain whose nodes carry a bounded
//! number of components is solved in O(n), where the dense `L D Lᵀ` of `M` is O(n³).

use crate::LinearError;

/// One node of the tree, as given to [`Articulated::new`].
#[derive(Clone, Debug, PartialEq)]
pub struct ArticulatedNode {
    /// The parent node (an earlier one), `None` at a root.
    pub parent: Option<usize>,
    /// For each of this node's velocity components, the parent's component it continues
    /// (`X_j` as a gather), `None` for a component that starts here.
    pub source: Vec<Option<usize>>,
    /// `W_j`, row-major `d_j × d_j` with `d_j = source.len()`.
    pub inertia: Vec<f64>,
}

/// Why a tree was refused by [`Articulated::new`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ArticulatedError {
    /// A node's parent is not an earlier node.
    #[error("node {node}'s parent is not an earlier node")]
    ParentNotBefore {
        /// The node, from 0.
        node: usize,
    },
    /// A component continues one its parent does not have (or a root's continues any).
    #[error("node {node}'s component {component} continues a component its parent does not have")]
    SourceOutOfRange {
        /// The node, from 0.
        node: usize,
        /// The component, from 0.
        component: usize,
    },
    /// `W_j` does not have `d_j²` entries.
    #[error("node {node}'s inertia has {found} entries, not {expected}")]
    InertiaShape {
        /// The node, from 0.
        node: usize,
        /// `d_j²`.
        expected: usize,
        /// What was given.
        found: usize,
    },
}

/// The tree, its constant inertias and the buffers of the elimination: solving allocates
/// nothing. Invariant (checked by [`Articulated::new`]): every parent precedes its child and
/// every gathered component exists in the parent.
///
/// The tree's shape is fixed here, so each node's step is chosen once: nodes of up to
/// nine components run a step compiled for their dimension (the `d × d`
/// block in registers, the loops unrolled), and a node that continues its parent's
/// components one for one (the chains of absolute coordinates) adds its block to the
/// parent's without an index list.
#[derive(Clone, Debug)]
pub struct Articulated {
    parent: Vec<Option<usize>>,
    /// Node `j`'s components are `offset[j]..offset[j + 1]` of every per-component buffer.
    offset: Vec<usize>,
    /// For each component, the parent's component it continues, as an index into the
    /// per-component buffers.
    source: Vec<Option<usize>>,
    /// Node `j`'s continued components as `(component, parent's component)`, both local to
    /// their node, at `continued_offset[j]..continued_offset[j + 1]`: the inner loops run over
    /// these alone, with no test per component.
    continued: Vec<(usize, usize)>,
    continued_offset: Vec<usize>,
    /// Whether node `j` continues every component of its parent, in order, and has no other
    /// (`X_j = 1`): its block then adds to the parent's as a whole.
    identity: Vec<bool>,
    /// Node `j`'s `d_j × d_j` block starts at `block[j]`.
    block: Vec<usize>,
    /// `W`, constant.
    inertia: Vec<f64>,
    /// What the children carry into each node's articulated inertia, `Σ X_cᵀ Iᵃ_c X_c`
    /// (so that `Iᴬ = W + articulated`), laid out as `inertia`; zero between solves: each node
    /// clears its block when it reads it, and a failed solve clears the whole buffer.
    articulated: Vec<f64>,
    /// What the children carry into each node's bias force, `Σ X_cᵀ pᵃ_c`; zero between
    /// solves, as `articulated`.
    bias: Vec<f64>,
    projected: Vec<f64>,
    pivot: Vec<f64>,
    reduced: Vec<f64>,
    acceleration: Vec<f64>,
    /// The general step's working space: `Iᴬ` (`d²`), then `pᴬ`, `Iᴬ c` (`d` each).
    scratch: Vec<f64>,
}

/// The per-evaluation inputs of [`Articulated::solve`], together.
struct Given<'a> {
    motion: &'a [f64],
    bias_acceleration: &'a [f64],
    bias_force: &'a [f64],
    forces: &'a [f64],
}

/// The first `D` numbers of `xs` (one bounds check, where indexing each would take `D`).
fn load<const D: usize>(xs: &[f64]) -> [f64; D] {
    let mut out = [0.0; D];
    out.copy_from_slice(&xs[..D]);
    out
}

/// Calls `$self.$fixed::<D>(args)` for a node of `D ≤ 9` components, else
/// `$self.$general(args)`: the dispatch is one jump per node.
macro_rules! by_dimension {
    ($self:ident, $d:expr, $fixed:ident, $general:ident, $($arg:expr),*) => {
        match $d {
            1 => $self.$fixed::<1>($($arg),*),
            2 => $self.$fixed::<2>($($arg),*),
            3 => $self.$fixed::<3>($($arg),*),
            4 => $self.$fixed::<4>($($arg),*),
            5 => $self.$fixed::<5>($($arg),*),
            6 => $self.$fixed::<6>($($arg),*),
            7 => $self.$fixed::<7>($($arg),*),
            8 => $self.$fixed::<8>($($arg),*),
            9 => $self.$fixed::<9>($($arg),*),
            _ => $self.$general($($arg),*),
        }
    };
}

impl Articulated {
    /// The tree of `nodes` (node `j` is coordinate `j`).
    ///
    /// # Errors
    /// [`ArticulatedError`] when a parent does not precede its child, a component continues
    /// one its parent lacks, or an inertia has the wrong number of entries.
    pub fn new(nodes: &[ArticulatedNode]) -> Result<Articulated, ArticulatedError> {
        let mut offset = vec![0];
        let mut block = vec![0];
        let mut source = Vec::new();
        let mut inertia = Vec::new();
        for (j, node) in nodes.iter().enumerate() {
            let d = node.source.len();
            if node.inertia.len() != d * d {
                return Err(ArticulatedError::InertiaShape {
                    node: j,
                    expected: d * d,
                    found: node.inertia.len(),
                });
            }
            let parent_range = match node.parent {
                Some(p) if p >= j => return Err(ArticulatedError::ParentNotBefore { node: j }),
                Some(p) => offset[p]..offset[p + 1],
                None => 0..0,
            };
            for (component, s) in node.source.iter().enumerate() {
                let global = s.map(|s| parent_range.start + s);
                if global.is_some_and(|g| !parent_range.contains(&g)) {
                    return Err(ArticulatedError::SourceOutOfRange { node: j, component });
                }
                source.push(global);
            }
            inertia.extend_from_slice(&node.inertia);
            offset.push(source.len());
            block.push(inertia.len());
        }
        let mut continued = Vec::new();
        let mut continued_offset = vec![0];
        let mut identity = Vec::with_capacity(nodes.len());
        for (j, node) in nodes.iter().enumerate() {
            let parent_start = node.parent.map_or(0, |p| offset[p]);
            for (r, s) in source[offset[j]..offset[j + 1]].iter().enumerate() {
                if let Some(g) = s {
                    continued.push((r, g - parent_start));
                }
            }
            continued_offset.push(continued.len());
            let parent_width = node.parent.map(|p| offset[p + 1] - offset[p]);
            identity.push(
                parent_width == Some(node.source.len())
                    && node.source.iter().enumerate().all(|(r, s)| *s == Some(r)),
            );
        }
        let width = source.len();
        let largest = nodes.iter().map(|n| n.source.len()).max().unwrap_or(0);
        Ok(Articulated {
            parent: nodes.iter().map(|n| n.parent).collect(),
            offset,
            source,
            continued,
            continued_offset,
            identity,
            block,
            articulated: vec![0.0; inertia.len()],
            inertia,
            bias: vec![0.0; width],
            projected: vec![0.0; width],
            pivot: vec![0.0; nodes.len()],
            reduced: vec![0.0; nodes.len()],
            acceleration: vec![0.0; width],
            scratch: vec![0.0; largest * largest + 2 * largest],
        })
    }

    /// How many nodes (coordinates) the tree has.
    #[must_use]
    pub fn len(&self) -> usize {
        self.parent.len()
    }

    /// Whether the tree has no node.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.parent.is_empty()
    }

    /// How many velocity components all nodes carry together (`Σ d_j`): the length of the
    /// per-component slices that [`Articulated::solve`] takes.
    #[must_use]
    pub fn width(&self) -> usize {
        self.source.len()
    }

    /// Node `j`'s number of components.
    fn dimension(&self, j: usize) -> usize {
        self.offset[j + 1] - self.offset[j]
    }

    /// The accelerations `q̈` (into `accelerations`, one per node) from `S` (`motion`), `c`
    /// (`bias_acceleration`), `b` (`bias_force`), each [`Articulated::width`] long in node
    /// order, and `τ` (`forces`, one per node).
    ///
    /// # Errors
    /// [`LinearError::Singular`] naming the first node (from the leaves) whose pivot
    /// `D_j = Sᵀ Iᴬ S` is not positive or not finite: `M` is singular or not positive definite
    /// there (or the numbers are not finite).
    pub fn solve(
        &mut self,
        motion: &[f64],
        bias_acceleration: &[f64],
        bias_force: &[f64],
        forces: &[f64],
        accelerations: &mut [f64],
    ) -> Result<(), LinearError> {
        let given = Given {
            motion,
            bias_acceleration,
            bias_force,
            forces,
        };
        for j in (0..self.len()).rev() {
            let step = by_dimension!(
                self,
                self.dimension(j),
                eliminate_fixed,
                eliminate,
                j,
                &given
            );
            if step.is_err() {
                // Children of unfinished nodes left their sums behind: the next solve starts
                // from zero.
                self.articulated.fill(0.0);
                self.bias.fill(0.0);
                return step;
            }
        }
        for (j, acceleration) in accelerations.iter_mut().enumerate().take(self.len()) {
            *acceleration =
                by_dimension!(self, self.dimension(j), advance_fixed, advance, j, &given);
        }
        Ok(())
    }

    /// Node `j`'s continued components, `(component, parent's component)`.
    fn continued_of(&self, j: usize) -> &[(usize, usize)] {
        &self.continued[self.continued_offset[j]..self.continued_offset[j + 1]]
    }

    /// The backward step at a node of `D` components: its pivot and reduced force, and its
    /// articulated inertia and bias carried to its parent (see the module doc).
    fn eliminate_fixed<const D: usize>(
        &mut self,
        j: usize,
        given: &Given,
    ) -> Result<(), LinearError> {
        let (o, b) = (self.offset[j], self.block[j]);
        let s: [f64; D] = load(&given.motion[o..]);
        let c: [f64; D] = load(&given.bias_acceleration[o..]);
        let mut inertia = [[0.0; D]; D];
        {
            let own = &mut self.articulated[b..b + D * D];
            let w = &self.inertia[b..b + D * D];
            for (r, row) in inertia.iter_mut().enumerate() {
                for (k, x) in row.iter_mut().enumerate() {
                    *x = w[r * D + k] + own[r * D + k];
                }
            }
            own.fill(0.0);
        }
        let mut bias: [f64; D] = load(&given.bias_force[o..]);
        let carried = &mut self.bias[o..o + D];
        for (x, y) in bias.iter_mut().zip(carried.iter()) {
            *x += y;
        }
        carried.fill(0.0);
        let (mut u, mut ic) = ([0.0; D], [0.0; D]);
        for (r, row) in inertia.iter().enumerate() {
            for (k, &w) in row.iter().enumerate() {
                u[r] += w * s[k];
                ic[r] += w * c[k];
            }
        }
        let mut pivot = 0.0;
        let mut reduced = given.forces[j];
        for r in 0..D {
            pivot += s[r] * u[r];
            reduced -= s[r] * bias[r] + u[r] * c[r];
        }
        if !(pivot > 0.0 && pivot.is_finite()) {
            return Err(LinearError::Singular { column: j });
        }
        self.projected[o..o + D].copy_from_slice(&u);
        self.pivot[j] = pivot;
        self.reduced[j] = reduced;
        let Some(p) = self.parent[j] else {
            return Ok(());
        };
        let step = reduced / pivot;
        // pᵃ = pᴬ + Iᴬ c + U u / D and Iᵃ = Iᴬ − U Uᵀ / D, carried to the parent.
        let out: [f64; D] = std::array::from_fn(|r| bias[r] + ic[r] + u[r] * step);
        for (row, &ur) in inertia.iter_mut().zip(&u) {
            let scaled = ur / pivot;
            for (x, &uk) in row.iter_mut().zip(&u) {
                *x -= scaled * uk;
            }
        }
        let (po, pb) = (self.offset[p], self.block[p]);
        if self.identity[j] {
            let target = &mut self.articulated[pb..pb + D * D];
            for (x, y) in self.bias[po..po + D].iter_mut().zip(&out) {
                *x += y;
            }
            for (r, row) in inertia.iter().enumerate() {
                for (k, x) in row.iter().enumerate() {
                    target[r * D + k] += x;
                }
            }
        } else {
            let pd = self.dimension(p);
            let continued = &self.continued[self.continued_offset[j]..self.continued_offset[j + 1]];
            for &(r, sr) in continued {
                self.bias[po + sr] += out[r];
                for &(k, sk) in continued {
                    self.articulated[pb + sr * pd + sk] += inertia[r][k];
                }
            }
        }
        Ok(())
    }

    /// The backward step at a node of any number of components, as
    /// [`Articulated::eliminate_fixed`] with the block in the scratch buffer.
    fn eliminate(&mut self, j: usize, given: &Given) -> Result<(), LinearError> {
        let (o, d, b) = (self.offset[j], self.dimension(j), self.block[j]);
        if d == 0 {
            // A coordinate that moves no mass: nothing to pivot on.
            return Err(LinearError::Singular { column: j });
        }
        let s = &given.motion[o..o + d];
        let c = &given.bias_acceleration[o..o + d];
        let (inertia, rest) = self.scratch.split_at_mut(d * d);
        let (bias, rest) = rest.split_at_mut(d);
        let ic = &mut rest[..d];
        let own = &mut self.articulated[b..b + d * d];
        for ((x, w), a) in inertia
            .iter_mut()
            .zip(&self.inertia[b..b + d * d])
            .zip(&*own)
        {
            *x = w + a;
        }
        own.fill(0.0);
        for ((x, g), carried) in bias
            .iter_mut()
            .zip(&given.bias_force[o..o + d])
            .zip(&mut self.bias[o..o + d])
        {
            *x = g + *carried;
            *carried = 0.0;
        }
        let mut pivot = 0.0;
        let mut reduced = given.forces[j];
        for r in 0..d {
            let row = &inertia[r * d..(r + 1) * d];
            let (mut u, mut icr) = (0.0, 0.0);
            for k in 0..d {
                u += row[k] * s[k];
                icr += row[k] * c[k];
            }
            self.projected[o + r] = u;
            ic[r] = icr;
            pivot += s[r] * u;
            reduced -= s[r] * bias[r] + u * c[r];
        }
        if !(pivot > 0.0 && pivot.is_finite()) {
            return Err(LinearError::Singular { column: j });
        }
        self.pivot[j] = pivot;
        self.reduced[j] = reduced;
        let Some(p) = self.parent[j] else {
            return Ok(());
        };
        let (po, pd, pb) = (
            self.offset[p],
            self.offset[p + 1] - self.offset[p],
            self.block[p],
        );
        let u = &self.projected[o..o + d];
        let step = reduced / pivot;
        let continued = &self.continued[self.continued_offset[j]..self.continued_offset[j + 1]];
        for &(r, sr) in continued {
            self.bias[po + sr] += bias[r] + ic[r] + u[r] * step;
            let scaled = u[r] / pivot;
            for &(k, sk) in continued {
                self.articulated[pb + sr * pd + sk] += inertia[r * d + k] - scaled * u[k];
            }
        }
        Ok(())
    }

    /// The forward step at a node of `D` components: `q̈_j` from the parent's accelerations,
    /// and node `j`'s.
    fn advance_fixed<const D: usize>(&mut self, j: usize, given: &Given) -> f64 {
        let o = self.offset[j];
        let mut gathered = [0.0; D];
        if let Some(p) = self.parent[j] {
            let po = self.offset[p];
            if self.identity[j] {
                gathered.copy_from_slice(&self.acceleration[po..po + D]);
            } else {
                for &(r, sr) in self.continued_of(j) {
                    gathered[r] = self.acceleration[po + sr];
                }
            }
        }
        let mut reduced = self.reduced[j];
        let projected: [f64; D] = load(&self.projected[o..]);
        for (u, g) in projected.iter().zip(&gathered) {
            reduced -= u * g;
        }
        let x = reduced / self.pivot[j];
        let s: [f64; D] = load(&given.motion[o..]);
        let c: [f64; D] = load(&given.bias_acceleration[o..]);
        let mut acceleration = [0.0; D];
        for (r, a) in acceleration.iter_mut().enumerate() {
            *a = gathered[r] + s[r] * x + c[r];
        }
        self.acceleration[o..o + D].copy_from_slice(&acceleration);
        x
    }

    /// The forward step at a node of any number of components.
    fn advance(&mut self, j: usize, given: &Given) -> f64 {
        let (o, d) = (self.offset[j], self.dimension(j));
        let gathered = &mut self.scratch[..d];
        gathered.fill(0.0);
        if let Some(p) = self.parent[j] {
            let po = self.offset[p];
            for &(r, sr) in &self.continued[self.continued_offset[j]..self.continued_offset[j + 1]]
            {
                gathered[r] = self.acceleration[po + sr];
            }
        }
        let mut reduced = self.reduced[j];
        for (u, g) in self.projected[o..o + d].iter().zip(&*gathered) {
            reduced -= u * g;
        }
        let x = reduced / self.pivot[j];
        let own = self.acceleration[o..o + d]
            .iter_mut()
            .zip(&given.motion[o..o + d])
            .zip(&given.bias_acceleration[o..o + d]);
        for (((a, s), c), g) in own.zip(&*gathered) {
            *a = g + s * x + c;
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve_in_place;

    /// A planar chain of `n` unit point masses on unit rods at absolute angles `θ`: node `j`
    /// carries the velocity `(ẋ, ẏ)` of every mass from `j` on, `S_j = (cos θ_j, sin θ_j)`.
    fn chain(n: usize) -> Articulated {
        let nodes: Vec<ArticulatedNode> = (0..n)
            .map(|j| ArticulatedNode {
                parent: j.checked_sub(1),
                source: if j == 0 {
                    vec![None, None]
                } else {
                    vec![Some(0), Some(1)]
                },
                inertia: vec![1.0, 0.0, 0.0, 1.0],
            })
            .collect();
        match Articulated::new(&nodes) {
            Ok(tree) => tree,
            Err(error) => panic!("a valid chain was refused: {error}"),
        }
    }

    #[test]
    fn a_chain_of_masses_solves_its_dense_mass_matrix() {
        let n = 6;
        let theta: Vec<f64> = (0..n).map(|j| 0.3 + 0.7 * j as f64).collect();
        let motion: Vec<f64> = theta.iter().flat_map(|t| [t.cos(), t.sin()]).collect();
        // M_ij = Σ_{k ≥ max(i,j)} m_k S_i·S_j = (n − max(i,j)) cos(θ_i − θ_j).
        let mut mass = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                mass[i * n + j] = (n - i.max(j)) as f64 * (theta[i] - theta[j]).cos();
            }
        }
        let forces: Vec<f64> = (0..n).map(|j| 1.0 - 0.4 * j as f64).collect();
        let mut expected = forces.clone();
        assert!(solve_in_place(n, &mut mass, &mut expected).is_ok());
        let zero = vec![0.0; 2 * n];
        let mut found = vec![0.0; n];
        let mut tree = chain(n);
        assert!(tree
            .solve(&motion, &zero, &zero, &forces, &mut found)
            .is_ok());
        for (x, y) in found.iter().zip(&expected) {
            assert!(
                (x - y).abs() <= 1e-12 * (1.0 + y.abs()),
                "{found:?} vs {expected:?}"
            );
        }
    }

    /// A deterministic stream of numbers in (−1, 1).
    fn stream(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed;
        move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        }
    }

    /// `q̈` of a tree by the dense route: `J_k` (node `k`'s components as a function of `q̇`)
    /// from the gathers, `M = Σ J_kᵀ W_k J_k`, `f = τ − Σ J_kᵀ (W_k a⁰_k + b_k)` with `a⁰` the
    /// accelerations at `q̈ = 0`.
    fn dense_solution(
        nodes: &[ArticulatedNode],
        motion: &[f64],
        bias_acceleration: &[f64],
        bias_force: &[f64],
        forces: &[f64],
    ) -> Vec<f64> {
        let n = nodes.len();
        let mut start = vec![0];
        for node in nodes {
            start.push(start[start.len() - 1] + node.source.len());
        }
        let mut jacobian: Vec<Vec<f64>> = Vec::new(); // one row of n per component
        let mut rest: Vec<f64> = Vec::new(); // a⁰, one per component
        for (j, node) in nodes.iter().enumerate() {
            for (r, s) in node.source.iter().enumerate() {
                let g = start[j] + r;
                let (mut row, mut a) = (vec![0.0; n], bias_acceleration[g]);
                if let (Some(p), Some(s)) = (node.parent, s) {
                    row.clone_from(&jacobian[start[p] + s]);
                    a += rest[start[p] + s];
                }
                row[j] += motion[g];
                jacobian.push(row);
                rest.push(a);
            }
        }
        let mut mass = vec![0.0; n * n];
        let mut rhs = forces.to_vec();
        for (j, node) in nodes.iter().enumerate() {
            let d = node.source.len();
            for r in 0..d {
                let mut load = bias_force[start[j] + r];
                for k in 0..d {
                    let w = node.inertia[r * d + k];
                    load += w * rest[start[j] + k];
                    for a in 0..n {
                        for b in 0..n {
                            mass[a * n + b] +=
                                jacobian[start[j] + r][a] * w * jacobian[start[j] + k][b];
                        }
                    }
                }
                for a in 0..n {
                    rhs[a] -= jacobian[start[j] + r][a] * load;
                }
            }
        }
        assert!(solve_in_place(n, &mut mass, &mut rhs).is_ok());
        rhs
    }

    #[test]
    fn every_node_dimension_and_gather_matches_the_dense_solve() {
        // Dimensions 1 to 12 (the compiled steps and the general one), nodes that continue
        // their parent one for one and nodes that gather some components twice or not at all,
        // a branching tree, bias terms everywhere.
        let mut next = stream(7);
        let dims = [2, 2, 3, 12, 12, 9, 9, 4, 1, 6, 10, 5, 5, 7, 8];
        let parents = [
            None,
            Some(0),
            Some(1),
            Some(2),
            Some(3),
            Some(4),
            Some(5),
            Some(5),
        ];
        let mut nodes: Vec<ArticulatedNode> = Vec::new();
        for (j, &d) in dims.iter().enumerate() {
            let parent = parents
                .get(j)
                .copied()
                .unwrap_or_else(|| Some(j - 1 - j % 2));
            let source = (0..d)
                .map(|r| {
                    let pd = parent.map_or(0, |p| dims[p]);
                    match parent {
                        Some(_) if pd == d && j % 3 != 0 => Some(r),
                        Some(_) if r % 3 != 2 => Some((r * 5 + 1) % pd),
                        _ => None,
                    }
                })
                .collect();
            let a: Vec<f64> = (0..d * d).map(|_| next()).collect();
            let mut inertia = vec![0.0; d * d];
            for r in 0..d {
                for k in 0..d {
                    inertia[r * d + k] = (0..d).map(|i| a[i * d + r] * a[i * d + k]).sum::<f64>()
                        + if r == k { 1.0 } else { 0.0 };
                }
            }
            nodes.push(ArticulatedNode {
                parent,
                source,
                inertia,
            });
        }
        let width: usize = dims.iter().sum();
        let n = dims.len();
        let mut tree = Articulated::new(&nodes).expect("a valid tree");
        assert!(tree.identity.iter().any(|&x| x) && tree.identity.iter().any(|&x| !x));
        for _ in 0..3 {
            let motion: Vec<f64> = (0..width).map(|_| next()).collect();
            let bias_acceleration: Vec<f64> = (0..width).map(|_| next()).collect();
            let bias_force: Vec<f64> = (0..width).map(|_| next()).collect();
            let forces: Vec<f64> = (0..n).map(|_| next()).collect();
            let expected =
                dense_solution(&nodes, &motion, &bias_acceleration, &bias_force, &forces);
            let mut found = vec![0.0; n];
            assert!(tree
                .solve(
                    &motion,
                    &bias_acceleration,
                    &bias_force,
                    &forces,
                    &mut found
                )
                .is_ok());
            let scale = expected.iter().fold(1.0f64, |s, x| s.max(x.abs()));
            for (x, y) in found.iter().zip(&expected) {
                assert!((x - y).abs() <= 1e-10 * scale, "{found:?} vs {expected:?}");
            }
        }
    }

    #[test]
    fn a_failed_solve_leaves_nothing_behind() {
        let n = 4;
        let mut tree = chain(n);
        let theta = [0.3, 1.0, 1.7, 2.4];
        let motion: Vec<f64> = theta
            .iter()
            .flat_map(|t: &f64| [t.cos(), t.sin()])
            .collect();
        let zero = vec![0.0; 2 * n];
        let forces = [1.0, -0.5, 0.25, 2.0];
        let mut before = vec![0.0; n];
        assert!(tree
            .solve(&motion, &zero, &zero, &forces, &mut before)
            .is_ok());
        // Node 1 without motion: the leaves' sums are in its parent's buffers when it fails.
        let mut broken = motion.clone();
        broken[2] = 0.0;
        broken[3] = 0.0;
        let mut out = vec![0.0; n];
        assert_eq!(
            tree.solve(&broken, &zero, &zero, &forces, &mut out),
            Err(LinearError::Singular { column: 1 })
        );
        let mut after = vec![0.0; n];
        assert!(tree
            .solve(&motion, &zero, &zero, &forces, &mut after)
            .is_ok());
        assert_eq!(before, after);
    }

    #[test]
    fn a_node_without_inertia_is_singular() {
        let nodes = [ArticulatedNode {
            parent: None,
            source: vec![None],
            inertia: vec![0.0],
        }];
        let mut tree = Articulated::new(&nodes).expect("a valid one-node tree");
        let mut out = [0.0];
        assert_eq!(
            tree.solve(&[1.0], &[0.0], &[0.0], &[1.0], &mut out),
            Err(LinearError::Singular { column: 0 })
        );
    }

    #[test]
    fn malformed_trees_are_refused() {
        let node = |parent, source: Vec<Option<usize>>, entries| ArticulatedNode {
            parent,
            source,
            inertia: vec![1.0; entries],
        };
        assert_eq!(
            Articulated::new(&[node(Some(0), vec![None], 1)]).err(),
            Some(ArticulatedError::ParentNotBefore { node: 0 })
        );
        assert_eq!(
            Articulated::new(&[node(None, vec![Some(0)], 1)]).err(),
            Some(ArticulatedError::SourceOutOfRange {
                node: 0,
                component: 0
            })
        );
        assert_eq!(
            Articulated::new(&[node(None, vec![None, None], 3)]).err(),
            Some(ArticulatedError::InertiaShape {
                node: 0,
                expected: 4,
                found: 3
            })
        );
    }
}
