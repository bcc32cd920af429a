//! Geometry and mass: frames (with their rotations), points, particles and bodies, with the
//! checks on masses and inertia tensors.

use super::expr::Place;
use super::scope::{Level, Target};
use super::{id, name, Checker};
use crate::ast::{self, Ident};
use crate::diagnostic::{Diagnostic, DiagnosticKind, NameKind, Type};
use crate::model::*;
use crate::span::Span;

impl Checker {
    pub(super) fn point(&mut self, ident: &Ident, position: &ast::Expr) {
        let Some(position) = self.expr(
            position,
            Type::Vector,
            Place::configuration("a point's position"),
        ) else {
            self.poison(ident, NameKind::Point);
            return;
        };
        let target = Target::Point(PointId(id(self.model.points.len())));
        let level = self.level_of(&position);
        if self.declare(ident, NameKind::Point, target, level) {
            self.point_levels.push(level);
            self.model.points.push(Point {
                name: name(ident),
                position: Some(position),
            });
        }
    }

    pub(super) fn particle(&mut self, point: &Ident, mass: &ast::Expr, span: Span) {
        let target = self.lookup(point, NameKind::Point);
        let mass = self.mass(mass);
        if let (Some(Target::Point(point)), Some(mass)) = (target, mass) {
            self.model.particles.push(Particle { point, mass, span });
        }
    }

