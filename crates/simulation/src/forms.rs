//! The compiled equations as first-order systems for the integrators:
//! [`SecondOrder`] with state `y = (q, q̇)`, solving `M q̈ = f` (or the KKT system
//! `[M Aᵀ; A 0] [q̈; λ] = [f; b]` with constraints) at each evaluation and projecting onto
//! `Φ = 0`, `c = 0` after each step. Rows of `A` that depend on others at the state (a rolling
//! contact's normal row, implied by the contact staying in the plane) are left out of both
//! solves: [`independent_rows`] picks a largest independent subset by pivoted Gram–Schmidt
//! (a QR factorisation of `Aᵀ` with column pivoting), and the rows left out get no multiplier; [`Canonical`] with state `y = (q, p)`, Hamilton's
//! equations `q̇ = M⁻¹(p − p₀)`, `ṗ = ∂L/∂q + Q`, for the symplectic method.

use numeric::{cholesky_solve_in_place, solve_in_place, LinearError, OdeSystem, RhsError};

use crate::compiled::{Compiled, TreeRhs};

fn singular(error: LinearError) -> RhsError {
    match error {
        LinearError::Singular { column } => RhsError::SingularMatrix { column },
        _ => RhsError::NotFinite,
    }
}

/// `y = (q, q̇)`.
pub(crate) struct SecondOrder<'c> {
    compiled: &'c mut Compiled,
    matrix: Vec<f64>,
    vector: Vec<f64>,
    gram: Vec<f64>,
    multipliers: Vec<f64>,
    /// Scratch for [`independent_rows`]: the rows being orthogonalised.
    work: Vec<f64>,
    /// `0..m`, the rows to choose from.
    rows_all: Vec<usize>,
    /// The rows of `A` kept at the current state (positions in the list chosen from).
    selected: Vec<usize>,
}

/// Rows whose part orthogonal to the rows already kept is smaller than this, relative to the
/// largest row, depend on them. Far above rounding (1e-16 relative), far below the
/// conditioning of a real mechanism away from its singular configurations.
const DEPENDENT: f64 = 1e-10;

/// Picks from `rows` of `a` (row-major, `n` columns) a largest subset of linearly independent
/// rows and leaves their positions in `rows` in `selected`, in order: pivoted Gram–Schmidt, each step keeping the
/// row with the largest part orthogonal to those kept, until what is left is below
/// [`DEPENDENT`] times the largest row. `work` holds `rows.len() × n` numbers.
pub(crate) fn independent_rows(
    a: &[f64],
    n: usize,
    rows: &[usize],
    work: &mut Vec<f64>,
    selected: &mut Vec<usize>,
) {
    let k = rows.len();
    work.clear();
    for &r in rows {
        work.extend_from_slice(&a[r * n..(r + 1) * n]);
    }
    let norm = |w: &[f64], i: usize| w[i * n..(i + 1) * n].iter().map(|x| x * x).sum::<f64>();
    let largest = (0..k).map(|i| norm(work, i)).fold(0.0f64, f64::max).sqrt();
    let mut kept = vec![false; k];
    selected.clear();
    if largest == 0.0 || !largest.is_finite() {
        // Nothing to orthogonalise (every row vanishes here), or numbers that cannot be
        // judged: keep every row and let the solve report what it finds.
        selected.extend(0..k);
        return;
    }
    loop {
        let pivot = (0..k)
            .filter(|&i| !kept[i])
            .map(|i| (i, norm(work, i)))
            .max_by(|x, y| x.1.total_cmp(&y.1));
        let Some((p, size)) = pivot else { break };
        if size.sqrt() <= DEPENDENT * largest {
            break;
        }
        kept[p] = true;
        let (size, unit) = (size.sqrt(), p * n);
        for c in 0..n {
            work[unit + c] /= size;
        }
        for i in (0..k).filter(|&i| !kept[i]) {
            let dot: f64 = (0..n).map(|c| work[i * n + c] * work[unit + c]).sum();
            for c in 0..n {
                work[i * n + c] -= dot * work[unit + c];
            }
        }
    }
    selected.extend((0..k).filter(|&i| kept[i]));
}

