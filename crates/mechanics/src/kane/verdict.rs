//! The stability of a steady motion judged as a course judges it: relative to the family of
//! neighbouring steady motions.
//!
//! A nonholonomic system's steady motion is never isolated: the upright rolling disk has
//! neighbours rolling in a wide circle at a small lean, and others spinning a little faster.
//! Each such direction is a steady state of the linearized system, a vector in the kernel of
//! the state matrix `A`, and adds a zero eigenvalue. When the zero eigenvalue's algebraic
//! multiplicity equals the kernel's dimension, every zero is such a direction and the verdict
//! is the other eigenvalues' (Neimark & Fufaev; Bloch, *Nonholonomic Mechanics and Control*):
//!
//! | the other eigenvalues | verdict |
//! |---|---|
//! | all `Re λ < 0` | asymptotically stable relative to the family |
//! | none `Re λ > 0`, some on the imaginary axis | stable to first order (marginally) |
//! | some `Re λ > 0` | unstable |
//!
//! A zero eigenvalue with fewer eigenvectors than its multiplicity (a Jordan block) grows
//! linearly in time: unstable.
//!
//! Tolerances. An eigenvalue computed in floating point is off by about `ε ‖A‖ κ`, where `κ`
//! is its condition number; a zero of multiplicity `k` with a Jordan chain comes out as a ring
//! of radius about `ε^{1/k} ‖A‖` (`1.5·10⁻⁸ ‖A‖` for `k = 2`). So an eigenvalue counts as zero
//! below [`ZERO`]` ‖A‖`, and one is on the imaginary axis when its real part is below
//! [`AXIS`]` ‖A‖` (`10⁶ ε`, room for `κ` up to a million). A conservative system at an upright
//! steady motion has a spectrum symmetric under `λ → −λ`; there a simple eigenvalue off the
//! axis would need three partners (`±a ± i b`), so when the computed spectrum has that
//! symmetry, real parts up to [`ZERO`]` ‖A‖` are rounding and the eigenvalue is on the axis.

use super::steady::SteadyLinearization;
use super::KaneError;

/// Eigenvalues below this fraction of `‖A‖` are zero (module doc).
pub const ZERO: f64 = 1e-6;
/// Real parts below this fraction of `‖A‖` are on the imaginary axis (module doc).
pub const AXIS: f64 = 1e-10;
/// Rows whose part independent of the rows before is below this fraction of `‖A‖` are
/// dependent: the kernel of a family is exact to rounding, a Jordan block's is not near it.
const RANK: f64 = 1e-9;

/// What the linearization says of a steady motion (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SteadyVerdict {
    /// Every eigenvalue outside the family has a negative real part.
    AsymptoticallyStable,
    /// None to the right of the imaginary axis, some on it: stable to first order.
    Marginal,
    /// An eigenvalue with a positive real part.
    Unstable,
    /// A zero eigenvalue with a Jordan block: a mode growing linearly in time.
    GrowingZeroMode,
}

impl SteadyVerdict {
    /// The verdict as a course words it.
    #[must_use]
    pub fn words(self) -> &'static str {
        match self {
            SteadyVerdict::AsymptoticallyStable => {
                "asymptotically stable (relative to the family of steady motions)"
            }
            SteadyVerdict::Marginal => {
                "stable to first order (marginally: eigenvalues on the imaginary axis)"
            }
            SteadyVerdict::Unstable => "unstable",
            SteadyVerdict::GrowingZeroMode => "unstable (a growing zero mode)",
        }
    }

    /// Short name for tables and JSON: `asymptotic`, `marginal`, `unstable`.
    #[must_use]
    pub fn short(self) -> &'static str {
        match self {
            SteadyVerdict::AsymptoticallyStable => "asymptotic",
            SteadyVerdict::Marginal => "marginal",
            SteadyVerdict::Unstable | SteadyVerdict::GrowingZeroMode => "unstable",
        }
    }

    /// Whether the motion is stable, asymptotically or to first order.
    #[must_use]
    pub fn is_stable(self) -> bool {
        matches!(
            self,
            SteadyVerdict::AsymptoticallyStable | SteadyVerdict::Marginal
        )
    }
}

