//! Steady motions of nonholonomic systems by Kane's method: the linearization about the
//! motion the model's `initial` statement describes, sweeps of a parameter (the speed), and
//! the canonical second-order form `M q̈ + v C₁ q̇ + (g K₀ + v² K₂) q = 0` of the bicycle
//! literature.

use mechanics::kane::{KaneSystem, SteadyLinearization, SteadyMotion};

use crate::{Analysis, Error};

/// A linearization at each value of a swept parameter.
#[derive(Clone, Debug)]
pub struct SteadySweep {
    /// The swept parameter.
    pub parameter: String,
    /// Its values and the linearization there (or why there is none).
    pub steps: Vec<(f64, Result<SteadyLinearization, Error>)>,
}

/// What happens to the eigenvalues at a [`StabilityChange`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChangeKind {
    /// A real eigenvalue passes through zero (the bicycle's capsize speed).
    Real,
    /// A complex pair passes through the imaginary axis (the weave speed).
    Oscillatory,
    /// Two real eigenvalues meet and leave as a complex pair, or the reverse (the bicycle's
    /// bifurcation speed): the largest real part jumps there instead of passing zero.
    Coalescence,
}

/// Where a sweep's leading eigenvalue changes sign.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityChange {
    /// The parameter's value, found by bisection to about 1e-13.
    pub at: f64,
    /// What the eigenvalues do there.
    pub kind: ChangeKind,
}

/// `M q̈ + v C₁ q̇ + (g K₀ + v² K₂) q = 0` in the shape coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct CanonicalForm {
    /// The shape coordinates, in the matrices' order.
    pub coordinates: Vec<String>,
    /// The speed parameter `v`.
    pub speed: String,
    /// `M`.
    pub mass: Vec<Vec<f64>>,
    /// `C₁`.
    pub c1: Vec<Vec<f64>>,
    /// `K₀`.
    pub k0: Vec<Vec<f64>>,
    /// `K₂`.
    pub k2: Vec<Vec<f64>>,
}

impl Analysis {
    /// The system compiled for Kane's method.
    ///
    /// # Errors
    /// A value missing, or an expression the numeric evaluation cannot take.
    pub fn kane_system(&self) -> Result<(KaneSystem, Vec<f64>), Error> {
        let values = self.values()?;
        let names: Vec<String> = values.iter().map(|(n, _)| n.clone()).collect();
        let system = KaneSystem::new(self.system(), &names)?;
        Ok((system, values.into_iter().map(|(_, v)| v).collect()))
    }

    /// The steady motion of the `initial` statement (and values set): its coordinates, and
    /// the rates it gives; the others are zero for shape coordinates and follow from the
    /// constraints for the cyclic ones.
    ///
    /// # Errors
    /// An initial value that is not a number.
    pub fn steady_motion(&self) -> Result<SteadyMotion, Error> {
        let coordinates = self.system().coordinates().to_vec();
        let given = self.given_rates();
        let mut motion = SteadyMotion {
            configuration: Vec::with_capacity(coordinates.len()),
            rates: Vec::with_capacity(coordinates.len()),
            time: 0.0,
        };
        for q in &coordinates {
            motion.configuration.push(self.initial_value(q, false)?);
            motion.rates.push(if given.contains(q) {
                Some(self.initial_value(q, true)?)
            } else {
                None
            });
        }
        Ok(motion)
    }

    /// The coordinates whose rates the model's `initial` statement or a set value gives.
    fn given_rates(&self) -> Vec<String> {
        let mut given: Vec<String> = self.initial_rates_set();
        if let Some(source) = self.source() {
            for i in source.model.initial().iter().filter(|i| i.rate) {
                given.push(source.model.coordinate(i.coordinate).name.name.clone());
            }
        }
        given
    }

    /// The linearization about the steady motion of [`Analysis::steady_motion`], by Kane's
    /// method (docs/mechanics.md, "Steady motions of nonholonomic systems").
    ///
    /// # Errors
    /// As [`Analysis::kane_system`], or [`mechanics::kane::KaneError`]: the motion is not
    /// steady, its rates are not fixed, a singular matrix.
    pub fn steady_linearization(&self) -> Result<SteadyLinearization, Error> {
        let (system, values) = self.kane_system()?;
        let motion = self.steady_motion()?;
        let linearized = system.linearize_steady(&motion, &values);
        linearized.map_err(|e| self.at_initial_rate(e.into()))
    }