impl<'c> SecondOrder<'c> {
    pub(crate) fn new(compiled: &'c mut Compiled) -> Self {
        let size = compiled.n + compiled.m;
        let (n, m) = (compiled.n, compiled.m);
        SecondOrder {
            compiled,
            matrix: vec![0.0; size * size],
            vector: vec![0.0; size],
            gram: vec![0.0; m * m],
            multipliers: vec![0.0; m],
            work: Vec::with_capacity(m * n),
            selected: Vec::with_capacity(m),
            rows_all: Vec::with_capacity(m),
        }
    }

    /// Solves `(B Bᵀ) μ = r` and returns `Bᵀ μ` in `correction`, with `B` the rows of `A`
    /// (n columns) among `rows` that are independent at this state and `r` their residuals
    /// (`residual[i]` belongs to `rows[i]`): the least-norm correction that removes the
    /// residual. Dependent rows are left out, which makes `B Bᵀ` regular; their residuals
    /// go with the others' where the constraints are consistent.
    fn least_norm(
        &mut self,
        a: &[f64],
        rows: &[usize],
        residual: &[f64],
        correction: &mut [f64],
    ) -> Result<(), RhsError> {
        let n = self.compiled.n;
        independent_rows(a, n, rows, &mut self.work, &mut self.selected);
        let k = self.selected.len();
        for (i, &pi) in self.selected.iter().enumerate() {
            let ri = rows[pi];
            for (j, &pj) in self.selected.iter().enumerate() {
                let rj = rows[pj];
                self.gram[i * k + j] = (0..n).map(|c| a[ri * n + c] * a[rj * n + c]).sum();
            }
            self.multipliers[i] = residual[pi];
        }
        solve_in_place(k, &mut self.gram[..k * k], &mut self.multipliers[..k])
            .map_err(|_| RhsError::ProjectionFailed)?;
        for (c, value) in correction.iter_mut().enumerate() {
            *value = self
                .selected
                .iter()
                .enumerate()
                .map(|(i, &p)| a[rows[p] * n + c] * self.multipliers[i])
                .sum();
        }
        Ok(())
    }

    /// The multipliers `λ` of `M q̈ + Aᵀλ = f`, `A q̈ = b` at `(t, y)`, one per row of `A`;
    /// rows that depend on others at the state get 0 (the reaction `Aᵀλ` is the same).
    pub(crate) fn multipliers(&mut self, t: f64, y: &[f64]) -> Result<Vec<f64>, RhsError> {
        let n = self.compiled.n;
        let mut accelerations = vec![0.0; 2 * n];
        self.rhs(t, y, &mut accelerations)?;
        let mut lambda = vec![0.0; self.compiled.m];
        for (k, &row) in self.selected.iter().enumerate() {
            lambda[row] = self.vector[n + k];
        }
        Ok(lambda)
    }

    fn constraint_rows(&mut self) -> Vec<f64> {
        let (n, m) = (self.compiled.n, self.compiled.m);
        let c = &mut *self.compiled;
        // A model with constraints has no tree, so its dense tape is always compiled.
        let Some(dynamics) = c.dynamics.as_mut() else {
            return vec![0.0; m * n];
        };
        let out = dynamics.eval(&c.inputs);
        out[n * n + n..n * n + n + m * n].to_vec()
    }

