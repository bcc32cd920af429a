//! Issue 18, its last sentence: the rolling disk's upright stability derived in the
//! parameters, and what it exposed.
//!
//! The bug: at `v = 2 > √(g R/3)` the upright disk was called unstable, although its
//! eigenvalues are `0, 0, ±4.765 i`; one eigenvalue was not printed (the decoupled spin); a
//! sweep of `v` reported six "stability changes" where rounding gave purely imaginary
//! eigenvalues real parts of ±1e-15; the canonical form ignored the heading rate `ψ̇` (so
//! `K₂ = 0`). The cause: the zero eigenvalues are the family of neighbouring steady motions
//! (a wide circle at a small lean, a faster spin), which a course sets aside; the verdict is
//! the other eigenvalues', with the imaginary axis judged to rounding. The fix: the verdict
//! relative to the family (`mechanics::kane::SteadySpectrum`), `ψ̇ = −8 θ` eliminated from the
//! canonical form, and the condition in the parameters from the symbolic reduced equations:
//! `3 v² > g R` for the uniform disk, `4 v² > g R` for a hoop, and for a disk with diametral
//! and polar moments `A`, `C`: `C (C + m R²) v² > A m g R³` (derived with SymPy's
//! KanesMethod: its characteristic polynomial is `λ⁴ (A (A + m R²) λ² − A m g R + C (C + m R²) Ω²)`
//! with `Ω = v/R`).

use lagrange::cas::{Expr, Symbol};
use lagrange::mechanics::kane::SteadyVerdict;
use lagrange::mechanics::stability_condition::{ConditionCriterion, StabilityCondition, Verdict};
use lagrange::{Analysis, ChangeKind};

/// The brief's disk rolling upright along `x` at speed `v`, with the given inertia about its
/// diametral, polar and diametral axes.
fn disk(inertia: &str, extra: &str, v: f64) -> Analysis {
    let text = format!(
        "coordinates x, y, psi, theta, phi
parameters  m = 1, R = 0.5, g = 9.81, v = {v}{extra}
frame N
frame A = N rotated psi about z
frame L = A rotated theta about x
frame D = L rotated phi about y
point P = x*N.x + y*N.y
point G = x*N.x + y*N.y + R*L.z
body disk mass m at G frame D inertia {inertia}
gravity -g*N.z
constraint roll: rolling disk at P
initial x' = v, psi' = 0
"
    );
    match Analysis::from_text(&text) {
        Ok(a) => a,
        Err(e) => panic!("the disk model does not load: {e}"),
    }
}

const UNIFORM: &str = "m*R^2/4, m*R^2/2, m*R^2/4";
const HOOP: &str = "m*R^2/2, m*R^2, m*R^2/2";
const GENERAL: &str = "I_a, I_c, I_a";

fn condition(a: &Analysis) -> StabilityCondition {
    let lin = a
        .steady_linearization()
        .expect("upright rolling linearizes");
    let spectrum = lin.spectrum().expect("its spectrum");
    a.steady_condition(&lin, &spectrum)
        .expect("the symbolic route runs")
        .expect("a condition in the parameters")
}

/// The one inequality of the condition, as `difference > 0`.
fn difference(c: &StabilityCondition) -> Expr {
    let Verdict::When(all) = &c.verdict else {
        panic!("not a condition: {:?}", c.verdict)
    };
    assert_eq!(all.len(), 1, "{all:?}");
    all[0].difference()
}

/// `x / y` is a positive number.
fn positive_multiple(x: Expr, y: Expr) {
    let ratio = (x / y).normal();
    let n = ratio
        .as_number()
        .unwrap_or_else(|| panic!("{x} is not a multiple of {y}: {ratio}"));
    assert!(n.to_f64() > 0.0, "{x} is a negative multiple of {y}");
}

fn symbol(name: &str) -> Expr {
    Expr::symbol(name)
}

#[test]
fn the_uniform_disk_is_stable_to_first_order_iff_v_squared_exceeds_g_r_over_three() {
    let c = condition(&disk(UNIFORM, "", 2.0));
    assert_eq!(c.criterion, ConditionCriterion::EvenCharacteristic);
    let (v, g, r) = (symbol("v"), symbol("g"), symbol("R"));
    let d = difference(&c);
    assert!(d.equals(3 * v.powi(2) - g * r), "{d}");
    let text = c.sentence(lagrange::cas::print::to_unicode);
    assert_eq!(text, "stable to first order iff 3 v² > R g");
}

#[test]
fn the_hoop_is_stable_to_first_order_iff_v_squared_exceeds_g_r_over_four() {
    let c = condition(&disk(HOOP, "", 2.0));
    let (v, g, r) = (symbol("v"), symbol("g"), symbol("R"));
    let d = difference(&c);
    assert!(d.equals(4 * v.powi(2) - g * r), "{d}");
}

#[test]
fn the_general_disk_condition_is_c_times_c_plus_m_r_squared_v_squared_over_a_m_g_r_cubed() {
    let c = condition(&disk(GENERAL, ", I_a = 0.07, I_c = 0.11", 2.0));
    let (v, g, r, m) = (symbol("v"), symbol("g"), symbol("R"), symbol("m"));
    let (ia, ic) = (symbol("I_a"), symbol("I_c"));
    let expected = ic * (ic + m * r.powi(2)) * v.powi(2) - ia * m * g * r.powi(3);
    positive_multiple(difference(&c), expected);
}

