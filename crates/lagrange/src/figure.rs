//! [`Analysis::figure`]: the system drawn at its initial state (or the values set since), as
//! a textbook figure (crates/draw). The figure needs the model, which knows the geometry the
//! `System` no longer holds (where a spring is anchored, which point a link starts from).

use crate::analysis::{Analysis, Source};
use crate::error::Error;

/// The most frames an animation of a mode may have.
const MAX_FRAMES: f64 = 100_000.0;

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
        let source = self.animated_source(fps)?;
        let options = crate::SimulationOptions {
            t_end,
            output_step: Some(1.0 / fps),
            ..crate::SimulationOptions::default()
        };
        let run = self.simulate(&options)?;
        let model = &source.model;
        let column = |name: &str| run.columns.iter().position(|c| c == name);
        let frames = run
            .rows
            .iter()
            .map(|row| {
                let q = model
                    .coordinates()
                    .iter()
                    .map(|c| column(&c.name.name).map_or(0.0, |k| row[k]))
                    .collect();
                (row[0], q)
            })
            .collect();
        self.animate_frames(source, frames, traces, title(source, None))
    }

    /// The model to animate at `fps` frames per second: refused for a system built in code
    /// (no model to draw) or a frame rate that is not a positive number.
    fn animated_source(&self, fps: f64) -> Result<&Source, Error> {
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
        Ok(source)
    }

    /// The `k`-th linearized mode (from 1, by increasing frequency) about the first stable
    /// equilibrium, animated: `q(t) = q₀ + a φₖ cos(ωₖ t)` at `fps` frames per second from 0
    /// to `t_end` (default: three periods). The amplitude `a` moves the drawn point that
    /// moves farthest by an eighth of the figure's extent: visible, and still small.
    ///
    /// # Errors
    /// As [`Analysis::equilibria`] and [`Analysis::figure`]; [`Error::NotAvailable`] when no
    /// equilibrium is stable, when there is no mode `k` (or it does not oscillate), or for a
    /// frame rate or end time that is not a positive number.
    pub fn mode_animation(
        &self,
        k: usize,
        t_end: Option<f64>,
        fps: f64,
        traces: &[String],
    ) -> Result<String, Error> {
        let source = self.animated_source(fps)?;
        let mode = crate::modes::Mode::of(self, k)?;
        let t_end = t_end.unwrap_or(3.0 * std::f64::consts::TAU / mode.omega);
        let count = t_end * fps;
        if !(count.is_finite() && t_end > 0.0 && count <= MAX_FRAMES) {
            return Err(Error::NotAvailable(format!(
                "an animation of mode {k} to t = {t_end} at {fps} frames per second: give a \
                 positive end time and at most {MAX_FRAMES} frames"
            )));
        }
        let epsilon = mode.epsilon();
        let at_rest = self.scene_at(source, self.model_coordinates(source, &mode, 0.0))?;
        let nudged = self.scene_at(source, self.model_coordinates(source, &mode, epsilon))?;
        let amplitude = mode.amplitude(&at_rest, &nudged, epsilon);
        // Bounded above: `count` is at most MAX_FRAMES.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let frames = (0..=count.floor() as usize)
            .map(|i| {
                let t = i as f64 / fps;
                let q = self.model_coordinates(source, &mode, amplitude * (mode.omega * t).cos());
                (t, q)
            })
            .collect();
        let what = format!("mode {k}, ω = {:.4} rad/s", mode.omega);
        self.animate_frames(source, frames, traces, title(source, Some(&what)))
    }

    /// The model's coordinates at `q₀ + s φ` (a driven coordinate at 0: the figure's time
    /// drives it; an eliminated one at 0 until [`Analysis::apply_eliminations`]).
    fn model_coordinates(&self, source: &Source, mode: &crate::modes::Mode, s: f64) -> Vec<f64> {
        source
            .model
            .coordinates()
            .iter()
            .map(|c| mode.value(&c.name.name, s))
            .collect()
    }

    /// The scene of the figure at `q` (eliminated coordinates filled in), at time 0.
    fn scene_at(&self, source: &Source, mut q: Vec<f64>) -> Result<draw::Scene, Error> {
        self.apply_eliminations(&source.model, &mut q)?;
        let at = draw::Configuration {
            time: 0.0,
            coordinates: q,
        };
        Ok(draw::figure(&source.model, at)?.scene)
    }

    /// Draws `(time, coordinates)` frames, eliminated coordinates filled in, as a page.
    fn animate_frames(
        &self,
        source: &Source,
        frames: Vec<(f64, Vec<f64>)>,
        traces: &[String],
        title: String,
    ) -> Result<String, Error> {
        let model = &source.model;
        let mut configurations = Vec::with_capacity(frames.len());
        for (time, mut coordinates) in frames {
            self.apply_eliminations(model, &mut coordinates)?;
            configurations.push(draw::Configuration { time, coordinates });
        }
        let options = draw::AnimationOptions {
            traces: traces.to_vec(),
            title,
        };
        Ok(draw::animation(model, &configurations, &options)?)
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

/// A page title: the model file's name, and what is animated when it is not the motion.
fn title(source: &Source, what: Option<&str>) -> String {
    let stem = source
        .path
        .as_ref()
        .and_then(|p| p.file_stem())
        .map_or_else(
            || "lagrange".to_owned(),
            |s| s.to_string_lossy().into_owned(),
        );
    match what {
        Some(what) => format!("{stem}: {what}"),
        None => stem,
    }
}
