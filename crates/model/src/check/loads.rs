//! Applied loads: gravity, springs, dampers, dissipation, potentials, forces, couples and
//! generalized forces.

use super::expr::{rate_degree, Place};
use super::scope::Target;
use super::Checker;
use crate::ast::{self, Ident};
use crate::diagnostic::{Diagnostic, DiagnosticKind, NameKind, Type};
use crate::model::*;
use crate::span::Span;

impl Checker {
    pub(super) fn gravity(&mut self, g: &ast::Expr, span: Span) {
        if let Some(g) = self.expr(g, Type::Vector, Place::constant("gravity")) {
            self.load(Load::Gravity(g), span);
        }
    }

    pub(super) fn spring(
        &mut self,
        stiffness: &ast::Expr,
        connection: &ast::Connection,
        rest: Option<&ast::Expr>,
        span: Span,
    ) {
        let stiffness = self.expr(stiffness, Type::Scalar, Place::time("a spring's stiffness"));
        let connection = self.connection(connection, "a spring's ends");
        let rest = rest.map(|r| self.expr(r, Type::Scalar, Place::time("a spring's rest length")));
        if let (Some(stiffness), Some(connection), None | Some(Some(_))) =
            (stiffness, connection, &rest)
        {
            self.load(
                Load::Spring {
                    stiffness,
                    connection,
                    rest: rest.flatten(),
                },
                span,
            );
        }
    }

    pub(super) fn damper(
        &mut self,
        coefficient: &ast::Expr,
        connection: &ast::Connection,
        span: Span,
    ) {
        let coefficient = self.expr(
            coefficient,
            Type::Scalar,
            Place::time("a damping coefficient"),
        );
        let connection = self.connection(connection, "a damper's ends");
        if let (Some(coefficient), Some(connection)) = (coefficient, connection) {
            self.load(
                Load::Damper {
                    coefficient,
                    connection,
                },
                span,
            );
        }
    }

    pub(super) fn dissipation(&mut self, d: &ast::Expr, span: Span) {
        if let Some(d) = self.expr(d, Type::Scalar, Place::motion("a dissipation function")) {
            if rate_degree(&d).is_none_or(|degree| degree > 2) {
                self.diagnostics.push(
                    Diagnostic::new(
                        DiagnosticKind::WrongDegreeInRates {
                            place: "a Rayleigh dissipation function",
                            requirement: "at most quadratic",
                        },
                        d.span,
                    )
                    .with_help("Write D = ½ c q'² (a polynomial of degree 2 in the rates)."),
                );
            } else {
                self.load(Load::Dissipation(d), span);
            }
        }
    }

    pub(super) fn potential(&mut self, v: &ast::Expr, span: Span) {
        if let Some(v) = self.expr(v, Type::Scalar, Place::configuration("a potential")) {
            self.load(Load::Potential(v), span);
        }
    }

    pub(super) fn force(&mut self, force: &ast::Expr, point: &ast::Expr, span: Span) {
        let force = self.expr(force, Type::Vector, Place::motion("a force"));
        let point = self.expr(
            point,
            Type::Vector,
            Place::configuration("a point of application"),
        );
        if let (Some(force), Some(point)) = (force, point) {
            self.load(Load::Force { force, point }, span);
        }
    }

    pub(super) fn couple(&mut self, moment: &ast::Expr, body: &Ident, span: Span) {
        let moment = self.expr(moment, Type::Vector, Place::motion("a couple"));
        let body = self.lookup(body, NameKind::Body);
        if let (Some(moment), Some(Target::Body(body))) = (moment, body) {
            self.load(Load::Couple { moment, body }, span);
        }
    }

    pub(super) fn generalized_force(&mut self, force: &ast::Expr, coordinate: &Ident, span: Span) {
        let force = self.expr(force, Type::Scalar, Place::motion("a generalized force"));
        let coordinate = self.free_coordinate(coordinate);
        if let (Some(force), Some(coordinate)) = (force, coordinate) {
            self.load(Load::GeneralizedForce { force, coordinate }, span);
        }
    }

    fn load(&mut self, load: Load, span: Span) {
        self.model.loads.push(LoadItem { load, span });
    }

    fn connection(
        &mut self,
        connection: &ast::Connection,
        what: &'static str,
    ) -> Option<Connection> {
        match connection {
            ast::Connection::Points { from, to } => {
                let from = self.expr(from, Type::Vector, Place::configuration(what));
                let to = self.expr(to, Type::Vector, Place::configuration(what));
                Some(Connection::Points {
                    from: from?,
                    to: to?,
                })
            }
            ast::Connection::Scalar(value) => self
                .expr(
                    value,
                    Type::Scalar,
                    Place::configuration("the angle of a torsional element"),
                )
                .map(Connection::Scalar),
        }
    }
}