    /// `q̈` (and the multipliers) by the dense solve of `M q̈ = f` or the KKT system, at the
    /// state in the input buffer, into `self.vector`.
    fn dense(&mut self) -> Result<(), RhsError> {
        let (n, m) = (self.compiled.n, self.compiled.m);
        let c = &mut *self.compiled;
        // The dense tape is missing only where the right-hand side goes by the tree, which
        // comes here only to name a singular pivot; the caller then reports the tree's.
        let Some(dynamics) = c.dynamics.as_mut() else {
            return Err(RhsError::NotFinite);
        };
        let out = dynamics.eval(&c.inputs);
        let (mass, rest) = out.split_at(n * n);
        let (forcing, rest) = rest.split_at(n);
        let (a, b) = rest.split_at(m * n);
        if m == 0 {
            // A mass matrix is symmetric positive definite where the model is regular:
            // Cholesky first, LU (which also names the singular column) when that fails.
            self.matrix.copy_from_slice(mass);
            self.vector.copy_from_slice(forcing);
            if cholesky_solve_in_place(n, &mut self.matrix, &mut self.vector).is_err() {
                self.matrix.copy_from_slice(mass);
                self.vector[..n].copy_from_slice(forcing);
                solve_in_place(n, &mut self.matrix, &mut self.vector).map_err(singular)?;
            }
        } else {
            // Only independent rows enter the KKT matrix, which is singular otherwise; the
            // rows left out hold wherever the kept ones do (they are combinations of them).
            self.rows_all.clear();
            self.rows_all.extend(0..m);
            independent_rows(a, n, &self.rows_all, &mut self.work, &mut self.selected);
            let size = n + self.selected.len();
            for i in 0..n {
                let row = &mut self.matrix[i * size..(i + 1) * size];
                row[..n].copy_from_slice(&mass[i * n..(i + 1) * n]);
                for (k, &r) in self.selected.iter().enumerate() {
                    row[n + k] = a[r * n + i];
                }
                self.vector[i] = forcing[i];
            }
            for (k, &r) in self.selected.iter().enumerate() {
                let row = (n + k) * size;
                self.matrix[row..row + n].copy_from_slice(&a[r * n..(r + 1) * n]);
                self.matrix[row + n..row + size].fill(0.0);
                self.vector[n + k] = b[r];
            }
            solve_in_place(
                size,
                &mut self.matrix[..size * size],
                &mut self.vector[..size],
            )
            .map_err(singular)?;
        }
        Ok(())
    }

    /// `q̈` by the tree's O(n) elimination at the state in the input buffer, into
    /// `self.vector`; `None` without a tree.
    fn articulated(&mut self) -> Option<Result<(), LinearError>> {
        let n = self.compiled.n;
        let c = &mut *self.compiled;
        let TreeRhs {
            evaluator,
            solver,
            width,
            ..
        } = c.tree.as_mut()?;
        let w = *width;
        let out = evaluator.eval(&c.inputs);
        let (motion, rest) = out.split_at(w);
        let (bias_acceleration, rest) = rest.split_at(w);
        let (bias_force, forces) = rest.split_at(w);
        Some(solver.solve(
            motion,
            bias_acceleration,
            bias_force,
            forces,
            &mut self.vector[..n],
        ))
    }

    /// `q̈` at `(t, y)` by the dense solve and by the tree (`None` without one or where the
    /// tree's elimination fails): the two routes side by side, for tests and benchmarks.
    pub(crate) fn both_routes(
        &mut self,
        t: f64,
        y: &[f64],
    ) -> (Result<Vec<f64>, RhsError>, Option<Vec<f64>>) {
        let n = self.compiled.n;
        self.compiled.inputs[..2 * n].copy_from_slice(y);
        self.compiled.inputs[2 * n] = t;
        let tree = match self.articulated() {
            Some(Ok(())) => Some(self.vector[..n].to_vec()),
            _ => None,
        };
        let dense = self.dense().map(|()| self.vector[..n].to_vec());
        (dense, tree)
    }
}

/// The `k`-th of the states at which the routes are checked, spread over the configuration
/// space, and its time.
fn sample_state(n: usize, k: u32) -> (Vec<f64>, f64) {
    let y = (0..2 * n)
        .map(|i| (1.7 * f64::from(k + 1) + 0.9 * i as f64).sin() * if i < n { 2.0 } else { 1.0 })
        .collect();
    (y, 0.25 * f64::from(k))
}

