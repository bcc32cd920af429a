//! The equations of motion compiled for numbers: which expressions go on which tape, and the
//! input layout shared by all tapes, `[q₁…qₙ, q̇₁…q̇ₙ, t, parameters…]`.
//!
//! Four tapes, each evaluated only where it is needed:
//! * dynamics — `M` (row-major), `f`, `A`, `b`: every right-hand side evaluation, unless
//!   the tree below serves it;
//! * tree — `S`, `c`, `b`, `τ` of the model's kinematic tree ([`mechanics::KinematicTree`]),
//!   solved in O(n) by [`numeric::Articulated`]: every right-hand side evaluation of a model
//!   without constraints whose tree is cheaper than the dense `M` and agrees with it;
//! * monitor — energy, `Φ` of the holonomic rows, `c` of every row: at outputs and projections;
//! * canonical — `M`, `p₀ = ∂L/∂q̇|_{q̇=0}` and `∂L/∂q + Q`: only for the symplectic method;
//! * events — the stop events (`--stop-when`, lost contacts), then the recorded ones
//!   (`--record-when`).

use cas::{Expr, Symbol};
use mechanics::{ConstraintForm, Equations, KinematicTree, System};
use numeric::{Articulated, ArticulatedNode, Tape, TapeError};

/// A tape with its own buffers: evaluating allocates nothing.
#[derive(Clone, Debug)]
pub(crate) struct Evaluator {
    tape: Tape,
    registers: Vec<f64>,
    outputs: Vec<f64>,
}

impl Evaluator {
    pub(crate) fn new(outputs: &[Expr], inputs: &[Symbol]) -> Result<Evaluator, TapeError> {
        let tape = Tape::compile(outputs, inputs)?;
        Ok(Evaluator {
            registers: tape.registers(),
            outputs: vec![0.0; tape.output_count()],
            tape,
        })
    }

    pub(crate) fn eval(&mut self, inputs: &[f64]) -> &[f64] {
        self.tape
            .eval(inputs, &mut self.registers, &mut self.outputs);
        &self.outputs
    }

    pub(crate) fn instruction_count(&self) -> usize {
        self.tape.instruction_count()
    }
}

/// The compiled equations of one model. Invariant: every tape takes the input layout
/// `[q (n), q̇ (n), t, parameters]`; `holonomic` lists the constraint rows (of `m`) that have
/// a position-level `Φ`, in the order of the monitor's `Φ` outputs.
#[derive(Clone, Debug)]
pub(crate) struct Compiled {
    pub(crate) n: usize,
    pub(crate) m: usize,
    pub(crate) holonomic: Vec<usize>,
    /// The dense tape of `M`, `f`, `A`, `b`; `None` only where the right-hand side goes by the
    /// tree, which never reads it: the `n²` entries of `M`, folded and compiled, were most of
    /// the preparation of a large chain (16 s of the 3-D chain of 100 rods).
    /// [`Compiled::dense_tape`] compiles it where a caller asks for the dense route.
    pub(crate) dynamics: Option<Evaluator>,
    /// What the dense tape is compiled from.
    dense_source: DenseSource,
    /// The articulated-body route, where the model has a tree worth using.
    pub(crate) tree: Option<TreeRhs>,
    pub(crate) monitor: Evaluator,
    pub(crate) canonical: Option<(Evaluator, Evaluator)>,
    pub(crate) events: Option<Evaluator>,
    /// One-sided reactions evaluated numerically, stop events after the tape's.
    pub(crate) contacts: Option<crate::NumericContacts>,
    /// How many of the events (the first ones) stop the run; the others are recorded.
    pub(crate) stopping_events: usize,
    /// The input buffer, with the parameters' values in place.
    pub(crate) inputs: Vec<f64>,
    /// Whether the drift of every constraint row is known at position or velocity level.
    pub(crate) drift_known: bool,
}