/// A pseudo-random number in `[lo, hi)` (a fixed linear congruential sequence).
fn next(state: &mut u64, lo: f64, hi: f64) -> f64 {
    *state = state
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    let unit = (*state >> 11) as f64 / (1_u64 << 53) as f64;
    lo + (hi - lo) * unit
}

#[test]
fn on_each_side_of_the_boundary_the_condition_and_the_eigenvalues_agree() {
    let mut state = 18_u64;
    let c = condition(&disk(GENERAL, ", I_a = 0.07, I_c = 0.11", 2.0));
    let d = difference(&c);
    for _ in 0..6 {
        let (m, r, g) = (
            next(&mut state, 0.2, 5.0),
            // Radii on both sides of one: above it the largest pivot of the constraint rows
            // is the spin rate's, which must not decide the speeds.
            next(&mut state, 0.1, 3.0),
            next(&mut state, 1.0, 20.0),
        );
        let ia = m * r * r * next(&mut state, 0.1, 0.6);
        let ic = m * r * r * next(&mut state, 0.2, 1.2);
        let critical = (ia * m * g * r.powi(3) / (ic * (ic + m * r * r))).sqrt();
        for (factor, stable) in [(0.9, false), (1.1, true)] {
            let v = factor * critical;
            let mut a = disk(GENERAL, ", I_a = 0.07, I_c = 0.11", 2.0);
            for (name, value) in [
                ("m", m),
                ("R", r),
                ("g", g),
                ("I_a", ia),
                ("I_c", ic),
                ("v", v),
            ] {
                a.set_value(name, value).expect("a parameter");
            }
            let env = |s: Symbol| {
                [
                    ("m", m),
                    ("R", r),
                    ("g", g),
                    ("I_a", ia),
                    ("I_c", ic),
                    ("v", v),
                ]
                .iter()
                .find(|(n, _)| *n == s.name())
                .map(|(_, x)| *x)
            };
            let holds = d.eval(&env).expect("evaluates") > 0.0;
            let lin = a.steady_linearization().expect("linearizes");
            let verdict = lin.spectrum().expect("spectrum").verdict;
            assert_eq!(
                holds, stable,
                "the condition at {factor} × the critical speed"
            );
            assert_eq!(
                verdict.is_stable(),
                stable,
                "{verdict:?} at {factor} × critical"
            );
        }
    }
}

#[test]
fn at_two_metres_per_second_marginally_stable_and_at_one_unstable() {
    for (v, expected) in [
        (2.0, SteadyVerdict::Marginal),
        (1.0, SteadyVerdict::Unstable),
    ] {
        let lin = disk(UNIFORM, "", v)
            .steady_linearization()
            .expect("linearizes");
        let s = lin.spectrum().expect("spectrum");
        assert_eq!(s.verdict, expected, "v = {v}: {:?}", s.eigenvalues);
        // Every state's eigenvalue, the two zeros the family's (a wide circle, a faster spin).
        assert_eq!(s.eigenvalues.len(), lin.states.len());
        assert_eq!((s.zero_multiplicity, s.kernel_dimension), (2, 2));
        assert_eq!(s.family.iter().filter(|f| **f).count(), 2);
    }
}

#[test]
fn the_sweep_finds_one_change_at_the_square_root_of_g_r_over_three() {
    let a = disk(UNIFORM, "", 2.0);
    let sweep = a.steady_sweep("v", 0.0, 4.0, 20).expect("the sweep");
    let changes = a.steady_crossings(&sweep).expect("its changes");
    assert_eq!(changes.len(), 1, "{changes:?}");
    let exact = (9.81_f64 * 0.5 / 3.0).sqrt();
    assert!(
        (changes[0].at - exact).abs() < 1e-8,
        "{changes:?} vs {exact}"
    );
    assert_eq!(changes[0].kind, ChangeKind::Coalescence);
}

#[test]
fn the_canonical_form_eliminates_the_heading_rate() {
    let form = disk(UNIFORM, "", 2.0)
        .canonical_form("v")
        .expect("the canonical form");
    assert_eq!(form.coordinates, ["theta"]);
    // M = 5 m R²/4, K₀ = −m R, K₂ = 3 m: 5 m R²/4 θ̈ + (3 m v² − m g R) θ = 0.
    let close = |x: f64, y: f64| (x - y).abs() < 1e-12;
    assert!(close(form.mass[0][0], 0.3125), "{form:?}");
    assert!(close(form.c1[0][0], 0.0), "{form:?}");
    assert!(close(form.k0[0][0], -0.5), "{form:?}");
    assert!(close(form.k2[0][0], 3.0), "{form:?}");
}

#[test]
fn the_solution_states_the_verdict_and_the_condition() {
    let solution = disk(UNIFORM, "", 2.0)
        .solution(None)
        .expect("the disk's solution");
    // The document wraps its paragraphs: compare with the line breaks as spaces.
    let text = solution.document.to_text().replace('\n', " ");
    assert!(text.contains("Steady motion and its stability"), "{text}");
    assert!(
        text.contains(
            "Verdict: stable to first order (marginally: eigenvalues on the imaginary axis)"
        ),
        "{text}"
    );
    assert!(
        text.contains("stable to first order iff 3 v² > R g"),
        "{text}"
    );
}