    /// A mistake of the steady motion asked for (not steady, rates not fixed), located at
    /// the model's first `initial` rate, which asked for it; other errors as they are.
    fn at_initial_rate(&self, error: Error) -> Error {
        if error.kind() != crate::ErrorKind::Input {
            return error;
        }
        let Some(source) = self.source() else {
            return error;
        };
        let Some(rate) = source.model.initial().iter().find(|i| i.rate) else {
            return error;
        };
        let at = model::line_col(&source.text, rate.value.span.start);
        Error::Located {
            message: format!("linearizing about the steady motion of `initial`: {error}"),
            line: at.line,
            column: at.column,
            kind: crate::ErrorKind::Input,
        }
    }

    /// The steady linearization at `steps` evenly spaced values of `parameter` from `from`
    /// to `to` (both included), from one compilation of the system.
    ///
    /// # Errors
    /// As [`Analysis::kane_system`], or a parameter that cannot be set.
    pub fn steady_sweep(
        &self,
        parameter: &str,
        from: f64,
        to: f64,
        steps: usize,
    ) -> Result<SteadySweep, Error> {
        let (system, _) = self.kane_system()?;
        let mut out = Vec::with_capacity(steps);
        for k in 0..steps {
            let x = if steps > 1 {
                from + (to - from) * k as f64 / (steps - 1) as f64
            } else {
                from
            };
            out.push((x, self.linearize_at(&system, parameter, x)));
        }
        Ok(SteadySweep {
            parameter: parameter.to_string(),
            steps: out,
        })
    }

    /// The steady linearization with `parameter` set to `x`.
    fn linearize_at(
        &self,
        system: &KaneSystem,
        parameter: &str,
        x: f64,
    ) -> Result<SteadyLinearization, Error> {
        let mut at = self.clone();
        at.set_value(parameter, x)?;
        let values: Vec<f64> = at.values()?.into_iter().map(|(_, v)| v).collect();
        Ok(system.linearize_steady(&at.steady_motion()?, &values)?)
    }

    /// The parameter values in `from..to` where the sweep's stability changes: where the
    /// largest real part of the eigenvalues that are not zero crosses zero, refined by
    /// bisection.
    ///
    /// # Errors
    /// As [`Analysis::steady_sweep`].
    pub fn steady_crossings(&self, sweep: &SteadySweep) -> Result<Vec<StabilityChange>, Error> {
        let (system, _) = self.kane_system()?;
        let mut out = Vec::new();
        for pair in sweep.steps.windows(2) {
            let ((a, Ok(la)), (b, Ok(lb))) = (&pair[0], &pair[1]) else {
                continue;
            };
            for oscillatory in [false, true] {
                let (fa, fb) = (leading(la, oscillatory), leading(lb, oscillatory));
                if let (Some(fa), Some(fb)) = (fa, fb) {
                    if (fa < 0.0) != (fb < 0.0) {
                        out.push(self.bisect(
                            &system,
                            &sweep.parameter,
                            (*a, fa),
                            (*b, fb),
                            oscillatory,
                        )?);
                    }
                }
            }
        }
        out.sort_by(|x, y| x.at.total_cmp(&y.at));
        Ok(out)
    }

    fn bisect(
        &self,
        system: &KaneSystem,
        parameter: &str,
        (mut a, mut fa): (f64, f64),
        (mut b, mut fb): (f64, f64),
        oscillatory: bool,
    ) -> Result<StabilityChange, Error> {
        for _ in 0..200 {
            if (b - a).abs() <= 1e-13 * (1.0 + a.abs()) {
                break;
            }
            let m = 0.5 * (a + b);
            let lin = self.linearize_at(system, parameter, m)?;
            let Some(fm) = leading(&lin, oscillatory) else {
                break;
            };
            if (fm < 0.0) == (fa < 0.0) {
                (a, fa) = (m, fm);
            } else {
                (b, fb) = (m, fm);
            }
        }
        // A root of the leading real part shrinks with the interval; a jump does not.
        let kind = if fa.abs().min(fb.abs()) > 1e-6 {
            ChangeKind::Coalescence
        } else if oscillatory {
            ChangeKind::Oscillatory
        } else {
            ChangeKind::Real
        };
        Ok(StabilityChange {
            at: 0.5 * (a + b),
            kind,
        })
    }