impl Compiled {
    /// Compiles the equations. `parameters` are the values of every symbol that is not a
    /// coordinate, a rate or time; `events` are expressions of the same symbols, of which the
    /// first `stopping_events` stop the run and the others are recorded.
    pub(crate) fn new(
        system: &System,
        equations: &Equations,
        parameters: &[(String, f64)],
        timed_inputs: &[(String, Expr)],
        events: &[Expr],
        stopping_events: usize,
        canonical: bool,
    ) -> Result<Compiled, TapeError> {
        let n = equations.coordinates().len();
        let m = equations.constraint_names().len();
        let (inputs, values) = input_layout(equations.coordinates(), parameters);
        let fold = Folder::new(parameters, timed_inputs);

        let mut dynamic_outputs: Vec<Expr> = equations.mass_matrix().concat();
        dynamic_outputs.extend_from_slice(equations.forcing());
        dynamic_outputs.extend(equations.constraint_matrix().concat());
        dynamic_outputs.extend_from_slice(equations.constraint_rhs());
        let dense_source = DenseSource {
            outputs: dynamic_outputs,
            inputs: inputs.clone(),
            fold: fold.clone(),
        };
        let tree = if m == 0 {
            compile_tree(system, equations, &fold, &inputs, &values)
        } else {
            None
        };
        // The dense tape is compiled only where the tree's cost does not beat the dense
        // route's without it; then the two are compared with the dense tape's own count.
        let mut tree = tree;
        let dynamics = if tree.as_ref().is_some_and(|t| t.preferred) {
            None
        } else {
            let dynamics = dense_source.compile()?;
            if let Some(tree) = tree.as_mut() {
                tree.preferred = tree.cost < dense_cost(dynamics.instruction_count(), n);
            }
            Some(dynamics)
        };

        let levels = constraint_levels(system, equations);
        let drift_known = levels.len() == m;
        let (holonomic, positions, velocities) = if drift_known {
            split_levels(&levels)
        } else {
            (Vec::new(), Vec::new(), Vec::new())
        };
        let mut monitor_outputs = vec![fold.one(energy(equations))];
        monitor_outputs.extend(fold.all(&positions));
        monitor_outputs.extend(fold.all(&velocities));
        let monitor = Evaluator::new(&monitor_outputs, &inputs)?;

        let canonical = if canonical {
            let (mass_momentum, forces) = hamilton_outputs(equations);
            Some((
                Evaluator::new(&fold.all(&mass_momentum), &inputs)?,
                Evaluator::new(&fold.all(&forces), &inputs)?,
            ))
        } else {
            None
        };
        let events = if events.is_empty() {
            None
        } else {
            Some(Evaluator::new(&fold.all(events), &inputs)?)
        };
        let mut compiled = Compiled {
            n,
            m,
            holonomic,
            dynamics,
            dense_source,
            tree,
            monitor,
            canonical,
            events,
            contacts: None,
            stopping_events,
            inputs: values,
            drift_known,
        };
        if compiled.tree.is_some() {
            // With the dense tape at hand the two routes are compared; without it the tree's
            // accelerations are put into the model's own equations.
            let agrees = if compiled.dynamics.is_some() {
                crate::forms::tree_agrees(&mut compiled)
            } else {
                let forcing = fold.all(equations.forcing());
                let kinetic = fold.one(equations.kinetic_energy());
                crate::forms::tree_satisfies(&mut compiled, &inputs, &forcing, kinetic)
            };
            if !agrees {
                compiled.tree = None;
                compiled.dense_tape()?;
            }
        }
        Ok(compiled)
    }

    /// The dense tape, compiled now if the right-hand side went by the tree until now.
    ///
    /// # Errors
    /// [`TapeError`] when an expression of `M`, `f`, `A` or `b` cannot be compiled.
    pub(crate) fn dense_tape(&mut self) -> Result<&mut Evaluator, TapeError> {
        let dynamics = match self.dynamics.take() {
            Some(dynamics) => dynamics,
            None => self.dense_source.compile()?,
        };
        Ok(self.dynamics.insert(dynamics))
    }

    /// How many event functions there are: each output of the events tape, then each
    /// one-sided reaction evaluated numerically.
    pub(crate) fn event_count(&self) -> usize {
        self.tape_event_count() + self.contacts.as_ref().map_or(0, |c| c.columns.len())
    }

    /// How many event functions the events tape computes.
    pub(crate) fn tape_event_count(&self) -> usize {
        self.events.as_ref().map_or(0, |e| e.tape.output_count())
    }