    pub(super) fn frame(&mut self, ident: &Ident, rotation: Option<&(Ident, Vec<ast::Rotation>)>) {
        let target = Target::Frame(FrameId(id(self.model.frames.len())));
        let Some((parent, rotations)) = rotation else {
            if let Some((first_name, first)) = &self.inertial {
                self.diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::SecondInertialFrame { first_name: first_name.clone(), first: *first },
                        ident.span,
                    )
                    .with_related(*first, "the inertial frame")
                    .with_help(format!(
                        "Define `{}` relative to `{first_name}`: `frame {} = {first_name} rotated … about z`.",
                        ident.name, ident.name
                    )),
                );
                self.poison(ident, NameKind::Frame);
                return;
            }
            if self.declare(ident, NameKind::Frame, target, Level::Constant) {
                self.inertial = Some((ident.name.clone(), ident.span));
                self.frame_levels.push(Level::Constant);
                self.model.frames.push(Frame {
                    name: name(ident),
                    rotation: None,
                });
            }
            return;
        };
        let parent = self.lookup(parent, NameKind::Frame);
        let mut checked = Vec::new();
        let mut ok = true;
        for rotation in rotations {
            let angle = self.expr(
                &rotation.angle,
                Type::Scalar,
                Place::configuration("a rotation angle"),
            );
            let axis = Axis::from_name(&rotation.axis.name);
            if axis.is_none() {
                let written = &rotation.axis.name;
                let mut diagnostic = Diagnostic::new(
                    DiagnosticKind::UnknownRotationAxis {
                        axis: written.clone(),
                    },
                    rotation.axis.span,
                );
                diagnostic = match crate::diagnostic::suggest(written, ["x", "y", "z"]) {
                    Some(best) => diagnostic.with_help(format!("Did you mean `{best}`? Rotations are about `x`, `y` or `z`.")),
                    None if written.len() > 1 && written.ends_with(['x', 'y', 'z']) => diagnostic.with_help(format!(
                        "Write only the axis letter, `about {}`: the axis is shared by the frame and its parent.",
                        written.chars().last().unwrap_or('z')
                    )),
                    None => diagnostic.with_help("Rotations are about `x`, `y` or `z`."),
                };
                self.diagnostics.push(diagnostic);
            }
            match (angle, axis) {
                (Some(angle), Some(axis)) => checked.push(Rotation { angle, axis }),
                _ => ok = false,
            }
        }
        match parent {
            Some(Target::Frame(parent)) if ok => {
                let level = checked
                    .iter()
                    .map(|r| self.level_of(&r.angle))
                    .fold(self.frame_level(parent), Level::max);
                if self.declare(ident, NameKind::Frame, target, level) {
                    self.frame_levels.push(level);
                    self.model.frames.push(Frame {
                        name: name(ident),
                        rotation: Some((parent, checked)),
                    });
                }
            }
            _ => self.poison(ident, NameKind::Frame),
        }
    }

    pub(super) fn body(&mut self, ident: &Ident, clauses: &ast::BodyClauses) {
        let missing = |clause: &'static str, help: String| {
            Diagnostic::new(
                DiagnosticKind::BodyMissing {
                    body: ident.name.clone(),
                    clause,
                },
                ident.span,
            )
            .with_help(help)
        };
        let mut ok = true;
        let mass = match &clauses.mass {
            Some(mass) => self.mass(mass),
            None => {
                self.diagnostics.push(missing(
                    "mass",
                    format!("Add `mass m` to `body {}`.", ident.name),
                ));
                None
            }
        };
        let centre = match &clauses.centre {
            Some(point) => self.lookup(point, NameKind::Point),
            None => {
                self.diagnostics.push(missing(
                    "centre of mass",
                    "Add `at G`, where `G` is the point at its centre of mass.".to_string(),
                ));
                None
            }
        };
        let frame = match &clauses.frame {
            Some(frame) => self.lookup(frame, NameKind::Frame),
            None => {
                self.diagnostics.push(missing(
                    "frame",
                    "Add `frame B`, the frame attached to the body in whose axes the inertia is given.".to_string(),
                ));
                None
            }
        };
        let inertia = match &clauses.inertia {
            Some(inertia) => self.inertia(ident, inertia, centre),
            None => {
                self.diagnostics.push(missing(
                    "inertia",
                    "Add `inertia I1, I2, I3` (principal moments about the centre of mass, in the body frame's axes)."
                        .to_string(),
                ));
                None
            }
        };
        ok &= mass.is_some() && inertia.is_some();
        match (mass, centre, frame, inertia) {
            (
                Some(mass),
                Some(Target::Point(centre)),
                Some(Target::Frame(frame)),
                Some(inertia),
            ) if ok => {
                let target = Target::Body(BodyId(id(self.model.bodies.len())));
                if self.declare(ident, NameKind::Body, target, Level::Configuration) {
                    self.model.bodies.push(Body {
                        name: name(ident),
                        mass,
                        centre,
                        frame,
                        inertia,
                    });
                }
            }
            _ => self.poison(ident, NameKind::Body),
        }
    }

    fn inertia(
        &mut self,
        body: &Ident,
        clause: &ast::InertiaClause,
        centre: Option<Target>,
    ) -> Option<Inertia> {
        let place = Place::constant("a moment of inertia");
        let mut components: [Option<Expr>; 6] = Default::default();
        let mut ok = true;
        let principal = matches!(clause.spec, ast::InertiaSpec::Principal(_));
        match &clause.spec {
            ast::InertiaSpec::Principal(moments) => {
                for (slot, moment) in components.iter_mut().zip(moments) {
                    let checked = self.expr(moment, Type::Scalar, place);
                    *slot = self.moment(checked);
                    ok &= slot.is_some();
                }
            }
            ast::InertiaSpec::Components(pairs) => {
                ok &= self.inertia_components(body, clause, pairs, &mut components);
            }
        }
        let about = match &clause.about {
            Some(point) => match self.lookup(point, NameKind::Point) {
                Some(Target::Point(id)) => Some(id),
                _ => None,
            },
            None => match centre {
                Some(Target::Point(id)) => Some(id),
                _ => None,
            },
        };
        if ok {
            Some(Inertia {
                components,
                about: about?,
                principal,
            })
        } else {
            None
        }
    }

    /// Check `inertia xx = …, …` components into their slots (xx, yy, zz, xy, xz, yz); false
    /// when any is wrong or a moment is missing.
    fn inertia_components(
        &mut self,
        body: &Ident,
        clause: &ast::InertiaClause,
        pairs: &[(Ident, ast::Expr)],
        components: &mut [Option<Expr>; 6],
    ) -> bool {
        let place = Place::constant("a moment of inertia");
        let mut ok = true;
        let mut given = [false; 6];
        for (key, value) in pairs {
            let index = match key.name.as_str() {
                "xx" => Some(0),
                "yy" => Some(1),
                "zz" => Some(2),
                "xy" | "yx" => Some(3),
                "xz" | "zx" => Some(4),
                "yz" | "zy" => Some(5),
                _ => None,
            };
            let value = self.expr(value, Type::Scalar, place);
            let Some(index) = index else {
                let mut diagnostic = Diagnostic::new(
                    DiagnosticKind::UnknownOption {
                        option: key.name.clone(),
                        statement: "inertia",
                    },
                    key.span,
                );
                diagnostic = match crate::diagnostic::suggest(
                    &key.name,
                    ["xx", "yy", "zz", "xy", "xz", "yz"],
                ) {
                    Some(best) => diagnostic.with_help(format!("Did you mean `{best}`?")),
                    None => diagnostic
                        .with_help("The components are `xx`, `yy`, `zz`, `xy`, `xz` and `yz`."),
                };
                self.diagnostics.push(diagnostic);
                ok = false;
                continue;
            };
            if std::mem::replace(&mut given[index], true) {
                self.diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::DuplicateClause {
                            clause: key.name.clone(),
                        },
                        key.span,
                    )
                    .with_help("Give each component once (the tensor is symmetric: `xy` is `yx`)."),
                );
                ok = false;
            }
            let value = if index < 3 { self.moment(value) } else { value };
            ok &= value.is_some();
            if let Some(slot) = components.get_mut(index) {
                *slot = value;
            }
        }
        ok &= self.missing_moments(body, clause, &given);
        ok
    }

    /// Report each diagonal moment the components left out; false if any.
    fn missing_moments(
        &mut self,
        body: &Ident,
        clause: &ast::InertiaClause,
        given: &[bool; 6],
    ) -> bool {
        let mut ok = true;
        for (index, clause_name) in ["moment `xx`", "moment `yy`", "moment `zz`"]
            .into_iter()
            .enumerate()
        {
            if !given[index] {
                self.diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::BodyMissing { body: body.name.clone(), clause: clause_name },
                        clause.span,
                    )
                    .with_help("Give the three moments `xx`, `yy` and `zz`; products of inertia default to zero."),
                );
                ok = false;
            }
        }
        ok
    }

    /// Check a mass: a constant scalar, positive when it can be evaluated.
    fn mass(&mut self, mass: &ast::Expr) -> Option<Expr> {
        let mass = self.expr(mass, Type::Scalar, Place::constant("a mass"))?;
        match self.model.evaluate_constant(&mass) {
            Some(value) if value.is_nan() || value <= 0.0 || !value.is_normal() => {
                self.diagnostics.push(
                    Diagnostic::new(DiagnosticKind::NonPositiveMass { value }, mass.span)
                        .with_help("Give a positive mass (at least 2.2e-308; use other units for smaller ones); a massless point needs no `particle`."),
                );
                None
            }
            _ => Some(mass),
        }
    }

    /// Check that a moment of inertia that can be evaluated is not negative.
    fn moment(&mut self, moment: Option<Expr>) -> Option<Expr> {
        let moment = moment?;
        match self.model.evaluate_constant(&moment) {
            Some(value) if value.is_nan() || value < 0.0 => {
                self.diagnostics.push(
                    Diagnostic::new(DiagnosticKind::NegativeMoment { value }, moment.span)
                        .with_help("Moments of inertia are sums of m·r², never negative."),
                );
                None
            }
            _ => Some(moment),
        }
    }
}
