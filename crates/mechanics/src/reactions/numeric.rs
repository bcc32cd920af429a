//! Reactions evaluated numerically, state by state: no closed form is built, so the cost is a
//! compilation, whatever the size the closed form would have (issue 17).
//!
//! **Releases** (hinges, contacts, ropes, rolling contacts, clamps). The released system's
//! geometry is compiled for Kane's method ([`KaneSystem`]), and at a state of the constrained
//! system its Lagrange residuals `E_u − Q_u = (M q̈ − f)_u` are evaluated with dual numbers at
//! `u = u̇ = ü = 0`, the other coordinates at the constrained motion (accelerations given,
//! eliminated coordinates from their values). That is Lagrange I exactly as
//! [`super::reactions_of`] writes it in closed form; no other constraint's multiplier enters,
//! since a release is refused when another constraint moves with it.
//!
//! **Constraints kept with multipliers.** Their multipliers `λ`, given (solved from the KKT
//! system `[M Aᵀ; A 0] [q̈; λ] = [f; b]` by the caller, who has the equations compiled).
//!
//! **Driven coordinates, constraints eliminated by integration.** The residuals of the system
//! without them, as for a release, when that system has no other constraint.
//!
//! | symbol | meaning | shape |
//! |---|---|---|
//! | `q`, `q̇`, `q̈` | the constrained system's coordinates, rates, accelerations | n |
//! | `λ` | the multipliers of the rows kept with multipliers | m |
//! | `u`, `ψ` | a release's displacements and small rotations | — |
//! | `R = Σ r_u d_u` | the force on the released bodies, inertial components | 3 |
//!
//! Column names ([`ReactionColumn::name`], docs/reactions.md): `NAME_x`, `NAME_y`, `NAME_z` for
//! a force's inertial components (only the axes the release can move along), `NAME_N` for a
//! contact's or rolling contact's normal force, `NAME_T` for a rope's tension, `NAME_Mx`… for a
//! clamp's couple, `lambda_NAME` (or `lambda_NAME_1`, `lambda_NAME_2`, … for several rows) for
//! multipliers, `Q_NAME` for the force driving a driven coordinate and `Q_NAME_q` for the
//! generalized reaction on coordinate `q` of a constraint eliminated by integration.

use cas::{Expr, Symbol};
use numeric::Tape;

use super::{ReactionError, ReactionRequest, Release, ReleaseKind};
use crate::equations::Equations;
use crate::kane::{KaneError, KaneSystem};
use crate::system::{System, Vector};

/// Why a reaction cannot be evaluated numerically (then its closed form is the route).
#[derive(Debug, thiserror::Error, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum NumericGap {
    /// A symbol of the released system has no value (an input given as a function of time).
    #[error("`{0}` has no value")]
    UnknownSymbol(String),
    /// A coordinate of the released system is not one of the constrained system's, nor
    /// eliminated, driven or released.
    #[error("the coordinate `{0}` of the released system is not on the motion")]
    UnknownCoordinate(String),
    /// A function or form that the compiled evaluation does not know.
    #[error("{0}")]
    Uncompiled(String),
    /// The system without the constraint keeps other constraints, whose multipliers would
    /// enter its residuals.
    #[error("the system without it keeps other constraints")]
    OtherConstraints,
}

/// What a column holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Quantity {
    /// A force's inertial component (0, 1, 2 for x, y, z).
    Force(usize),
    /// The normal force of a contact or rolling contact, or a rope's tension.
    Along,
    /// A clamp's couple, inertial component.
    Couple(usize),
    /// A multiplier `λ` of a constraint row.
    Multiplier,
    /// A generalized reaction or driving force on a coordinate.
    Generalized,
}

/// One number a [`ReactionEvaluator`] gives per state.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReactionColumn {
    /// The reaction's name in the model.
    pub reaction: String,
    /// The column's name (see the module doc), unique among the columns.
    pub name: String,
    /// What it holds.
    pub quantity: Quantity,
}

/// A state of the constrained system, with what the caller solved there.
#[derive(Clone, Copy, Debug)]
pub struct ReactionState<'a> {
    /// Time.
    pub t: f64,
    /// The coordinates `q`, in the order of [`Equations::coordinates`].
    pub positions: &'a [f64],
    /// The rates `q̇`.
    pub rates: &'a [f64],
    /// The accelerations `q̈` on the motion.
    pub accelerations: &'a [f64],
    /// The multipliers, one per row of [`Equations::constraint_names`] (empty without).
    pub multipliers: &'a [f64],
    /// The values, in the order of the names given to [`ReactionEvaluator::new`].
    pub values: &'a [f64],
}