/// All eigenvalues of a steady linearization, which of them the family's, and the verdict.
#[derive(Clone, Debug, PartialEq)]
pub struct SteadySpectrum {
    /// Every eigenvalue `(re, im)` of the state matrix (the decoupled states' zeros too),
    /// sorted by real part then imaginary part.
    pub eigenvalues: Vec<(f64, f64)>,
    /// Whether each eigenvalue belongs to the family of neighbouring steady motions.
    pub family: Vec<bool>,
    /// The algebraic multiplicity of the zero eigenvalue.
    pub zero_multiplicity: usize,
    /// The dimension of the state matrix's kernel: the family's directions.
    pub kernel_dimension: usize,
    /// Whether the spectrum is symmetric under `λ → −λ` (a conservative system).
    pub symmetric: bool,
    /// `‖A‖` (Frobenius), the scale of the tolerances.
    pub scale: f64,
    /// The verdict.
    pub verdict: SteadyVerdict,
}

impl SteadySpectrum {
    /// Whether eigenvalue `k` lies on the imaginary axis (and is not the family's).
    #[must_use]
    pub fn on_axis(&self, k: usize) -> bool {
        let (re, _) = self.eigenvalues[k];
        !self.family[k] && re.abs() <= self.axis_tolerance()
    }

    /// The real part below which an eigenvalue is on the imaginary axis.
    #[must_use]
    pub fn axis_tolerance(&self) -> f64 {
        if self.symmetric {
            ZERO * self.scale
        } else {
            AXIS * self.scale
        }
    }

    /// The eigenvalues outside the family.
    pub fn others(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.eigenvalues
            .iter()
            .zip(&self.family)
            .filter(|(_, f)| !**f)
            .map(|(e, _)| *e)
    }
}

impl SteadyLinearization {
    /// The whole spectrum of the state matrix and the verdict relative to the family of
    /// steady motions (module doc).
    ///
    /// # Errors
    /// [`KaneError::Singular`] when the eigenproblem does not converge.
    pub fn spectrum(&self) -> Result<SteadySpectrum, KaneError> {
        let a = &self.state_matrix;
        let scale = a.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
        let eigenvalues = if a.is_empty() {
            Vec::new()
        } else {
            numeric::eigen::eigenvalues(a)
                .map_err(|_| KaneError::Singular("the state matrix's eigenproblem"))?
        };
        let zero: Vec<bool> = eigenvalues
            .iter()
            .map(|(re, im)| re.hypot(*im) <= ZERO * scale)
            .collect();
        let zero_multiplicity = zero.iter().filter(|z| **z).count();
        let kernel_dimension = a.len() - rank(a, RANK * scale);
        let family = if zero_multiplicity <= kernel_dimension {
            zero.clone()
        } else {
            vec![false; zero.len()]
        };
        let symmetric = is_symmetric(&eigenvalues, ZERO * scale);
        let mut spectrum = SteadySpectrum {
            eigenvalues,
            family,
            zero_multiplicity,
            kernel_dimension,
            symmetric,
            scale,
            verdict: SteadyVerdict::Marginal,
        };
        spectrum.verdict = if zero_multiplicity > kernel_dimension {
            SteadyVerdict::GrowingZeroMode
        } else {
            verdict_of_others(&spectrum)
        };
        Ok(spectrum)
    }
}

/// The verdict read off the eigenvalues outside the family.
fn verdict_of_others(spectrum: &SteadySpectrum) -> SteadyVerdict {
    let tolerance = spectrum.axis_tolerance();
    let mut on_axis = false;
    for (re, _) in spectrum.others() {
        if re > tolerance {
            return SteadyVerdict::Unstable;
        }
        on_axis |= re >= -tolerance;
    }
    if on_axis {
        SteadyVerdict::Marginal
    } else {
        SteadyVerdict::AsymptoticallyStable
    }
}