    /// Whether event `index` stops the run: the first `stopping_events` of the tape, and
    /// every numeric one-sided reaction.
    pub(crate) fn event_stops(&self, index: usize) -> bool {
        index < self.stopping_events || index >= self.tape_event_count()
    }

    /// Puts `(q, q̇, t)` into the input buffer.
    pub(crate) fn set_state(&mut self, q: &[f64], qd: &[f64], t: f64) {
        let n = self.n;
        self.inputs[..n].copy_from_slice(q);
        self.inputs[n..2 * n].copy_from_slice(qd);
        self.inputs[2 * n] = t;
    }

    /// Energy and constraint drift (the largest `|Φ|` or `|c|`; 0 without constraints, NaN
    /// when the constraint rows could not be matched) at the state in the input buffer.
    pub(crate) fn energy_and_drift(&mut self) -> (f64, f64) {
        let (energy, position, velocity) = self.energy_and_drifts();
        (energy, position.max(velocity))
    }

    /// Energy, position drift (the largest `|Φ|` of the holonomic rows) and velocity drift
    /// (the largest `|c|` of every row) at the state in the input buffer; the drifts are 0
    /// without constraints and NaN when the constraint rows could not be matched.
    pub(crate) fn energy_and_drifts(&mut self) -> (f64, f64, f64) {
        let holonomic = self.holonomic.len();
        let known = self.drift_known;
        let out = self.monitor.eval(&self.inputs);
        let largest = |xs: &[f64]| {
            if known {
                xs.iter().fold(0.0f64, |d, x| d.max(x.abs()))
            } else {
                f64::NAN
            }
        };
        let position = largest(&out[1..1 + holonomic]);
        let velocity = largest(&out[1 + holonomic..]);
        (out[0], position, velocity)
    }
}

/// The dense tape's expressions (`M` row-major, `f`, `A`, `b`, unfolded), the input layout
/// and the run's numbers.
#[derive(Clone, Debug)]
struct DenseSource {
    outputs: Vec<Expr>,
    inputs: Vec<Symbol>,
    fold: Folder,
}

impl DenseSource {
    fn compile(&self) -> Result<Evaluator, TapeError> {
        Evaluator::new(&self.fold.all(&self.outputs), &self.inputs)
    }
}

/// The articulated-body route of a model without constraints: a tape of `[S, c, b, τ]` and
/// the tree's solver (with `W` in place). Invariant: the tape's outputs are `3 width + n`.
#[derive(Clone, Debug)]
pub(crate) struct TreeRhs {
    pub(crate) evaluator: Evaluator,
    pub(crate) solver: Articulated,
    pub(crate) width: usize,
    /// Machine instructions of one evaluation by the tree, estimated ([`tree_cost`]).
    pub(crate) cost: usize,
    /// Whether the right-hand side goes by the tree: it costs less than the dense route
    /// ([`dense_cost`]; with the dense tape's count where that tape was compiled, without
    /// it — a lower bound — where the tree wins even so). A tree kept but not preferred still
    /// serves [`crate::Simulation::rhs_both_routes`].
    pub(crate) preferred: bool,
}

/// Machine instructions of one right-hand side by the tree: 18 a tape instruction, about 290
/// a node and 29 per entry of its `d_j × d_j` block, and 350 per call. Fitted to callgrind's
/// counts per evaluation (`bench/compare/callgrind.sh`, docs/performance.md, issue 20) on
/// the n-link pendulums (n = 2…10, d = 2: within 25 %) and the 3-D chains (1 to 10 rods,
/// d = 9: the marginal cost of a rod within 2 %, the first rod overestimated).
fn tree_cost(tape_instructions: usize, dimensions: impl Iterator<Item = usize>) -> usize {
    350 + 18 * tape_instructions + dimensions.map(|d| 290 + 29 * d * d).sum::<usize>()
}

