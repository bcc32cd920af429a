//! [`Analysis`]: one mechanical system and everything lagrange works out for it, each part
//! computed once, when first asked for, and kept. Values (parameters, inputs, initial state)
//! are applied here and nowhere else; the equations hold parameters as symbols, so changing a
//! value keeps them and drops only what depends on numbers.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

use cas::{Expr, Symbol};
use mechanics::{Equations, ReactionRequest, System};

use crate::assign::{self, Assignment, AssignmentError};
use crate::error::{Error, ErrorKind, ModelErrors};

/// The model a system was read from, kept for what only the model knows: its initial values,
/// its `simulate` statement, the reactions it asks for and the text for messages.
#[derive(Debug, Clone)]
pub struct Source {
    /// The checked model (with the values set since).
    pub model: model::Model,
    /// The model text.
    pub text: String,
    /// The file it came from, if any.
    pub path: Option<PathBuf>,
}

/// A system and its analysis. See the crate documentation for a tour.
#[derive(Debug)]
pub struct Analysis {
    system: System,
    source: Option<Source>,
    /// Inputs given as functions of time.
    timed_inputs: Vec<(String, Expr)>,
    /// Initial values set by name: `(coordinate, rate?, value)`.
    initial: Vec<(String, bool, f64)>,
    /// Reactions asked for in code (a model's come from its text).
    requests: Option<Vec<ReactionRequest>>,
    /// The limits of the symbolic work (`None`: the process-wide ones).
    work_limits: Option<cas::WorkLimits>,
    equations: OnceLock<Result<Equations, Error>>,
    derivations: AtomicUsize,
    /// How many times reactions were derived (all of them, or the one-sided ones alone).
    pub(crate) reaction_derivations: AtomicUsize,
    pub(crate) contacts: OnceLock<Result<Vec<(String, Expr)>, Error>>,
    pub(crate) reactions: OnceLock<Result<Option<crate::Reactions>, Error>>,
    /// How reactions are computed.
    pub(crate) reaction_route: crate::ReactionRoute,
    /// The reactions compiled for numeric evaluation (value names fixed when compiled).
    pub(crate) evaluator: OnceLock<Result<Option<mechanics::ReactionEvaluator>, Error>>,
    pub(crate) equilibria: OnceLock<Result<crate::Equilibria, Error>>,
}

impl Clone for Analysis {
    /// A copy with the same system and values; what was computed is computed again on demand.
    fn clone(&self) -> Analysis {
        let mut copy = Analysis::new(self.system.clone(), self.source.clone());
        copy.timed_inputs.clone_from(&self.timed_inputs);
        copy.initial.clone_from(&self.initial);
        copy.requests.clone_from(&self.requests);
        copy.work_limits = self.work_limits;
        copy.reaction_route = self.reaction_route;
        if let Some(Ok(equations)) = self.equations.get() {
            let _ = copy.equations.set(Ok(equations.clone()));
        }
        // Contacts depend on the equations alone, not on values.
        if let Some(Ok(contacts)) = self.contacts.get() {
            let _ = copy.contacts.set(Ok(contacts.clone()));
        }
        copy
    }
}

impl Analysis {
    fn new(system: System, source: Option<Source>) -> Analysis {
        Analysis {
            system,
            source,
            timed_inputs: Vec::new(),
            initial: Vec::new(),
            requests: None,
            work_limits: None,
            equations: OnceLock::new(),
            derivations: AtomicUsize::new(0),
            reaction_derivations: AtomicUsize::new(0),
            contacts: OnceLock::new(),
            reactions: OnceLock::new(),
            reaction_route: crate::ReactionRoute::default(),
            evaluator: OnceLock::new(),
            equilibria: OnceLock::new(),
        }
    }

    /// The analysis of a system built in code.
    #[must_use]
    pub fn from_system(system: System) -> Analysis {
        Analysis::new(system, None)
    }

    /// Reads, checks and lowers model text.
    ///
    /// # Errors
    /// [`Error::Model`] with every mistake found, or a located lowering error.
    pub fn from_text(text: &str) -> Result<Analysis, Error> {
        Analysis::from_source(text.to_owned(), None)
    }

