//! Declarations of names with values: coordinates, parameters, inputs, constants and driven
//! coordinates, each declared in file order and poisoned when its value does not check.

use super::expr::Place;
use super::scope::{Level, Target};
use super::{id, name, Checker};
use crate::ast::{Binding, Ident};
use crate::diagnostic::{NameKind, Type};
use crate::model::*;

impl Checker {
    pub(super) fn coordinates(&mut self, names: &[Ident]) {
        for ident in names {
            let target = Target::Coordinate(CoordinateId(id(self.model.coordinates.len())));
            if self.declare(ident, NameKind::Coordinate, target, Level::Configuration) {
                self.model.coordinates.push(Coordinate {
                    name: name(ident),
                    driven: None,
                });
            }
        }
    }

    pub(super) fn parameters(&mut self, bindings: &[Binding]) {
        for Binding { name: ident, value } in bindings {
            let value = value
                .as_ref()
                .map(|v| self.expr(v, Type::Scalar, Place::constant("a parameter value")));
            if matches!(value, Some(None)) {
                self.poison(ident, NameKind::Parameter);
                continue;
            }
            let target = Target::Parameter(ParameterId(id(self.model.parameters.len())));
            if self.declare(ident, NameKind::Parameter, target, Level::Constant) {
                self.model.parameters.push(Parameter {
                    name: name(ident),
                    value: value.flatten(),
                });
            }
        }
    }

    pub(super) fn inputs(&mut self, bindings: &[Binding]) {
        for Binding { name: ident, value } in bindings {
            let value = value
                .as_ref()
                .map(|v| self.expr(v, Type::Scalar, Place::time("an input value")));
            if matches!(value, Some(None)) {
                self.poison(ident, NameKind::Input);
                continue;
            }
            let target = Target::Input(InputId(id(self.model.inputs.len())));
            if self.declare(ident, NameKind::Input, target, Level::Time) {
                self.model.inputs.push(Input {
                    name: name(ident),
                    value: value.flatten(),
                });
            }
        }
    }

    pub(super) fn constants(&mut self, bindings: &[Binding]) {
        for Binding { name: ident, value } in bindings {
            let Some(value) = value
                .as_ref()
                .and_then(|v| self.any_expr(v, Place::constant("a constant")))
            else {
                self.poison(ident, NameKind::Constant);
                continue;
            };
            let target = Target::Constant(ConstantId(id(self.model.constants.len())), value.ty);
            if self.declare(ident, NameKind::Constant, target, Level::Constant) {
                self.model.constants.push(Constant {
                    name: name(ident),
                    value,
                });
            }
        }
    }

    pub(super) fn driven(&mut self, bindings: &[Binding]) {
        for Binding { name: ident, value } in bindings {
            let Some(value) = value.as_ref().and_then(|v| {
                self.expr(v, Type::Scalar, Place::time("a driven coordinate's motion"))
            }) else {
                self.poison(ident, NameKind::DrivenCoordinate);
                continue;
            };
            let target = Target::Coordinate(CoordinateId(id(self.model.coordinates.len())));
            if self.declare(ident, NameKind::DrivenCoordinate, target, Level::Time) {
                self.model.coordinates.push(Coordinate {
                    name: name(ident),
                    driven: Some(value),
                });
            }
        }
    }
}