/// Whether the tree's `q̈` agrees with the dense solve's at three states spread over the
/// configuration space (to 1e-8 of the largest), where both can be solved; at least two must
/// be. The check is numeric so that it holds whatever route derived `M` and `f`; an
/// analytic function that agreed at these states and differed elsewhere would be a
/// coincidence of measure zero.
pub(crate) fn tree_agrees(compiled: &mut Compiled) -> bool {
    let n = compiled.n;
    let saved = compiled.inputs[..=2 * n].to_vec();
    let mut system = SecondOrder::new(compiled);
    let mut compared = 0;
    let mut agree = true;
    for k in 0..3u32 {
        let (y, t) = sample_state(n, k);
        if let (Ok(dense), Some(tree)) = system.both_routes(t, &y) {
            let scale = dense.iter().fold(1.0f64, |s, x| s.max(x.abs()));
            let error = dense
                .iter()
                .zip(&tree)
                .fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
            compared += 1;
            agree &= error <= 1e-8 * scale;
        }
    }
    system.compiled.inputs[..=2 * n].copy_from_slice(&saved);
    agree && compared >= 2
}

/// Whether the tree's `q̈` satisfies the model's own equations `M q̈ = f`, where the dense tape
/// was not compiled: at the states of [`tree_agrees`] (at least two solved), along two
/// directions `w` each, `wᵀ M q̈ = (T(q, w + q̈) − T(q, w − q̈)) / 2` from the kinetic energy's
/// expression (`T = ½ q̇ᵀ M q̇`) against `wᵀ f` from the forcing's, to 1e-8 of the terms' size.
/// `forcing` and `kinetic` take the input layout's symbols (`inputs`). Evaluating `n`
/// expressions and `T` costs a small part of compiling the `n²` entries of `M`, and a wrong
/// `q̈` passes only if its residual is orthogonal to every direction, a coincidence of
/// measure zero.
pub(crate) fn tree_satisfies(
    compiled: &mut Compiled,
    inputs: &[cas::Symbol],
    forcing: &[cas::Expr],
    kinetic: cas::Expr,
) -> bool {
    let n = compiled.n;
    let saved = compiled.inputs[..=2 * n].to_vec();
    let mut system = SecondOrder::new(compiled);
    let mut compared = 0;
    let mut agree = true;
    for k in 0..3u32 {
        let (y, t) = sample_state(n, k);
        system.compiled.set_state(&y[..n], &y[n..], t);
        if !matches!(system.articulated(), Some(Ok(()))) {
            continue;
        }
        let accelerations = &system.vector[..n];
        let mut values: std::collections::HashMap<cas::Symbol, f64> = inputs
            .iter()
            .copied()
            .zip(system.compiled.inputs.iter().copied())
            .collect();
        let forces: Option<Vec<f64>> = forcing
            .iter()
            .map(|e| e.eval(&|s| values.get(&s).copied()).ok())
            .collect();
        let Some(forces) = forces else {
            agree = false;
            break;
        };
        for direction in 0..2u32 {
            let w: Vec<f64> = (0..n)
                .map(|i| (2.3 * f64::from(2 * k + direction + 1) + 1.1 * i as f64).cos())
                .collect();
            let mut energy = |sign: f64| {
                for (i, rate) in inputs[n..2 * n].iter().enumerate() {
                    values.insert(*rate, w[i] + sign * accelerations[i]);
                }
                kinetic.eval(&|s| values.get(&s).copied()).ok()
            };
            let (Some(plus), Some(minus)) = (energy(1.0), energy(-1.0)) else {
                agree = false;
                break;
            };
            let work: f64 = w.iter().zip(&forces).map(|(a, b)| a * b).sum();
            let size = plus.abs()
                + minus.abs()
                + w.iter()
                    .zip(&forces)
                    .map(|(a, b)| (a * b).abs())
                    .sum::<f64>();
            agree &= ((plus - minus) / 2.0 - work).abs() <= 1e-8 * size;
        }
        compared += 1;
    }
    system.compiled.inputs[..=2 * n].copy_from_slice(&saved);
    agree && compared >= 2
}