    /// Reads, checks and lowers a model file.
    ///
    /// # Errors
    /// [`Error::Read`] when the file cannot be read (or is not UTF-8), else as
    /// [`Analysis::from_text`].
    pub fn from_file(path: &Path) -> Result<Analysis, Error> {
        let bytes = std::fs::read(path).map_err(|e| Error::Read {
            path: path.to_owned(),
            reason: e.to_string(),
        })?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let at = e.utf8_error().valid_up_to();
            let valid = String::from_utf8_lossy(&e.as_bytes()[..at]).into_owned();
            let at = model::line_col(&valid, valid.len());
            Error::Read {
                path: path.to_owned(),
                reason: format!(
                    "it is not UTF-8 text (a byte that is not UTF-8 at line {}, column {}); save it as UTF-8",
                    at.line, at.column
                ),
            }
        })?;
        Analysis::from_source(text, Some(path.to_owned()))
    }

    fn from_source(text: String, path: Option<PathBuf>) -> Result<Analysis, Error> {
        let model = model::load(&text).map_err(|d| {
            Error::Model(ModelErrors {
                diagnostics: d.0,
                source: text.clone(),
            })
        })?;
        let system = model::lower(&model).map_err(|e| located(&text, &e))?;
        Ok(Analysis::new(system, Some(Source { model, text, path })))
    }

    /// The model's warnings drawn under their source lines (empty without any).
    #[must_use]
    pub fn warnings(&self, file: &str, options: model::RenderOptions) -> String {
        match &self.source {
            Some(source) if !source.model.warnings().is_empty() => {
                model::render(source.model.warnings(), file, &source.text, options)
            }
            _ => String::new(),
        }
    }

    /// The system.
    #[must_use]
    pub fn system(&self) -> &System {
        &self.system
    }

    /// The model it was read from, if it was.
    #[must_use]
    pub fn source(&self) -> Option<&Source> {
        self.source.as_ref()
    }

    /// Asks for reactions on a system built in code (a model asks in its text).
    #[must_use]
    pub fn with_reactions(mut self, requests: Vec<ReactionRequest>) -> Analysis {
        self.requests = Some(requests);
        self.contacts = OnceLock::new();
        self.forget_reactions();
        self
    }

    /// Sets a value: a parameter, an input (a number or, for an input, a function of `t`),
    /// an initial value `q` or rate `q_d` / `q'`. What depends on numbers is worked out
    /// again when next asked for; the equations are kept.
    ///
    /// # Errors
    /// [`Error::Assignment`] for an unknown name or a value that is not a number.
    pub fn set(&mut self, assignment: &Assignment) -> Result<(), Error> {
        let name = assignment.name.as_str();
        let text = assignment.text.as_str();
        let env = self.environment()?;
        let timed = assign::depends_on_time(assignment.value);
        let is_parameter = self.system.parameters().iter().any(|(n, _)| n == name);
        let is_input = self.system.inputs().iter().any(|(n, _)| n == name);
        if timed && !is_input {
            return Err(AssignmentError::TimeDependent {
                name: name.to_owned(),
            }
            .into());
        }
        if timed {
            self.timed_inputs.retain(|(n, _)| n != name);
            self.timed_inputs.push((name.to_owned(), assignment.value));
            self.forget_numbers();
            return Ok(());
        }
        let number = assign::number(text, assignment.value, &|s| env(s))?;
        // A value written without names stays exact (`pi/2`, `1/3`) for reports.
        let value = if cas_has_symbols(assignment.value) {
            Expr::float(number)
        } else {
            assignment.value
        };
        if is_parameter || is_input {
            if is_parameter {
                self.system.set_parameter(name, Some(value));
            } else {
                self.system.set_input(name, Some(value));
                self.timed_inputs.retain(|(n, _)| n != name);
            }
        } else {
            let (base, rate) = coordinate_of(name);
            let free = self.system.coordinates().iter().any(|q| q == base);
            if !free {
                return Err(self.unknown(name));
            }
            self.initial.retain(|(q, r, _)| !(q == base && *r == rate));
            self.initial.push((base.to_owned(), rate, number));
        }
        if let Some(source) = &mut self.source {
            if let Ok(model) = source.model.with_overrides(&[(name.to_owned(), number)]) {
                source.model = model;
            }
        }
        self.forget_numbers();
        Ok(())
    }

    /// [`Analysis::set`] for each, in order.
    ///
    /// # Errors
    /// The first refused one.
    pub fn set_all(&mut self, assignments: &[Assignment]) -> Result<(), Error> {
        assignments.iter().try_for_each(|a| self.set(a))
    }

    /// Sets a value by name: `analysis.set_value("g", 9.81)`.
    ///
    /// # Errors
    /// As [`Analysis::set`].
    pub fn set_value(&mut self, name: &str, value: f64) -> Result<(), Error> {
        self.set(&Assignment::number(name, value))
    }

    fn unknown(&self, name: &str) -> Error {
        let known = self
            .system
            .parameters()
            .iter()
            .chain(self.system.inputs())
            .map(|(n, _)| n.clone())
            .chain(
                self.system
                    .coordinates()
                    .iter()
                    .flat_map(|q| [q.clone(), format!("{q}_d")]),
            )
            .collect();
        AssignmentError::UnknownName {
            name: name.to_owned(),
            known,
        }
        .into()
    }

    fn forget_numbers(&mut self) {
        self.equilibria = OnceLock::new();
        // The one-sided scan of reactions reads the initial state; the compiled reactions
        // name the values (an input set to a function of time leaves them).
        self.forget_reactions();
    }

    /// Drops the reactions computed (closed forms and compiled), to be computed again.
    pub(crate) fn forget_reactions(&mut self) {
        self.reactions = OnceLock::new();
        self.evaluator = OnceLock::new();
    }

    /// Sets the limits of the symbolic work of this analysis' derivations (the default:
    /// `cas::work_limits()`, process-wide). What was already derived is kept; a derivation
    /// stopped by a limit ([`Error::WorkLimit`]) is tried again with the new limits.
    pub fn set_work_limits(&mut self, limits: cas::WorkLimits) {
        self.work_limits = Some(limits);
        let stopped =
            |r: Option<&Result<_, Error>>| matches!(r, Some(Err(e)) if e.work_limit().is_some());
        if stopped(self.equations.get()) {
            self.equations = OnceLock::new();
        }
        if matches!(self.reactions.get(), Some(Err(e)) if e.work_limit().is_some()) {
            self.forget_reactions();
        }
        if matches!(self.equilibria.get(), Some(Err(e)) if e.work_limit().is_some()) {
            self.equilibria = OnceLock::new();
        }
    }

    /// `f` under this analysis' work limits.
    pub(crate) fn within_limits<T>(&self, f: impl FnOnce() -> T) -> T {
        match self.work_limits {
            Some(limits) => cas::with_work_limits(limits, f),
            None => f(),
        }
    }

    /// `f` as one limited scope of the symbolic core under this analysis' work limits: past a
    /// limit, the located error of a derivation inside, or [`Error::WorkLimit`] saying `what`
    /// was under way.
    pub(crate) fn limited<T>(
        &self,
        what: &str,
        f: impl FnOnce() -> Result<T, Error>,
    ) -> Result<T, Error> {
        self.within_limits(|| match cas::run_limited(f) {
            (result, None) => result,
            (Err(e), Some(_)) if e.work_limit().is_some() => Err(e),
            (_, Some(error)) => Err(Error::WorkLimit {
                message: format!("{what}: {error}"),
                error,
                at: None,
            }),
        })
    }

    /// A work limit hit in the mechanics as [`Error::WorkLimit`], located at the model
    /// statement of the part that was being derived; other errors as they are.
    pub(crate) fn locate_work_limit(&self, error: Error) -> Error {
        use mechanics::{MechanicsError as M, ReactionError as R};
        let (part, limit) = match &error {
            Error::Mechanics(M::WorkLimit { part, error })
            | Error::Reactions(R::Mechanics {
                source: M::WorkLimit { part, error },
                ..
            }) => (part.clone(), error.clone()),
            Error::Reactions(R::WorkLimit(error)) => (None, error.clone()),
            _ => return error,
        };
        // A limit hit in a phase of the whole system (the sum of the parts, Lagrange's
        // equations) has no statement of its own: the coordinates it derives are named.
        let at = match part {
            Some(p) => self.statement_of(&p),
            None => self.coordinates_statement(),
        };
        Error::WorkLimit {
            message: error.to_string(),
            error: limit,
            at,
        }
    }

    /// Line and column of the first coordinate's name in the `coordinates` statement.
    fn coordinates_statement(&self) -> Option<(usize, usize)> {
        let source = self.source.as_ref()?;
        let span = source.model.coordinates().first()?.name.span;
        let at = model::line_col(&source.text, span.start);
        Some((at.line, at.column))
    }

    /// Line and column of the model statement a part of the system comes from.
    fn statement_of(&self, part: &mechanics::Part) -> Option<(usize, usize)> {
        let source = self.source.as_ref()?;
        let model = &source.model;
        let span = match part {
            mechanics::Part::Particle(name) => {
                model
                    .particles()
                    .iter()
                    .find(|p| &model.point(p.point).name.name == name)?
                    .span
            }
            mechanics::Part::Body(name) => {
                model
                    .bodies()
                    .iter()
                    .find(|b| &b.name.name == name)?
                    .name
                    .span
            }
            mechanics::Part::Constraint(name) => {
                model
                    .constraints()
                    .iter()
                    .find(|c| c.name.as_ref().map_or("constraint", |n| n.name.as_str()) == name)?
                    .span
            }
            // Loads that do no virtual work are not lowered; then the indices differ.
            mechanics::Part::Load(index) if model.loads().len() == self.system.loads().len() => {
                model.loads().get(*index)?.span
            }
            _ => return None,
        };
        let at = model::line_col(&source.text, span.start);
        Some((at.line, at.column))
    }

    /// The equations of motion (Lagrange II), derived once.
    ///
    /// # Errors
    /// [`Error::Mechanics`] when the system is degenerate (a singular mass matrix, …),
    /// [`Error::Constraints`] naming constraints that contradict or restate one another, or
    /// [`Error::WorkLimit`] when the derivation outgrows the work limits.
    pub fn equations(&self) -> Result<&Equations, Error> {
        self.equations
            .get_or_init(|| {
                self.derivations.fetch_add(1, Ordering::Relaxed);
                let equations = self
                    .within_limits(|| mechanics::derive(&self.system))
                    .map_err(|e| self.locate_work_limit(e.into()))?;
                // Constraints that contradict or restate one another leave the multipliers
                // undetermined: nothing downstream is meaningful.
                match mechanics::constraint_conflict(&self.system, &equations) {
                    Some(conflict) => Err(conflict.into()),
                    None => Ok(equations),
                }
            })
            .as_ref()
            .map_err(Clone::clone)
    }

    /// How many times the equations were derived (one at most: the tests count it).
    #[must_use]
    pub fn derivations(&self) -> usize {
        self.derivations.load(Ordering::Relaxed)
    }

    /// How many times reactions were derived (each costs far more than the equations).
    #[must_use]
    pub fn reaction_derivations(&self) -> usize {
        self.reaction_derivations.load(Ordering::Relaxed)
    }

    /// Inputs given as functions of time.
    #[must_use]
    pub fn timed_inputs(&self) -> &[(String, Expr)] {
        &self.timed_inputs
    }

    /// The numeric value of every parameter and of every input held constant (an input
    /// without a value is held at 0); parameters without a value are left out.
    ///
    /// # Errors
    /// [`Error::MissingValue`] when a value given is not a number.
    pub fn values(&self) -> Result<Vec<(String, f64)>, Error> {
        let mut values: Vec<(String, f64)> = Vec::new();
        let lookup = |values: &[(String, f64)], s: Symbol| {
            values.iter().find(|(n, _)| n == s.name()).map(|(_, v)| *v)
        };
        // Parameters refer to earlier ones, so one pass in order gives all their values.
        for (name, value) in self.system.parameters() {
            if let Some(e) = value {
                let x = e
                    .eval(&|s| lookup(&values, s))
                    .map_err(|_| Error::MissingValue {
                        what: format!("the value of parameter `{name}`"),
                    })?;
                values.push((name.clone(), x));
            }
        }
        for (name, value) in self.system.inputs() {
            if self.timed_inputs.iter().any(|(n, _)| n == name) {
                continue;
            }
            let x = match value {
                Some(e) => e
                    .eval(&|s| lookup(&values, s))
                    .map_err(|_| Error::MissingValue {
                        what: format!("the value of input `{name}`"),
                    })?,
                None => 0.0,
            };
            values.push((name.clone(), x));
        }
        Ok(values)
    }

    fn environment(&self) -> Result<impl Fn(Symbol) -> Option<f64>, Error> {
        let values = self.values().unwrap_or_default();
        Ok(move |s: Symbol| values.iter().find(|(n, _)| n == s.name()).map(|(_, v)| *v))
    }

    /// The initial state in the order of the equations' coordinates: positions, then rates.
    /// Set values win, then the model's `initial` statement, then 0.
    ///
    /// # Errors
    /// As [`Analysis::equations`], or [`Error::MissingValue`] for an initial value that is not
    /// a number.
    pub fn initial_state(&self) -> Result<Vec<f64>, Error> {
        let coordinates = self.equations()?.coordinates();
        let n = coordinates.len();
        let mut state = vec![0.0; 2 * n];
        for (k, q) in coordinates.iter().enumerate() {
            for (rate, slot) in [(false, k), (true, n + k)] {
                state[slot] = self.initial_value(q, rate)?;
            }
        }
        Ok(state)
    }

    /// The coordinates whose rates were set since the model was read.
    pub(crate) fn initial_rates_set(&self) -> Vec<String> {
        self.initial
            .iter()
            .filter(|(_, rate, _)| *rate)
            .map(|(q, _, _)| q.clone())
            .collect()
    }

    pub(crate) fn initial_value(&self, q: &str, rate: bool) -> Result<f64, Error> {
        if let Some((_, _, v)) = self.initial.iter().find(|(c, r, _)| c == q && *r == rate) {
            return Ok(*v);
        }
        match &self.source {
            Some(source) => {
                source
                    .model
                    .initial_value(q, rate)
                    .ok_or_else(|| Error::MissingValue {
                        what: format!("the initial value of `{q}{}`", if rate { "_d" } else { "" }),
                    })
            }
            None => Ok(0.0),
        }
    }

    /// The reactions asked for: in code ([`Analysis::with_reactions`]) or by the model.
    ///
    /// # Errors
    /// A located error when the model's request cannot be built.
    pub(crate) fn requests(&self) -> Result<Vec<ReactionRequest>, Error> {
        if let Some(requests) = &self.requests {
            return Ok(requests.clone());
        }
        match &self.source {
            Some(source) => {
                model::reaction_requests(&source.model).map_err(|e| located(&source.text, &e))
            }
            None => Ok(Vec::new()),
        }
    }
}

/// `q_d` / `q'` → (`q`, true); `q` → (`q`, false).
fn coordinate_of(name: &str) -> (&str, bool) {
    if let Some(base) = name.strip_suffix("_d") {
        (base, true)
    } else if let Some(base) = name.strip_suffix('\'') {
        (base, true)
    } else {
        (name, false)
    }
}

fn cas_has_symbols(e: Expr) -> bool {
    let mut stack = vec![e];
    while let Some(e) = stack.pop() {
        if matches!(e.node(), cas::Node::Symbol(_)) {
            return true;
        }
        stack.extend_from_slice(e.children());
    }
    false
}

/// A lowering error with the line and column of the model text it comes from.
pub(crate) fn located(text: &str, error: &model::LowerError) -> Error {
    let at = model::line_col(text, error.span().start);
    Error::Located {
        message: error.to_string(),
        line: at.line,
        column: at.column,
        kind: ErrorKind::Input,
    }
}