/// Whether the eigenvalues can be paired `λ ↔ −λ` to within `tolerance` (each used once).
fn is_symmetric(eigenvalues: &[(f64, f64)], tolerance: f64) -> bool {
    let mut used = vec![false; eigenvalues.len()];
    for (re, im) in eigenvalues {
        let partner = eigenvalues.iter().enumerate().position(|(k, (r, i))| {
            !used[k] && (r + re).hypot(i + im) <= tolerance.max(f64::MIN_POSITIVE)
        });
        match partner {
            Some(k) => used[k] = true,
            None => return false,
        }
    }
    true
}

/// The rank of `a`: rows whose part orthogonal to the rows before exceeds `tolerance`
/// (Gram–Schmidt, twice for orthogonality).
fn rank(a: &[Vec<f64>], tolerance: f64) -> usize {
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for row in a {
        let mut v = row.clone();
        for _ in 0..2 {
            for b in &basis {
                let p: f64 = v.iter().zip(b).map(|(x, y)| x * y).sum();
                for (x, y) in v.iter_mut().zip(b) {
                    *x -= p * y;
                }
            }
        }
        let rest = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if rest > tolerance && rest > 0.0 {
            basis.push(v.iter().map(|x| x / rest).collect());
        }
    }
    basis.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn linearization(a: Vec<Vec<f64>>) -> SteadyLinearization {
        SteadyLinearization {
            cyclic: Vec::new(),
            shape: Vec::new(),
            holonomic: Vec::new(),
            speeds: Vec::new(),
            configuration: Vec::new(),
            rates: Vec::new(),
            states: (0..a.len()).map(|k| format!("s{k}")).collect(),
            decoupled: Vec::new(),
            mass: Vec::new(),
            damping: Vec::new(),
            stiffness: Vec::new(),
            eigenvalues: Vec::new(),
            state_matrix: a,
        }
    }

    #[test]
    fn a_family_of_steady_motions_leaves_the_verdict_to_the_other_eigenvalues() {
        // The upright disk's structure: θ̇ = θ_d, ψ̈ = −8 θ̇, θ̈ = 2 ψ̇ − 6.7 θ, φ̈ = 0.
        let a = vec![
            vec![0.0, 0.0, 1.0, 0.0],
            vec![0.0, 0.0, -8.0, 0.0],
            vec![-6.7, 2.0, 0.0, 0.0],
            vec![0.0, 0.0, 0.0, 0.0],
        ];
        let s = linearization(a).spectrum().unwrap();
        assert_eq!((s.zero_multiplicity, s.kernel_dimension), (2, 2));
        assert!(s.symmetric);
        assert_eq!(s.verdict, SteadyVerdict::Marginal);
        assert_eq!(s.eigenvalues.len(), 4);
        assert_eq!(s.family.iter().filter(|f| **f).count(), 2);
        // Slower: the lean's stiffness changes sign and a real pair ±μ appears.
        let b = vec![
            vec![0.0, 0.0, 1.0, 0.0],
            vec![0.0, 0.0, -1.0, 0.0],
            vec![3.0, 0.5, 0.0, 0.0],
            vec![0.0, 0.0, 0.0, 0.0],
        ];
        let s = linearization(b).spectrum().unwrap();
        assert_eq!(s.verdict, SteadyVerdict::Unstable);
    }

    #[test]
    fn a_zero_eigenvalue_with_a_jordan_block_grows() {
        let a = vec![vec![0.0, 1.0], vec![0.0, 0.0]];
        let s = linearization(a).spectrum().unwrap();
        assert_eq!((s.zero_multiplicity, s.kernel_dimension), (2, 1));
        assert_eq!(s.verdict, SteadyVerdict::GrowingZeroMode);
    }

    #[test]
    fn damped_modes_beside_a_family_are_asymptotically_stable() {
        let a = vec![
            vec![0.0, 1.0, 0.0],
            vec![-4.0, -0.5, 0.0],
            vec![0.0, 0.0, 0.0],
        ];
        let s = linearization(a).spectrum().unwrap();
        assert!(!s.symmetric);
        assert_eq!(s.verdict, SteadyVerdict::AsymptoticallyStable);
    }
}
