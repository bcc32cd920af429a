//! Constraint reactions of an [`Analysis`]: all those asked for (derived only when asked
//! for: they cost far more than the equations of motion), and the one-sided ones alone
//! (contacts, ropes, rolling contacts' normal forces), which decide where a simulation stops.

use std::sync::atomic::Ordering;

use cas::Expr;
use mechanics::{Agreement, Reaction, ReactionRequest};
use report::UnilateralReport;

use crate::{Analysis, Error, ReactionValues};

/// The reactions a system asks for.
#[derive(Debug, Clone)]
pub struct Reactions {
    /// The independent coordinates the reactions are written in.
    pub coordinates: Vec<String>,
    /// The reactions, in the order asked.
    pub reactions: Vec<Reaction>,
    /// For each reaction, its one-sided analysis when it pushes or pulls only.
    pub unilateral: Vec<Option<UnilateralReport>>,
    /// When the reactions are evaluated numerically instead ([`crate::ReactionRoute`]; then
    /// `reactions` is empty): their values at the run's initial state.
    pub numeric: Option<ReactionValues>,
}

impl Reactions {
    /// Whether Lagrange I and Newton–Euler disagree on any reaction (a bug of lagrange).
    #[must_use]
    pub fn disagree(&self) -> bool {
        self.reactions
            .iter()
            .any(|r| r.agreement == Agreement::Disagree)
    }

    /// The reactions as `lagrange reactions` prints them: each by both methods, and for a
    /// one-sided one where it holds.
    #[must_use]
    pub fn to_text(&self) -> String {
        if let Some(values) = &self.numeric {
            let sentence = NUMERIC_SENTENCE.replacen("the", "The", 1);
            return format!("{sentence}.\n{}", values.to_text());
        }
        let texts: Vec<String> = (self.reactions.iter().zip(&self.unilateral))
            .map(|(r, u)| report::reaction_text(r, u.as_ref()))
            .collect();
        texts.join("\n")
    }

    /// The reactions as JSON (docs/json.md).
    #[must_use]
    pub fn to_json(&self) -> serde_json::Value {
        let mut value =
            report::reactions_json(&self.coordinates, &self.reactions, &self.unilateral);
        if let (Some(numeric), Some(object)) = (&self.numeric, value.as_object_mut()) {
            object.insert("numeric".into(), numeric.to_json());
        }
        value
    }
}

/// What a solution or `lagrange reactions` says when the reactions are evaluated numerically.
pub(crate) const NUMERIC_SENTENCE: &str = "the reactions are evaluated numerically, state by state (their closed form would be large; the closed-form route derives it)";

/// Whether a request is for a force that can only push or pull.
pub(crate) fn one_sided(request: &ReactionRequest) -> bool {
    matches!(request, ReactionRequest::Release(r) if r.kind.is_unilateral() || r.normal.is_some())
}

impl Analysis {
    /// Every reaction asked for, by Lagrange I and Newton–Euler; `None` when none is.
    ///
    /// # Errors
    /// As [`Analysis::equations`], or [`Error::Reactions`].
    pub fn reactions(&self) -> Result<Option<&Reactions>, Error> {
        self.reactions
            .get_or_init(|| self.compute_reactions())
            .as_ref()
            .map(Option::as_ref)
            .map_err(Clone::clone)
    }

    fn compute_reactions(&self) -> Result<Option<Reactions>, Error> {
        let requests = self.requests()?;
        if requests.is_empty() {
            return Ok(None);
        }
        let equations = self.equations()?;
        if self.numeric_reactions_chosen() {
            return Ok(Some(Reactions {
                coordinates: equations.coordinates().to_vec(),
                reactions: Vec::new(),
                unilateral: Vec::new(),
                numeric: Some(self.reactions_at_start()?),
            }));
        }
        self.reaction_derivations.fetch_add(1, Ordering::Relaxed);
        let reactions = self
            .within_limits(|| mechanics::reactions_of(self.system(), equations, &requests))
            .map_err(|e| self.locate_work_limit(e.into()))?;
        let unilateral = reactions
            .iter()
            .map(|r| {
                let (value, _) = r.along?;
                Some(UnilateralReport {
                    along_motion: mechanics::along_motion(equations, value),
                    scan: self.scan(value),
                })
            })
            .collect();
        Ok(Some(Reactions {
            coordinates: equations.coordinates().to_vec(),
            reactions,
            unilateral,
            numeric: None,
        }))
    }