impl OdeSystem for SecondOrder<'_> {
    fn dimension(&self) -> usize {
        2 * self.compiled.n
    }

    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        let n = self.compiled.n;
        self.compiled.inputs[..2 * n].copy_from_slice(y);
        self.compiled.inputs[2 * n] = t;
        // A pivot the tree cannot take (a singular or non-finite state) goes to the dense
        // solve, which names the singular column as it always has.
        let by_tree = self.compiled.tree.as_ref().is_some_and(|t| t.preferred);
        match by_tree.then(|| self.articulated()).flatten() {
            Some(Ok(())) => {}
            // Without the dense tape (the tree's route did not compile it) the tree's pivot
            // names the column.
            Some(Err(error)) if self.compiled.dynamics.is_none() => return Err(singular(error)),
            _ => self.dense()?,
        }
        dy[..n].copy_from_slice(&y[n..]);
        dy[n..].copy_from_slice(&self.vector[..n]);
        Ok(())
    }

    fn project(&mut self, t: f64, y: &mut [f64]) -> Result<bool, RhsError> {
        let (n, m) = (self.compiled.n, self.compiled.m);
        if m == 0 || !self.compiled.drift_known {
            return Ok(false);
        }
        let holonomic = self.compiled.holonomic.clone();
        let mut correction = vec![0.0; n];
        // Positions: Gauss–Newton on Φ(q) = 0 with the Jacobian Φ_q = A (holonomic rows).
        if !holonomic.is_empty() {
            let mut converged = false;
            for _ in 0..20 {
                self.compiled.set_state(&y[..n], &y[n..], t);
                let out = self.compiled.monitor.eval(&self.compiled.inputs);
                let phi: Vec<f64> = out[1..1 + holonomic.len()].to_vec();
                let scale = 1.0 + y[..n].iter().fold(0.0f64, |s, x| s.max(x.abs()));
                let a = self.constraint_rows();
                // Φ ≈ A δq: a residual is judged as the position error it stands for, so a
                // constraint whose terms are large where the motion has taken it (x³ + y² = l²
                // at x = −16) is not held to an absolute residual its own rounding exceeds.
                let converged_row = |(i, value): (usize, &f64)| {
                    let row = &a[holonomic[i] * n..(holonomic[i] + 1) * n];
                    let gradient = row.iter().map(|x| x * x).sum::<f64>().sqrt();
                    value.abs() <= 1e-14 * scale * gradient.max(1.0)
                };
                if phi.iter().enumerate().all(converged_row) {
                    converged = true;
                    break;
                }
                self.least_norm(&a, &holonomic, &phi, &mut correction)?;
                for (q, dq) in y[..n].iter_mut().zip(&correction) {
                    *q -= dq;
                }
            }
            if !converged {
                return Err(RhsError::ProjectionFailed);
            }
        }
        // Velocities: c = A q̇ + c₀ is affine in q̇, so one least-norm correction is exact.
        self.compiled.set_state(&y[..n], &y[n..], t);
        let hol = holonomic.len();
        let c: Vec<f64> =
            self.compiled.monitor.eval(&self.compiled.inputs)[1 + hol..1 + hol + m].to_vec();
        let a = self.constraint_rows();
        let all: Vec<usize> = (0..m).collect();
        self.least_norm(&a, &all, &c, &mut correction)?;
        for (v, dv) in y[n..].iter_mut().zip(&correction) {
            *v -= dv;
        }
        Ok(true)
    }

    fn event_count(&self) -> usize {
        self.compiled.event_count()
    }

    fn event_stops(&self, index: usize) -> bool {
        self.compiled.event_stops(index)
    }

    fn events(&mut self, t: f64, y: &[f64], g: &mut [f64]) {
        let n = self.compiled.n;
        let tape = self.compiled.tape_event_count();
        let c = &mut *self.compiled;
        c.inputs[..2 * n].copy_from_slice(y);
        c.inputs[2 * n] = t;
        if let Some(events) = c.events.as_mut() {
            let out = events.eval(&c.inputs);
            g[..tape].copy_from_slice(&out[..tape]);
        }
        if tape < g.len() {
            self.contact_events(t, y, &mut g[tape..]);
        }
    }
}