    /// The canonical form about the steady motion, with `speed` the parameter that sets the
    /// steady rates: `C₁ = C/v`, `K₀ = K(v = 0)/|g|`, `K₂ = (K(v) − K(0))/v²`.
    ///
    /// # Errors
    /// As [`Analysis::steady_linearization`]; [`Error::NotAvailable`] when the speed is zero
    /// or a shape coordinate's rate is not a speed.
    pub fn canonical_form(&self, speed: &str) -> Result<CanonicalForm, Error> {
        let (system, values) = self.kane_system()?;
        let names = system.value_names().to_vec();
        let v = names
            .iter()
            .position(|n| n == speed)
            .map(|k| values[k])
            .filter(|v| *v != 0.0)
            .ok_or_else(|| {
                Error::NotAvailable("the canonical form needs a nonzero speed".into())
            })?;
        let g = gravity(self, &names, &values);
        let moving = self.steady_linearization()?;
        let still = self.linearize_at(&system, speed, 0.0)?;
        let rows: Vec<usize> = moving
            .shape
            .iter()
            .map(|s| moving.speeds.iter().position(|u| u == s))
            .collect::<Option<_>>()
            .ok_or_else(|| {
                Error::NotAvailable(
                    "the canonical form needs each shape coordinate's rate as a speed".into(),
                )
            })?;
        let pick = |f: &dyn Fn(usize, usize) -> f64| -> Vec<Vec<f64>> {
            (0..rows.len())
                .map(|i| (0..rows.len()).map(|j| f(i, j)).collect())
                .collect()
        };
        let mass = pick(&|i, j| moving.mass[rows[i]][rows[j]]);
        let c1 = pick(&|i, j| moving.damping[rows[i]][rows[j]] / v);
        let k0 = pick(&|i, j| still.stiffness[rows[i]][j] / g);
        let k2 =
            pick(&|i, j| (moving.stiffness[rows[i]][j] - still.stiffness[rows[i]][j]) / (v * v));
        Ok(CanonicalForm {
            coordinates: moving.shape.clone(),
            speed: speed.to_string(),
            mass,
            c1,
            k0,
            k2,
        })
    }

    /// Whether `lagrange linearize` linearizes about a steady motion by Kane's method: the
    /// system has velocity constraints (rolling, a blade) and the `initial` statement gives a
    /// rate that is not zero (a motion rather than a rest state).
    #[must_use]
    pub fn describes_steady_motion(&self) -> bool {
        let velocity = self.system().constraints().iter().any(|c| {
            c.equations
                .iter()
                .any(|e| matches!(e, mechanics::ConstraintForm::Velocity(_)))
        });
        velocity
            && self
                .steady_motion()
                .is_ok_and(|m| m.rates.iter().flatten().any(|r| *r != 0.0))
    }

    /// The parameter the given steady rates change with (the speed), if exactly one does.
    #[must_use]
    pub fn steady_speed_parameter(&self) -> Option<String> {
        let base = self.steady_motion().ok()?;
        let values = self.values().ok()?;
        let mut found = Vec::new();
        for (name, value) in &values {
            let mut other = self.clone();
            let changed = if *value == 0.0 { 1.0 } else { 2.0 * value };
            if other.set_value(name, changed).is_err() {
                continue;
            }
            if other.steady_motion().ok()?.rates != base.rates {
                found.push(name.clone());
            }
        }
        (found.len() == 1).then(|| found.remove(0))
    }
}

/// The largest real part among the complex eigenvalues, or among the real ones (the decoupled
/// states' zeros are not among them).
fn leading(lin: &SteadyLinearization, oscillatory: bool) -> Option<f64> {
    let scale = lin
        .eigenvalues
        .iter()
        .fold(1.0_f64, |m, (re, im)| m.max(re.hypot(*im)));
    lin.eigenvalues
        .iter()
        .filter(|(_, im)| (im.abs() > 1e-9 * scale) == oscillatory)
        .map(|(re, _)| *re)
        .reduce(f64::max)
}

/// The magnitude of gravity at the given values.
fn gravity(analysis: &Analysis, names: &[String], values: &[f64]) -> f64 {
    let env = |s: cas::Symbol| names.iter().position(|n| n == s.name()).map(|k| values[k]);
    analysis
        .system()
        .gravity()
        .iter()
        .map(|e| e.eval(&env).unwrap_or(0.0))
        .map(|x| x * x)
        .sum::<f64>()
        .sqrt()
}