/// The reactions asked for, compiled to be evaluated at any state of the constrained system.
#[derive(Clone, Debug)]
pub struct ReactionEvaluator {
    n: usize,
    /// The auxiliary expressions (directions, eliminated and driven coordinates) over
    /// `(q, q̇, q̈, t, values)`.
    aux: Tape,
    entries: Vec<Entry>,
    columns: Vec<ReactionColumn>,
}

/// Where a coordinate of a released (or reduced) system takes its value on the motion.
#[derive(Clone, Copy, Debug)]
enum Source {
    /// The constrained system's coordinate of this index.
    Kept(usize),
    /// Auxiliary outputs `at`, `at + 1`, `at + 2`: value, rate, acceleration.
    Aux(usize),
    /// A displacement or rotation: zero.
    Zero,
}

#[derive(Clone, Debug)]
enum Entry {
    Release(Box<Released>),
    Multipliers(Vec<usize>),
    Residuals {
        kane: Box<KaneSystem>,
        sources: Vec<Source>,
        rows: Vec<usize>,
    },
}

#[derive(Clone, Debug)]
struct Released {
    kane: KaneSystem,
    sources: Vec<Source>,
    /// Per displacement: its coordinate's index and where its direction starts in `aux`.
    displacements: Vec<(usize, usize)>,
    /// Per rotation: its coordinate's index and where its axis starts in `aux`.
    rotations: Vec<(usize, usize)>,
    /// The force axes given as columns.
    force_axes: Vec<usize>,
    /// The couple axes given as columns (a clamp).
    couple_axes: Vec<usize>,
    along: Along,
}

#[derive(Clone, Copy, Debug)]
enum Along {
    None,
    /// The first displacement's residual (a contact or rope).
    First,
    /// `R · n`, `n` starting at this `aux` output.
    Normal(usize),
}

/// The auxiliary expressions being collected, and the constrained system's symbols.
struct AuxBuilder<'e> {
    equations: &'e Equations,
    /// Each eliminated coordinate's value in the kept coordinates only.
    eliminated: Vec<(String, Expr)>,
    outputs: Vec<Expr>,
}

impl ReactionEvaluator {
    /// Compiles the reactions `requests` of `system`, whose equations are `equations`;
    /// `values` names every parameter and input that has a value.
    ///
    /// # Errors
    /// [`ReactionError::NotNumeric`] for a reaction that this route cannot evaluate (its
    /// closed form remains), [`ReactionError::Entangled`] as for the closed form, or
    /// [`ReactionError::UnknownConstraint`].
    pub fn new(
        system: &System,
        equations: &Equations,
        requests: &[ReactionRequest],
        values: &[String],
    ) -> Result<ReactionEvaluator, ReactionError> {
        let mut aux = AuxBuilder::new(equations);
        let mut entries = Vec::with_capacity(requests.len());
        let mut columns = Vec::new();
        for request in requests {
            let entry = match request {
                ReactionRequest::Release(release) => {
                    super::lagrange_one::check_disentangled(release)?;
                    let released = released(release, &mut aux, values)?;
                    columns.extend(released.columns(release));
                    Entry::Release(Box::new(released))
                }
                ReactionRequest::Constraint { name, without } => {
                    if !system.constraints().iter().any(|c| &c.name == name) {
                        return Err(ReactionError::UnknownConstraint(name.clone()));
                    }
                    constraint_entry(name, without, &mut aux, values, &mut columns)?
                }
                ReactionRequest::Driven {
                    name,
                    without,
                    motion,
                } => {
                    if !without.constraints().is_empty() {
                        return Err(not_numeric(name, NumericGap::OtherConstraints));
                    }
                    let driven = [(name.clone(), *motion)];
                    let (kane, sources) = reduced(name, without, &mut aux, values, &driven)?;
                    let row = index_of(&kane, name)?;
                    columns.push(ReactionColumn {
                        reaction: name.clone(),
                        name: format!("Q_{name}"),
                        quantity: Quantity::Generalized,
                    });
                    Entry::Residuals {
                        kane: Box::new(kane),
                        sources,
                        rows: vec![row],
                    }
                }
            };
            entries.push(entry);
        }
        let tape = aux.compile(values)?;
        Ok(ReactionEvaluator {
            n: equations.coordinates().len(),
            aux: tape,
            entries,
            columns,
        })
    }

