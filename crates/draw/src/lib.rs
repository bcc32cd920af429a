//! Pictures of a mechanical system: the geometry of a model at a configuration, computed
//! from the model, as a textbook figure in SVG.
//!
//! Three steps, each a plain value the next consumes:
//!
//! 1. [`Scene`]: what to draw, in world coordinates, read off the model by evaluating its
//!    geometry at the configuration and near it (`build`, `marks`, `loads`): fixed points get
//!    supports, rigid links and slender bodies become rods, bodies with an axis of symmetry
//!    disks, particles dots (or blocks when they slide along a line), springs zigzags (coils
//!    when torsional), dampers dashpots, forces and couples arrows, and each generalized
//!    coordinate an angle arc or a displacement arrow.
//! 2. [`View`]: the projection, square-on for a planar system, oblique for a spatial one.
//! 3. SVG text with labels placed so that they overlap neither each other nor the drawing
//!    where a free place exists (`layout`).
//!
//! ```
//! let model = model::load(
//!     "coordinates theta\nparameters m = 1, l = 1, g = 9.81\nframe N\n\
//!      point P = l*sin(theta)*N.x - l*cos(theta)*N.y\nparticle P mass m\ngravity -g*N.y\n",
//! )
//! .expect("a valid model");
//! let at = draw::Configuration { time: 0.0, coordinates: vec![0.5] };
//! let figure = draw::figure(&model, at)?;
//! assert!(figure.svg.starts_with("<svg"));
//! assert!(figure.svg.contains(r#"id="point-P""#));
//! # Ok::<(), draw::DrawError>(())
//! ```
#![warn(missing_docs)]

mod animate;
mod build;
pub mod layout;
mod loads;
mod marks;
mod names;
mod raster;
mod sample;
mod scene;
mod svg;
mod view;

pub use animate::{animation, AnimationOptions};
pub use layout::Rect;
pub use names::{symbol, text};
pub use raster::RasterError;
pub use sample::Configuration;
pub use scene::{ArcKind, ArrowKind, Item, Scene, P3};
pub use view::View;

/// Why a figure could not be drawn.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DrawError {
    /// The configuration does not give a finite value to each coordinate of the model.
    #[error("the configuration gives {given} coordinate values, but the model has {needed} coordinates (or a value is not finite)")]
    State {
        /// Values given.
        given: usize,
        /// Coordinates of the model.
        needed: usize,
    },
    /// An expression of the geometry could not be evaluated.
    #[error("cannot evaluate `{what}` for the figure: {source}")]
    Evaluate {
        /// The expression, as written in the model.
        what: String,
        /// Why.
        source: model::EvaluationError,
    },
}

/// A drawn figure.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// The SVG document.
    pub svg: String,
    /// What it shows, in world coordinates.
    pub scene: Scene,
    /// The projection used.
    pub view: View,
    /// Each label's id and page box.
    pub labels: Vec<(String, Rect)>,
    /// The labels that touch the drawing because no clear place was found near their point.
    pub touching: Vec<String>,
    /// What was drawn, for [`Figure::png`].
    shapes: Vec<raster::Shape>,
    /// The page box of the picture.
    bounds: ((f64, f64), (f64, f64)),
}

impl Figure {
    /// The figure as a PNG image, `scale` image pixels per SVG pixel (2 for print).
    ///
    /// # Errors
    /// [`RasterError::Size`] when the image would be empty or more than 16384 pixels on a
    /// side; [`RasterError::Encode`] if the encoder fails.
    pub fn png(&self, scale: f64) -> Result<Vec<u8>, RasterError> {
        raster::png(&self.shapes, self.bounds, scale)
    }
}

/// The figure of `model` at `at`.
///
/// # Errors
/// [`DrawError::State`] for a configuration of the wrong length; [`DrawError::Evaluate`]
/// when a parameter the geometry needs has no value.
pub fn figure(model: &model::Model, at: Configuration) -> Result<Figure, DrawError> {
    let sampler = sample::Sampler::new(model, at)?;
    let (scene, plane) = build::scene(&sampler, None)?;
    let view = view::fit(&scene, plane);
    let written = svg::write(&scene, &view);
    Ok(Figure {
        svg: written.svg,
        scene,
        view,
        labels: written.labels,
        touching: written.touching,
        shapes: written.shapes,
        bounds: written.bounds,
    })
}