/// Machine instructions of one right-hand side by the dense route with a tape of
/// `tape_instructions` (0 for a lower bound): 18 a tape instruction, the `L D Lᵀ` solve and
/// the copies `300 + 250 n + 22 (n³/6 + n²)`, fitted as [`tree_cost`] (n = 2…20, within
/// 15 % but for the 3-D chain of 5 rods, 25 %).
fn dense_cost(tape_instructions: usize, n: usize) -> usize {
    let cubic = n.saturating_pow(3) / 6 + n.saturating_mul(n);
    300usize
        .saturating_add(18usize.saturating_mul(tape_instructions))
        .saturating_add(250usize.saturating_mul(n))
        .saturating_add(22usize.saturating_mul(cubic))
}

/// The tree route, where the model has a kinematic tree; `None` where it has none or a number
/// is missing.
fn compile_tree(
    system: &System,
    equations: &Equations,
    fold: &Folder,
    inputs: &[Symbol],
    values: &[f64],
) -> Option<TreeRhs> {
    let tree = KinematicTree::of(system, equations)?;
    let n = equations.coordinates().len();
    let width = tree.motion().len();
    let mut outputs = fold.all(tree.motion());
    outputs.extend(fold.all(tree.bias_acceleration()));
    outputs.extend(fold.all(tree.bias_force()));
    outputs.extend(fold.all(tree.forces()));
    let evaluator = Evaluator::new(&outputs, inputs).ok()?;
    // `W` is free of the state (`KinematicTree` checks): evaluated once, at the parameters.
    let inertias: Vec<Expr> = tree
        .nodes()
        .iter()
        .flat_map(|node| fold.all(&node.inertia))
        .collect();
    let mut inertia = Evaluator::new(&inertias, inputs).ok()?;
    let inertia = inertia.eval(values);
    if !inertia.iter().all(|x| x.is_finite()) {
        return None;
    }
    let mut at = 0;
    let nodes: Vec<ArticulatedNode> = tree
        .nodes()
        .iter()
        .map(|node| {
            let size = node.inertia.len();
            at += size;
            ArticulatedNode {
                parent: node.parent,
                source: node.source.clone(),
                inertia: inertia[at - size..at].to_vec(),
            }
        })
        .collect();
    let solver = Articulated::new(&nodes).ok()?;
    let cost = tree_cost(
        evaluator.instruction_count(),
        tree.nodes().iter().map(|node| node.source.len()),
    );
    Some(TreeRhs {
        evaluator,
        solver,
        width,
        cost,
        preferred: cost < dense_cost(0, n),
    })
}

/// The constraints kept with multipliers, at position level (`Φ`, for holonomic rows) and at
/// velocity level (`c`), rebuilt from the system the way `mechanics::derive` keeps them: in
/// declaration order, eliminated coordinates substituted, rows that vanish dropped.
/// The tapes' input layout `[q, q̇, t, parameters…]`, and the buffer with the parameters'
/// values in place.
pub(crate) fn input_layout(
    names: &[String],
    parameters: &[(String, f64)],
) -> (Vec<Symbol>, Vec<f64>) {
    let n = names.len();
    let mut inputs: Vec<Symbol> = Vec::with_capacity(2 * n + 1 + parameters.len());
    let mut values = vec![0.0; 2 * n + 1];
    inputs.extend(names.iter().filter_map(|q| Expr::coordinate(q).as_symbol()));
    inputs.extend(names.iter().filter_map(|q| Expr::rate(q, 1).as_symbol()));
    inputs.extend(Expr::time().as_symbol());
    for (name, value) in parameters {
        if let Some(s) = Expr::symbol(name).as_symbol() {
            inputs.push(s);
            values.push(*value);
        }
    }
    (inputs, values)
}

/// Folds the run's numbers into expressions before compiling. The parameters are numbers for
/// the whole run: in normal form the terms that differ only in parameters (Σ m_k l_i l_j
/// cos θ_i cos θ_j …) then merge, which shrinks the n-link pendulum's forcing about n-fold.
/// Values enter as floats, never as exact integers: the normal form would expand
/// trigonometry of small integer multiples (`cos(ω t)` with an integer ω).
#[derive(Clone, Debug)]
pub(crate) struct Folder {
    timed: Vec<(Expr, Expr)>,
    constants: Vec<(Expr, Expr)>,
}

