//! [`Analysis::figure`]: the system drawn at its initial state (or the values set since), as
//! a textbook figure (crates/draw). The figure needs the model, which knows the geometry the
//! `System` no longer holds (where a spring is anchored, which point a link starts from).

use crate::analysis::Analysis;
use crate::error::Error;

impl Analysis {
    /// The figure of the model at time `time`, with the coordinates at their initial values
    /// (values set with [`Analysis::set`] win); a coordinate that a constraint eliminates
    /// takes the value the constraint gives it.
    ///
    /// # Errors
    /// [`Error::NotAvailable`] for a system built in code (it has no model to draw);
    /// [`Error::MissingValue`] for an initial value that is not a number; [`Error::Figure`]
    /// when a value the geometry needs is missing; for a model with gear or velocity
    /// constraints, as [`Analysis::equations`].
    pub fn figure(&self, time: f64) -> Result<draw::Figure, Error> {
        let Some(source) = self.source() else {
            return Err(Error::NotAvailable(
                "a system built in code has no model to draw".to_owned(),
            ));
        };
        let model = &source.model;
        let mut coordinates = Vec::with_capacity(model.coordinates().len());
        for c in model.coordinates() {
            coordinates.push(match c.driven {
                Some(_) => 0.0,
                None => self.initial_value(&c.name.name, false)?,
            });
        }
        self.apply_eliminations(model, &mut coordinates)?;
        let at = draw::Configuration { time, coordinates };
        Ok(draw::figure(model, at)?)
    }

    /// The simulated motion as a self-contained HTML animation: one frame per `1/fps` from the
    /// initial state to `t_end` (or the model's `simulate` end), the paths of the points named
    /// in `traces` drawn.
    ///
    /// # Errors
    /// As [`Analysis::simulate`] and [`Analysis::figure`]; [`Error::NotAvailable`] for a
    /// frame rate that is not positive.
    pub fn animation(
        &self,
        t_end: Option<f64>,
        fps: f64,
        traces: &[String],
    ) -> Result<String, Error> {
        let Some(source) = self.source() else {
            return Err(Error::NotAvailable(
                "a system built in code has no model to draw".to_owned(),
            ));
        };
        if !(fps.is_finite() && fps > 0.0) {
            return Err(Error::NotAvailable(format!(
                "a frame rate must be a positive number, not {fps}"
            )));
        }
        let options = crate::SimulationOptions {
            t_end,
            output_step: Some(1.0 / fps),
            ..crate::SimulationOptions::default()
        };
        let run = self.simulate(&options)?;
        let model = &source.model;
        let column = |name: &str| run.columns.iter().position(|c| c == name);
        let mut frames = Vec::with_capacity(run.rows.len());
        for row in &run.rows {
            let mut q: Vec<f64> = model
                .coordinates()
                .iter()
                .map(|c| column(&c.name.name).map_or(0.0, |k| row[k]))
                .collect();
            self.apply_eliminations(model, &mut q)?;
            frames.push(draw::Configuration {
                time: row[0],
                coordinates: q,
            });
        }
        let title = source
            .path
            .as_ref()
            .and_then(|p| p.file_stem())
            .map_or_else(
                || "lagrange".to_owned(),
                |s| s.to_string_lossy().into_owned(),
            );
        let options = draw::AnimationOptions {
            traces: traces.to_vec(),
            title,
        };
        Ok(draw::animation(model, &frames, &options)?)
    }

    /// Gives each coordinate a constraint eliminates its value in the others. Only gear and
    /// velocity constraints eliminate coordinates, so other models are not derived here.
    fn apply_eliminations(&self, model: &model::Model, q: &mut [f64]) -> Result<(), Error> {
        let eliminating = model.constraints().iter().any(|c| {
            matches!(
                c.kind,
                model::ConstraintKind::Gear { .. } | model::ConstraintKind::Velocity { .. }
            )
        });
        if !eliminating {
            return Ok(());
        }
        let equations = self.equations()?;
        let values = self.values()?;
        let names: Vec<&str> = model
            .coordinates()
            .iter()
            .map(|c| c.name.name.as_str())
            .collect();
        for e in equations.eliminated() {
            let lookup = |s: cas::Symbol| {
                let name = s.name();
                names
                    .iter()
                    .position(|n| *n == name)
                    .map(|k| q[k])
                    .or_else(|| values.iter().find(|(n, _)| n == name).map(|(_, v)| *v))
            };
            let value = e.value.eval(&lookup).map_err(|_| Error::MissingValue {
                what: format!(
                    "the value of `{}` that `{}` gives",
                    e.coordinate, e.constraint
                ),
            })?;
            if let Some(k) = names.iter().position(|n| *n == e.coordinate) {
                q[k] = value;
            }
        }
        Ok(())
    }
}