    /// An estimate of the work of the closed form: `Σ s·k²` over the released (and reduced)
    /// systems, `s` the operations of the compiled geometry and `k` the coordinates (the
    /// Lagrangian's terms grow with `s`, the equations with `k²`). Multipliers alone cost
    /// nothing here (their closed form is bounded by the solve's own budget).
    #[must_use]
    pub fn closed_form_work(&self) -> usize {
        let work = |kane: &KaneSystem| {
            let k = kane.coordinates().len();
            kane.size().saturating_mul(k * k)
        };
        self.entries
            .iter()
            .map(|entry| match entry {
                Entry::Release(r) => work(&r.kane),
                Entry::Residuals { kane, .. } => work(kane),
                Entry::Multipliers(_) => 0,
            })
            .fold(0, usize::saturating_add)
    }

    /// The columns, in the order [`ReactionEvaluator::evaluate`] gives their values.
    #[must_use]
    pub fn columns(&self) -> &[ReactionColumn] {
        &self.columns
    }

    /// Every column's value at `state` (NaN where a value is not finite, or the state has
    /// the wrong length).
    #[must_use]
    pub fn evaluate(&self, state: &ReactionState<'_>) -> Vec<f64> {
        let n = self.n;
        if [state.positions, state.rates, state.accelerations]
            .iter()
            .any(|x| x.len() != n)
        {
            return vec![f64::NAN; self.columns.len()];
        }
        let mut inputs = Vec::with_capacity(3 * n + 1 + state.values.len());
        inputs.extend_from_slice(state.positions);
        inputs.extend_from_slice(state.rates);
        inputs.extend_from_slice(state.accelerations);
        inputs.push(state.t);
        inputs.extend_from_slice(state.values);
        if inputs.len() != self.aux.input_count() {
            return vec![f64::NAN; self.columns.len()];
        }
        let mut aux = vec![0.0; self.aux.output_count()];
        self.aux.eval(&inputs, &mut self.aux.registers(), &mut aux);
        let mut out = Vec::with_capacity(self.columns.len());
        for entry in &self.entries {
            match entry {
                Entry::Release(r) => r.evaluate(state, &aux, &mut out),
                Entry::Multipliers(rows) => out.extend(
                    rows.iter()
                        .map(|&k| state.multipliers.get(k).copied().unwrap_or(f64::NAN)),
                ),
                Entry::Residuals {
                    kane,
                    sources,
                    rows,
                } => {
                    let r = residuals(kane, sources, state, &aux);
                    out.extend(rows.iter().map(|&j| r[j]));
                }
            }
        }
        out.iter_mut()
            .filter(|x| !x.is_finite())
            .for_each(|x| *x = f64::NAN);
        out
    }
}

impl Released {
    fn columns(&self, release: &Release) -> Vec<ReactionColumn> {
        let name = &release.name;
        let column = |suffix: &str, quantity| ReactionColumn {
            reaction: name.clone(),
            name: format!("{name}_{suffix}"),
            quantity,
        };
        let mut columns: Vec<ReactionColumn> = self
            .force_axes
            .iter()
            .map(|&k| column(AXES[k], Quantity::Force(k)))
            .collect();
        if !matches!(self.along, Along::None) {
            let word = if release.kind == ReleaseKind::Rope {
                "T"
            } else {
                "N"
            };
            columns.push(column(word, Quantity::Along));
        }
        columns.extend(
            self.couple_axes
                .iter()
                .map(|&k| column(&format!("M{}", AXES[k]), Quantity::Couple(k))),
        );
        columns
    }

    fn evaluate(&self, state: &ReactionState<'_>, aux: &[f64], out: &mut Vec<f64>) {
        let r = residuals(&self.kane, &self.sources, state, aux);
        let mut force = [0.0; 3];
        for &(u, at) in &self.displacements {
            for (k, f) in force.iter_mut().enumerate() {
                *f += r[u] * aux[at + k];
            }
        }
        out.extend(self.force_axes.iter().map(|&k| force[k]));
        match self.along {
            Along::None => {}
            Along::First => out.push(self.displacements.first().map_or(f64::NAN, |&(u, _)| r[u])),
            Along::Normal(at) => out.push((0..3).map(|k| force[k] * aux[at + k]).sum()),
        }
        let mut couple = [0.0; 3];
        for &(psi, at) in &self.rotations {
            for (k, c) in couple.iter_mut().enumerate() {
                *c += r[psi] * aux[at + k];
            }
        }
        out.extend(self.couple_axes.iter().map(|&k| couple[k]));
    }
}