impl Folder {
    pub(crate) fn new(parameters: &[(String, f64)], timed_inputs: &[(String, Expr)]) -> Folder {
        Folder {
            timed: timed_inputs
                .iter()
                .map(|(name, value)| (Expr::symbol(name), *value))
                .collect(),
            constants: parameters
                .iter()
                .map(|(name, value)| (Expr::symbol(name), Expr::float(*value)))
                .collect(),
        }
    }

    /// Inputs given as functions of time go in first: their expressions may hold parameters.
    fn one(&self, e: Expr) -> Expr {
        e.subs(&self.timed).subs(&self.constants).normal()
    }

    pub(crate) fn all(&self, es: &[Expr]) -> Vec<Expr> {
        es.iter().map(|e| self.one(*e)).collect()
    }
}

/// The energy monitored along a run: the conserved `h` when there is one, else `K + V`.
fn energy(equations: &Equations) -> Expr {
    equations
        .first_integrals()
        .iter()
        .find(|f| f.coordinate.is_none())
        .map_or_else(
            || (equations.kinetic_energy() + equations.potential_energy()).normal(),
            |f| f.value,
        )
}

/// The holonomic rows' indices, their position-level and every row's velocity-level
/// expressions.
fn split_levels(levels: &[(Option<Expr>, Expr)]) -> (Vec<usize>, Vec<Expr>, Vec<Expr>) {
    let holonomic = levels
        .iter()
        .enumerate()
        .filter(|(_, (phi, _))| phi.is_some())
        .map(|(k, _)| k)
        .collect();
    let positions = levels.iter().filter_map(|(phi, _)| *phi).collect();
    let velocities = levels.iter().map(|(_, c)| *c).collect();
    (holonomic, positions, velocities)
}

/// Hamilton's form for the symplectic method: `M` and `p₀ = ∂L/∂q̇ at q̇ = 0` (so that
/// `p = M q̇ + p₀`), and `∂L/∂q + Q`.
fn hamilton_outputs(equations: &Equations) -> (Vec<Expr>, Vec<Expr>) {
    let names = equations.coordinates();
    let lagrangian = equations.lagrangian();
    let at_rest: Vec<(Expr, Expr)> = names
        .iter()
        .map(|x| (Expr::rate(x, 1), Expr::zero()))
        .collect();
    let partial = |e: Expr, s: Option<Symbol>| s.map_or_else(Expr::zero, |s| e.diff(s));
    let mut mass_momentum: Vec<Expr> = equations.mass_matrix().concat();
    mass_momentum.extend(names.iter().map(|x| {
        partial(lagrangian, Expr::rate(x, 1).as_symbol())
            .subs(&at_rest)
            .normal()
    }));
    let forces = names
        .iter()
        .zip(equations.generalized_forces())
        .map(|(x, force)| (partial(lagrangian, Expr::coordinate(x).as_symbol()) + *force).normal())
        .collect();
    (mass_momentum, forces)
}

fn constraint_levels(system: &System, equations: &Equations) -> Vec<(Option<Expr>, Expr)> {
    let mut pairs: Vec<Vec<(Expr, Expr)>> = Vec::new();
    for e in equations.eliminated() {
        let mut value = e.value;
        let mut level = Vec::new();
        for order in 0..3u8 {
            let target = if order == 0 {
                Expr::coordinate(&e.coordinate)
            } else {
                Expr::rate(&e.coordinate, order)
            };
            level.push((target, value));
            value = value.dt();
        }
        pairs.push(level);
    }
    let substitute = |mut x: Expr| {
        for level in &pairs {
            x = x.subs(level);
        }
        x.normal()
    };
    let mut rows = Vec::new();
    for constraint in system.constraints() {
        for form in &constraint.equations {
            match form {
                ConstraintForm::Holonomic(f) => {
                    let phi = substitute(*f);
                    let c = phi.dt().normal();
                    if !c.is_zero() {
                        rows.push((Some(phi), c));
                    }
                }
                ConstraintForm::Velocity(c) => {
                    let c = substitute(*c);
                    if !c.is_zero() {
                        rows.push((None, c));
                    }
                }
                // A form this code does not know cannot be matched to its row: the row count
                // then differs and drift is reported as unknown rather than wrong.
                _ => {}
            }
        }
    }
    rows
}