    /// The one-sided reactions asked for, `(name, value)` with `value ≥ 0` while the
    /// constraint holds. Only these are derived (or read from [`Analysis::reactions`] when
    /// that was already asked for): a bilateral hinge costs nothing here.
    ///
    /// # Errors
    /// As [`Analysis::reactions`].
    pub fn one_sided_contacts(&self) -> Result<&[(String, Expr)], Error> {
        self.contacts
            .get_or_init(|| {
                let along = |reactions: &[Reaction]| {
                    reactions
                        .iter()
                        .filter_map(|r| r.along.map(|(value, _)| (r.name.clone(), value)))
                        .collect()
                };
                // Closed forms already derived serve; numeric values do not (a stop event is
                // an expression of the state).
                match self.reactions.get() {
                    Some(Ok(None)) => return Ok(Vec::new()),
                    Some(Ok(Some(computed))) if computed.numeric.is_none() => {
                        return Ok(along(&computed.reactions));
                    }
                    _ => {}
                }
                let requests: Vec<ReactionRequest> =
                    self.requests()?.into_iter().filter(one_sided).collect();
                if requests.is_empty() {
                    return Ok(Vec::new());
                }
                let equations = self.equations()?;
                self.reaction_derivations.fetch_add(1, Ordering::Relaxed);
                let reactions = self
                    .within_limits(|| mechanics::reactions_of(self.system(), equations, &requests))
                    .map_err(|e| self.locate_work_limit(e.into()))?;
                Ok(along(&reactions))
            })
            .as_ref()
            .map(Vec::as_slice)
            .map_err(Clone::clone)
    }

    /// Where a one-sided reaction of a one-coordinate system changes sign, from the initial
    /// state, with the model's values.
    fn scan(&self, value: Expr) -> Option<mechanics::Unilateral> {
        let equations = self.equations().ok()?;
        if equations.coordinates().len() != 1 {
            return None;
        }
        let state = self.initial_state().ok()?;
        let values = self.values().ok()?;
        let lookup = |s: cas::Symbol| values.iter().find(|(n, _)| n == s.name()).map(|(_, v)| *v);
        mechanics::scan_unilateral(equations, value, (state[0], state[1]), &lookup)
    }
}

/// The multipliers of the constraints kept with multipliers at one state, solved numerically
/// on the compiled equations (`[M Aᵀ; A 0] [q̈; λ] = [f; b]`): what is printed when the
/// closed form would be too large.
#[derive(Debug, Clone, PartialEq)]
pub struct NumericMultipliers {
    /// The time of the state.
    pub t: f64,
    /// The state: the coordinates, then their rates.
    pub state: Vec<f64>,
    /// The coordinates' names.
    pub coordinates: Vec<String>,
    /// Each constraint row's constraint name and multiplier `λ` (rows that depend on others
    /// at the state get 0).
    pub multipliers: Vec<(String, f64)>,
}

impl NumericMultipliers {
    /// The multipliers as text: the state, then `λ` of each row by its constraint's name.
    #[must_use]
    pub fn to_text(&self) -> String {
        let n = self.coordinates.len();
        let state: Vec<String> = self
            .coordinates
            .iter()
            .zip(&self.state)
            .map(|(q, x)| format!("{q} = {x}"))
            .chain(
                self.coordinates
                    .iter()
                    .zip(&self.state[n..])
                    .map(|(q, x)| format!("{q}' = {x}")),
            )
            .collect();
        let mut text = format!(
            "multipliers λ of M q̈ + Aᵀλ = f, solved numerically at t = {} ({}):\n",
            self.t,
            state.join(", ")
        );
        for (name, value) in &self.multipliers {
            text.push_str(&format!("  {name}: λ = {value:.9e}\n"));
        }
        text
    }
}

impl Error {
    /// Whether this is the refusal of reactions too large for closed form, after which the
    /// numeric multipliers ([`Analysis::multipliers_at_start`]) are what can be given.
    #[must_use]
    pub fn is_too_large_for_closed_form(&self) -> bool {
        matches!(
            self,
            Error::Reactions(mechanics::ReactionError::TooLarge { .. })
        )
    }
}

impl Analysis {
    /// The multipliers at the run's initial state (the model's `initial`, projected onto the
    /// constraints), solved numerically on compiled equations: no symbolic solve, so it
    /// costs a derivation and a compilation whatever the size of the closed form.
    ///
    /// # Errors
    /// As [`Analysis::simulation`] (with an end time of one time unit after the start when
    /// the model gives none: only the initial state is used), or a singular KKT matrix there.
    pub fn multipliers_at_start(&self) -> Result<NumericMultipliers, Error> {
        let mut options = crate::SimulationOptions::default();
        if self.settings(&options).is_err() {
            options.t_end = Some(options.t_start.unwrap_or(0.0) + 1.0);
        }
        let mut simulation = self.simulation(&options)?;
        let t = simulation.span().0;
        let state = simulation.initial_state().to_vec();
        let values = simulation.multipliers_at(t, &state)?;
        let names = self.equations()?.constraint_names();
        Ok(NumericMultipliers {
            t,
            state,
            coordinates: self.equations()?.coordinates().to_vec(),
            multipliers: names.iter().cloned().zip(values).collect(),
        })
    }
}