/// The inertial axes' names in column names.
const AXES: [&str; 3] = ["x", "y", "z"];

/// The residuals `(M q̈ − f)_j` of a compiled system at the constrained motion.
fn residuals(
    kane: &KaneSystem,
    sources: &[Source],
    state: &ReactionState<'_>,
    aux: &[f64],
) -> Vec<f64> {
    let pick = |order: usize| -> Vec<f64> {
        sources
            .iter()
            .map(|s| match s {
                Source::Kept(k) => match order {
                    0 => state.positions[*k],
                    1 => state.rates[*k],
                    _ => state.accelerations[*k],
                },
                Source::Aux(at) => aux[at + order],
                Source::Zero => 0.0,
            })
            .collect()
    };
    kane.lagrange_residuals(&pick(0), &pick(1), &pick(2), state.t, state.values)
}

fn index_of(kane: &KaneSystem, name: &str) -> Result<usize, ReactionError> {
    kane.coordinates()
        .iter()
        .position(|q| q == name)
        .ok_or_else(|| not_numeric(name, NumericGap::UnknownCoordinate(name.to_string())))
}

fn not_numeric(reaction: &str, gap: NumericGap) -> ReactionError {
    ReactionError::NotNumeric {
        reaction: reaction.to_string(),
        gap,
    }
}

fn compiled(
    reaction: &str,
    system: &System,
    values: &[String],
) -> Result<KaneSystem, ReactionError> {
    KaneSystem::new(system, values).map_err(|e| {
        let gap = match e {
            KaneError::UnknownSymbol(s) => NumericGap::UnknownSymbol(s),
            other => NumericGap::Uncompiled(other.to_string()),
        };
        not_numeric(reaction, gap)
    })
}