impl SecondOrder<'_> {
    /// The one-sided reactions evaluated numerically at `(t, y)` (NaN where the equations
    /// cannot be solved there).
    fn contact_events(&mut self, t: f64, y: &[f64], g: &mut [f64]) {
        let n = self.compiled.n;
        let mut derivative = vec![0.0; 2 * n];
        if self.rhs(t, y, &mut derivative).is_err() {
            g.fill(f64::NAN);
            return;
        }
        let mut lambda = vec![0.0; self.compiled.m];
        if self.compiled.m > 0 {
            for (k, &row) in self.selected.iter().enumerate() {
                lambda[row] = self.vector[n + k];
            }
        }
        let Some(contacts) = self.compiled.contacts.as_ref() else {
            return;
        };
        let values = contacts.evaluator.evaluate(&mechanics::ReactionState {
            t,
            positions: &y[..n],
            rates: &y[n..],
            accelerations: &derivative[n..],
            multipliers: &lambda,
            values: &contacts.values,
        });
        for (slot, (_, column)) in g.iter_mut().zip(&contacts.columns) {
            *slot = values.get(*column).copied().unwrap_or(f64::NAN);
        }
    }
}

/// `y = (q, p)`.
pub(crate) struct Canonical<'c> {
    compiled: &'c mut Compiled,
    matrix: Vec<f64>,
    velocity: Vec<f64>,
}

impl<'c> Canonical<'c> {
    pub(crate) fn new(compiled: &'c mut Compiled) -> Self {
        let n = compiled.n;
        Canonical {
            compiled,
            matrix: vec![0.0; n * n],
            velocity: vec![0.0; n],
        }
    }

    /// `q̇ = M⁻¹ (p − p₀)` at `(t, q, p)`, left in `self.velocity`.
    fn solve_velocity(&mut self, t: f64, y: &[f64]) -> Result<(), RhsError> {
        let n = self.compiled.n;
        let c = &mut *self.compiled;
        c.inputs[..n].copy_from_slice(&y[..n]);
        c.inputs[n..2 * n].fill(0.0);
        c.inputs[2 * n] = t;
        let Some((mass_momentum, _)) = c.canonical.as_mut() else {
            return Err(RhsError::NotFinite);
        };
        let out = mass_momentum.eval(&c.inputs);
        self.matrix.copy_from_slice(&out[..n * n]);
        for i in 0..n {
            self.velocity[i] = y[n + i] - out[n * n + i];
        }
        solve_in_place(n, &mut self.matrix, &mut self.velocity).map_err(singular)
    }

    /// The rates `q̇` of a canonical state.
    pub(crate) fn velocity(&mut self, t: f64, y: &[f64]) -> Result<Vec<f64>, RhsError> {
        self.solve_velocity(t, y)?;
        Ok(self.velocity.clone())
    }
}

impl OdeSystem for Canonical<'_> {
    fn dimension(&self) -> usize {
        2 * self.compiled.n
    }

    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
        let n = self.compiled.n;
        self.solve_velocity(t, y)?;
        let c = &mut *self.compiled;
        c.inputs[n..2 * n].copy_from_slice(&self.velocity);
        let Some((_, forces)) = c.canonical.as_mut() else {
            return Err(RhsError::NotFinite);
        };
        let out = forces.eval(&c.inputs);
        dy[..n].copy_from_slice(&self.velocity);
        dy[n..].copy_from_slice(&out[..n]);
        Ok(())
    }

    fn event_count(&self) -> usize {
        self.compiled.event_count()
    }

    fn event_stops(&self, index: usize) -> bool {
        self.compiled.event_stops(index)
    }

    fn events(&mut self, t: f64, y: &[f64], g: &mut [f64]) {
        let n = self.compiled.n;
        if self.solve_velocity(t, y).is_err() {
            g.fill(f64::NAN);
            return;
        }
        let c = &mut *self.compiled;
        c.inputs[n..2 * n].copy_from_slice(&self.velocity);
        if let Some(events) = c.events.as_mut() {
            let out = events.eval(&c.inputs);
            g.copy_from_slice(&out[..g.len()]);
        }
    }
}
