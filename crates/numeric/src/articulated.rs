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
    /// Node `j`'s `d_j × d_j` block starts at `block[j]`.
    block: Vec<usize>,
    inertia: Vec<f64>,
    articulated: Vec<f64>,
    bias: Vec<f64>,
    projected: Vec<f64>,
    pivot: Vec<f64>,
    reduced: Vec<f64>,
    acceleration: Vec<f64>,
    scratch: Vec<f64>,
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
        for (j, node) in nodes.iter().enumerate() {
            let parent_start = node.parent.map_or(0, |p| offset[p]);
            for (r, s) in source[offset[j]..offset[j + 1]].iter().enumerate() {
                if let Some(g) = s {
                    continued.push((r, g - parent_start));
                }
            }
            continued_offset.push(continued.len());
        }
        let width = source.len();
        let largest = nodes.iter().map(|n| n.source.len()).max().unwrap_or(0);
        Ok(Articulated {
            parent: nodes.iter().map(|n| n.parent).collect(),
            offset,
            source,
            continued,
            continued_offset,
            block,
            articulated: inertia.clone(),
            inertia,
            bias: vec![0.0; width],
            projected: vec![0.0; width],
            pivot: vec![0.0; nodes.len()],
            reduced: vec![0.0; nodes.len()],
            acceleration: vec![0.0; width],
            scratch: vec![0.0; largest],
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
        self.articulated.copy_from_slice(&self.inertia);
        let width = self.width();
        self.bias.copy_from_slice(&bias_force[..width]);
        for j in (0..self.len()).rev() {
            self.eliminate(j, motion, bias_acceleration, forces[j])?;
        }
        for (j, acceleration) in accelerations.iter_mut().enumerate().take(self.len()) {
            *acceleration = self.advance(j, motion, bias_acceleration);
        }
        Ok(())
    }

    /// The backward step at node `j`: its pivot and reduced force, and its articulated
    /// inertia and bias carried to its parent.
    fn eliminate(
        &mut self,
        j: usize,
        motion: &[f64],
        bias_acceleration: &[f64],
        force: f64,
    ) -> Result<(), LinearError> {
        let (o, d, b) = (
            self.offset[j],
            self.offset[j + 1] - self.offset[j],
            self.block[j],
        );
        let s = &motion[o..o + d];
        let c = &bias_acceleration[o..o + d];
        if d == 0 {
            // A coordinate that moves no mass: nothing to pivot on.
            return Err(LinearError::Singular { column: j });
        }
        let (head, tail) = self.articulated.split_at_mut(b);
        let own = &tail[..d * d];
        let mut pivot = 0.0;
        let mut reduced = force;
        let rows = own
            .chunks_exact(d)
            .zip(&mut self.projected[o..o + d])
            .zip(&mut self.scratch[..d])
            .zip(s.iter().zip(c))
            .zip(&self.bias[o..o + d]);
        for ((((row, projected), scratch), (&sr, &cr)), &br) in rows {
            let (mut u, mut ic) = (0.0, 0.0);
            for ((&w, &sk), &ck) in row.iter().zip(s).zip(c) {
                u += w * sk;
                ic += w * ck;
            }
            *projected = u;
            pivot += sr * u;
            reduced -= sr * br + u * cr;
            // pᴬ + Iᴬ c, completed below once u is known.
            *scratch = br + ic;
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
        let parent_block = &mut head[pb..pb + pd * pd];
        let u = &self.projected[o..o + d];
        let step = reduced / pivot;
        let continued = &self.continued[self.continued_offset[j]..self.continued_offset[j + 1]];
        for &(r, sr) in continued {
            self.bias[po + sr] += self.scratch[r] + u[r] * step;
            let scaled = u[r] / pivot;
            let row = &own[r * d..(r + 1) * d];
            let target = &mut parent_block[sr * pd..(sr + 1) * pd];
            for &(k, sk) in continued {
                target[sk] += row[k] - scaled * u[k];
            }
        }
        Ok(())
    }

    /// The forward step at node `j`: `q̈_j` from the parent's accelerations, and node `j`'s.
    fn advance(&mut self, j: usize, motion: &[f64], bias_acceleration: &[f64]) -> f64 {
        let (o, d) = (self.offset[j], self.offset[j + 1] - self.offset[j]);
        let mut reduced = self.reduced[j];
        self.scratch[..d].fill(0.0);
        if let Some(p) = self.parent[j] {
            let po = self.offset[p];
            for &(r, sr) in &self.continued[self.continued_offset[j]..self.continued_offset[j + 1]]
            {
                let gathered = self.acceleration[po + sr];
                self.scratch[r] = gathered;
                reduced -= self.projected[o + r] * gathered;
            }
        }
        let x = reduced / self.pivot[j];
        for r in 0..d {
            self.acceleration[o + r] =
                self.scratch[r] + motion[o + r] * x + bias_acceleration[o + r];
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
