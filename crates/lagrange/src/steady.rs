//! Steady motions of nonholonomic systems by Kane's method: the linearization about the
//! motion the model's `initial` statement describes, sweeps of a parameter (the speed), and
//! the canonical second-order form `M q̈ + v C₁ q̇ + (g K₀ + v² K₂) q = 0` of the bicycle
//! literature.

use mechanics::kane::{
    KaneSystem, SteadyLinearization, SteadyMotion, SteadySpectrum, SteadyVerdict,
};

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
    /// The speeds eliminated (not shape rates, whose linearized equations integrate to a
    /// combination of the shape coordinates, `ψ̇ = −8 θ`), each with its coefficients on
    /// the shape coordinates at the speed of the form.
    pub eliminated: Vec<(String, Vec<f64>)>,
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
    pub(crate) fn given_rates(&self) -> Vec<String> {
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

    /// The parameter values in `from..to` where the sweep's stability changes, refined by
    /// bisection: where the largest real part of the eigenvalues outside the family of steady
    /// motions crosses zero (real parts on the imaginary axis to rounding count as zero, so
    /// that purely imaginary eigenvalues make no crossings), and where the verdict changes
    /// otherwise (a real pair `±μ` becoming `±iω`: the upright disk at `v² = g R/3`).
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
            let found = out.len();
            for oscillatory in [false, true] {
                let (fa, fb) = (
                    leading(la, oscillatory, true),
                    leading(lb, oscillatory, true),
                );
                if let (Some((fa, sa)), Some((fb, sb))) = (fa, fb) {
                    if sa != 0 && sb != 0 && sa != sb {
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
            let (va, vb) = (class(la), class(lb));
            if out.len() == found && va.is_some() && vb.is_some() && va != vb {
                out.push(self.bisect_verdict(&system, &sweep.parameter, *a, *b)?);
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
            // Near a real eigenvalue through zero the family's test would count it as one of
            // the family's zeros: the bisection reads every eigenvalue of the coupled states.
            let Some((fm, _)) = leading(&lin, oscillatory, false) else {
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

    /// Bisection on the verdict between `a` and `b`, where it differs; the kind read off the
    /// unstable side's growing eigenvalues (real: a real pair turned complex; complex: a
    /// pair through the imaginary axis).
    fn bisect_verdict(
        &self,
        system: &KaneSystem,
        parameter: &str,
        mut a: f64,
        mut b: f64,
    ) -> Result<StabilityChange, Error> {
        let at = |x: f64| -> Result<(SteadyLinearization, Option<&'static str>), Error> {
            let lin = self.linearize_at(system, parameter, x)?;
            let v = class(&lin);
            Ok((lin, v))
        };
        let (mut la, va) = at(a)?;
        let (mut lb, _) = at(b)?;
        for _ in 0..200 {
            if (b - a).abs() <= 1e-13 * (1.0 + a.abs()) {
                break;
            }
            let m = 0.5 * (a + b);
            let (lm, vm) = at(m)?;
            if vm == va {
                (a, la) = (m, lm);
            } else {
                (b, lb) = (m, lm);
            }
        }
        let unstable = if verdict(&la).is_some_and(|v| !v.is_stable()) {
            &la
        } else {
            &lb
        };
        let growing_real = unstable.spectrum().is_ok_and(|s| {
            s.others()
                .filter(|(re, _)| *re > 0.0)
                .all(|(_, im)| im == 0.0)
        });
        let kind = if growing_real {
            ChangeKind::Coalescence
        } else {
            ChangeKind::Oscillatory
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
        let not_reducible = || {
            Error::NotAvailable(
                "the canonical form needs every other speed decoupled or a combination of the \
                 shape coordinates"
                    .into(),
            )
        };
        let moving_form = shape_equations(&moving, &rows).ok_or_else(not_reducible)?;
        let still_form = shape_equations(&still, &rows).ok_or_else(not_reducible)?;
        let n = rows.len();
        let pick = |f: &dyn Fn(usize, usize) -> f64| -> Vec<Vec<f64>> {
            (0..n).map(|i| (0..n).map(|j| f(i, j)).collect()).collect()
        };
        let mass = moving_form.mass;
        let c1 = pick(&|i, j| moving_form.damping[i][j] / v);
        let k0 = pick(&|i, j| still_form.stiffness[i][j] / g);
        let k2 = pick(&|i, j| (moving_form.stiffness[i][j] - still_form.stiffness[i][j]) / (v * v));
        Ok(CanonicalForm {
            coordinates: moving.shape.clone(),
            speed: speed.to_string(),
            mass,
            c1,
            k0,
            k2,
            eliminated: moving_form.eliminated,
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

/// The largest real part among the complex eigenvalues, or among the real ones, outside the
/// family of steady motions (the decoupled states' zeros are not among them, and as many of
/// the eigenvalues nearest zero as the family has coupled directions are left out), with its
/// sign: `0` when it is on the imaginary axis to rounding ([`SteadySpectrum::axis_tolerance`]).
/// With `aside` false, every eigenvalue of the coupled states counts and the sign is exact.
fn leading(lin: &SteadyLinearization, oscillatory: bool, aside: bool) -> Option<(f64, i8)> {
    let scale = lin
        .eigenvalues
        .iter()
        .fold(1.0_f64, |m, (re, im)| m.max(re.hypot(*im)));
    let spectrum = if aside { lin.spectrum().ok() } else { None };
    let family = spectrum
        .as_ref()
        .map_or(0, |s| s.family.iter().filter(|f| **f).count())
        .saturating_sub(lin.decoupled.len());
    let mut by_size: Vec<(f64, f64)> = lin.eigenvalues.clone();
    by_size.sort_by(|x, y| x.0.hypot(x.1).total_cmp(&y.0.hypot(y.1)));
    let tolerance = spectrum
        .as_ref()
        .map_or(0.0, SteadySpectrum::axis_tolerance);
    let re = by_size
        .iter()
        .skip(family)
        .filter(|(_, im)| (im.abs() > 1e-9 * scale) == oscillatory)
        .map(|(re, _)| *re)
        .reduce(f64::max)?;
    let sign = if re.abs() <= tolerance {
        0
    } else if re < 0.0 {
        -1
    } else {
        1
    };
    Some((re, sign))
}

/// The verdict relative to the family of steady motions.
fn verdict(lin: &SteadyLinearization) -> Option<SteadyVerdict> {
    lin.spectrum().ok().map(|s| s.verdict)
}

/// The verdict's class: asymptotic, marginal or unstable.
fn class(lin: &SteadyLinearization) -> Option<&'static str> {
    verdict(lin).map(SteadyVerdict::short)
}

/// `M q̈ + C q̇ + K q = 0` in the shape coordinates alone.
struct ShapeEquations {
    mass: Vec<Vec<f64>>,
    damping: Vec<Vec<f64>>,
    stiffness: Vec<Vec<f64>>,
    eliminated: Vec<(String, Vec<f64>)>,
}

/// The rows of the shape coordinates' speeds (`rows`, one per shape coordinate) with every
/// other speed `u_c` eliminated where that is exact: a speed that nothing changes (its row of
/// `A` zero) stays at its steady value, so its perturbation is zero within the family; a
/// speed whose linearized equation is a combination of shape rates, `u̇_c = Σ a_i q̇_i`,
/// integrates to `u_c = Σ a_i q_i` (the constant fixed by the family: the upright disk's
/// `ψ̇ = −8 θ`), and its terms `M_rc u̇_c + D_rc u_c` join the damping and the stiffness.
/// `None` when some other speed is neither.
fn shape_equations(lin: &SteadyLinearization, rows: &[usize]) -> Option<ShapeEquations> {
    let s = lin.shape.len();
    let n = rows.len();
    let a = &lin.state_matrix;
    let tiny = 1e-12 * a.iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
    let mass: Vec<Vec<f64>> = rows
        .iter()
        .map(|r| rows.iter().map(|c| lin.mass[*r][*c]).collect())
        .collect();
    let mut damping: Vec<Vec<f64>> = rows
        .iter()
        .map(|r| rows.iter().map(|c| lin.damping[*r][*c]).collect())
        .collect();
    let mut stiffness: Vec<Vec<f64>> = rows.iter().map(|r| lin.stiffness[*r].clone()).collect();
    let mut eliminated = Vec::new();
    for c in (0..lin.speeds.len()).filter(|c| !rows.contains(c)) {
        let row = a.get(s + c)?;
        if row.iter().all(|x| x.abs() <= tiny) {
            continue;
        }
        let outside = (0..row.len()).any(|k| {
            let shape_rate = k >= s && rows.contains(&(k - s));
            !shape_rate && row[k].abs() > tiny
        });
        if outside {
            return None;
        }
        let coefficients: Vec<f64> = rows.iter().map(|r| row[s + r]).collect();
        for i in 0..n {
            for j in 0..n {
                damping[i][j] += lin.mass[rows[i]][c] * coefficients[j];
                stiffness[i][j] += lin.damping[rows[i]][c] * coefficients[j];
            }
        }
        eliminated.push((format!("{}_d", lin.speeds[c]), coefficients));
    }
    Some(ShapeEquations {
        mass,
        damping,
        stiffness,
        eliminated,
    })
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