/// A system with extra coordinates (displacements, a driven one) compiled, and where each of
/// its coordinates takes its value on the motion.
fn reduced(
    reaction: &str,
    system: &System,
    aux: &mut AuxBuilder<'_>,
    values: &[String],
    prescribed: &[(String, Expr)],
) -> Result<(KaneSystem, Vec<Source>), ReactionError> {
    let kane = compiled(reaction, system, values)?;
    let sources = kane
        .coordinates()
        .iter()
        .map(|q| {
            if let Some((_, motion)) = prescribed.iter().find(|(p, _)| p == q) {
                return Ok(aux.motion(*motion));
            }
            aux.source(q)
                .ok_or_else(|| not_numeric(reaction, NumericGap::UnknownCoordinate(q.clone())))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok((kane, sources))
}

fn released(
    release: &Release,
    aux: &mut AuxBuilder<'_>,
    values: &[String],
) -> Result<Released, ReactionError> {
    let extra: Vec<(String, Expr)> = release
        .displacements
        .iter()
        .chain(&release.rotations)
        .map(|(u, _)| (u.clone(), Expr::zero()))
        .collect();
    let (kane, mut sources) = reduced(&release.name, &release.system, aux, values, &extra)?;
    let mut placed = |list: &[(String, Vector)]| -> Result<Vec<(usize, usize)>, ReactionError> {
        list.iter()
            .map(|(u, d)| {
                let j = index_of(&kane, u)?;
                sources[j] = Source::Zero;
                Ok((j, aux.vector(d)))
            })
            .collect()
    };
    let displacements = placed(&release.displacements)?;
    let rotations = placed(&release.rotations)?;
    let used = |list: &[(String, Vector)]| -> Vec<usize> {
        (0..3)
            .filter(|&k| list.iter().any(|(_, d)| !d[k].normal().is_zero()))
            .collect()
    };
    let along = match (release.kind.is_unilateral(), &release.normal) {
        (true, _) if !release.displacements.is_empty() => Along::First,
        (_, Some(n)) => Along::Normal(aux.vector(n)),
        _ => Along::None,
    };
    let couple_axes = if release.kind == ReleaseKind::Clamp {
        used(&release.rotations)
    } else {
        Vec::new()
    };
    Ok(Released {
        kane,
        sources,
        displacements,
        rotations,
        force_axes: used(&release.displacements),
        couple_axes,
        along,
    })
}

/// A constraint's reaction: its multipliers, or (eliminated by integration) the residuals of
/// the system without it on every coordinate.
fn constraint_entry(
    name: &str,
    without: &System,
    aux: &mut AuxBuilder<'_>,
    values: &[String],
    columns: &mut Vec<ReactionColumn>,
) -> Result<Entry, ReactionError> {
    let rows: Vec<usize> = (aux.equations.constraint_names().iter().enumerate())
        .filter(|(_, n)| *n == name)
        .map(|(k, _)| k)
        .collect();
    if !rows.is_empty() {
        let several = rows.len() > 1;
        columns.extend((0..rows.len()).map(|i| ReactionColumn {
            reaction: name.to_string(),
            name: if several {
                format!("lambda_{name}_{}", i + 1)
            } else {
                format!("lambda_{name}")
            },
            quantity: Quantity::Multiplier,
        }));
        return Ok(Entry::Multipliers(rows));
    }
    if !without.constraints().is_empty() {
        return Err(not_numeric(name, NumericGap::OtherConstraints));
    }
    let (kane, sources) = reduced(name, without, aux, values, &[])?;
    columns.extend(kane.coordinates().iter().map(|q| ReactionColumn {
        reaction: name.to_string(),
        name: format!("Q_{name}_{q}"),
        quantity: Quantity::Generalized,
    }));
    let rows = (0..kane.coordinates().len()).collect();
    Ok(Entry::Residuals {
        kane: Box::new(kane),
        sources,
        rows,
    })
}

impl<'e> AuxBuilder<'e> {
    fn new(equations: &'e Equations) -> AuxBuilder<'e> {
        // Eliminations are applied in order: a value may name a coordinate eliminated later.
        let list = equations.eliminated();
        let eliminated = list
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let mut value = e.value;
                for later in &list[i + 1..] {
                    let v1 = later.value.dt();
                    value = value.subs(&[
                        (Expr::coordinate(&later.coordinate), later.value),
                        (Expr::rate(&later.coordinate, 1), v1),
                        (Expr::rate(&later.coordinate, 2), v1.dt()),
                    ]);
                }
                (e.coordinate.clone(), value)
            })
            .collect();
        AuxBuilder {
            equations,
            eliminated,
            outputs: Vec::new(),
        }
    }

    /// Where coordinate `q` takes its value: kept, or eliminated (value, rate, acceleration).
    fn source(&mut self, q: &str) -> Option<Source> {
        if let Some(k) = self.equations.coordinates().iter().position(|c| c == q) {
            return Some(Source::Kept(k));
        }
        let value = self.eliminated.iter().find(|(c, _)| c == q)?.1;
        Some(self.motion(value))
    }

    /// A motion `x(q, t)`: its value, rate and acceleration as auxiliary outputs.
    fn motion(&mut self, x: Expr) -> Source {
        let at = self.outputs.len();
        let rate = x.dt();
        self.outputs.extend([x, rate, rate.dt()]);
        Source::Aux(at)
    }

    /// A vector's components as auxiliary outputs; where they start.
    fn vector(&mut self, v: &Vector) -> usize {
        let at = self.outputs.len();
        self.outputs.extend(v.iter().copied());
        at
    }

    /// The outputs compiled over `(q, q̇, q̈, t, values)`.
    fn compile(self, values: &[String]) -> Result<Tape, ReactionError> {
        let coordinates = self.equations.coordinates();
        let mut inputs: Vec<Symbol> = Vec::with_capacity(3 * coordinates.len() + 1 + values.len());
        for order in 0..3u8 {
            inputs.extend(coordinates.iter().filter_map(|q| {
                if order == 0 {
                    Expr::coordinate(q).as_symbol()
                } else {
                    Expr::rate(q, order).as_symbol()
                }
            }));
        }
        inputs.extend(Expr::time().as_symbol());
        inputs.extend(values.iter().filter_map(|v| Expr::symbol(v).as_symbol()));
        let outputs: Vec<Expr> = self.outputs.iter().map(|e| e.normal()).collect();
        Tape::compile(&outputs, &inputs).map_err(|e| {
            not_numeric(
                "(directions and eliminated coordinates)",
                match e {
                    numeric::TapeError::UnboundSymbol { name } => NumericGap::UnknownSymbol(name),
                    other => NumericGap::Uncompiled(other.to_string()),
                },
            )
        })
    }
}
