//! The property test on generated models (issue 23): random planar and 3-D chains and trees
//! written as model text — particles and bodies off their axes, full inertia tensors,
//! constant angle offsets inline and as parameters, springs with rest lengths, torsional
//! springs, dampers, gravity in any direction, constant and follower forces, couples, a
//! driven pivot, a spinning frame — each derived by lagrange and held against an independent
//! numeric route built from the same geometry (`generated/route.rs`: rotation matrices, dual
//! numbers). Accelerations agree to 1e-8 at random states; a conservative model's energy or
//! Jacobi integral is reported and kept along a short simulation.
//!
//! The CI run is bounded: a fixed seed and a fixed number of models, less the ones that are
//! slow to derive today (`SLOW`). A longer campaign: `tools/generated/campaign.sh` (the
//! ignored test `campaign_of_generated_models`, with `LAGRANGE_GENERATED_SEED`, `_FIRST`,
//! `_COUNT` and `_LINKS`); `write_models` writes models for `tools/json_sympy/check.sh`. The
//! ignored tests at the end are the slow derivations this test found, minimised (they fail
//! today: docs/reliability.md, "What it found").

mod generated;

use generated::check::check;
use generated::generate::{model, Size};

/// The CI run: this many models from this seed.
const SEED: u64 = 20_261_125;
const MODELS: u64 = 100;
const SIZE: Size = Size { max_links: 3 };
/// Models of the CI seed that take seconds to minutes to derive (issue 23, "constant angles
/// and offsets cost nothing extra", is not met yet: see `slow_generated_models`). Left out of
/// the CI run so that it stays bounded; the ignored test checks them.
const SLOW: &[u64] = &[
    11, 21, 25, 27, 28, 33, 34, 60, 61, 63, 64, 68, 71, 80, 81, 82, 83, 88, 94,
];

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// The seed of the `i`-th model of a campaign.
fn model_seed(seed: u64, i: u64) -> u64 {
    seed.wrapping_mul(1_000_003).wrapping_add(i)
}

/// Checks the models `indices` of a campaign from `seed`; how many were conservative (and
/// simulated), and the failures, each with its model text.
fn campaign(seed: u64, indices: impl Iterator<Item = u64>, size: Size) -> (usize, Vec<String>) {
    let mut failures = Vec::new();
    let mut conservative = 0;
    let verbose = std::env::var_os("LAGRANGE_GENERATED_VERBOSE").is_some();
    for i in indices {
        let model_seed = model_seed(seed, i);
        let m = model(model_seed, size);
        let start = std::time::Instant::now();
        let result = check(&m, model_seed, 4);
        if verbose {
            eprintln!(
                "model {i} ({}): {:.2} s, {}",
                m.comment,
                start.elapsed().as_secs_f64(),
                if result.is_ok() {
                    "agrees"
                } else {
                    "DISAGREES"
                }
            );
        }
        match result {
            Ok(tally) => {
                conservative += usize::from(tally.simulated);
                if tally.states < 2 {
                    failures.push(format!("only {} usable states\n{}", tally.states, m.text()));
                }
            }
            Err(why) => failures.push(format!("model {i}: {why}\n{}", m.text())),
        }
    }
    (conservative, failures)
}

#[test]
fn generated_models_agree_with_the_numeric_route() {
    let indices = (0..MODELS).filter(|i| !SLOW.contains(i));
    let (conservative, failures) = campaign(SEED, indices, SIZE);
    assert!(
        failures.is_empty(),
        "{} of {MODELS} models disagree:\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
    // The mix covers both kinds of model.
    assert!(conservative >= 20, "{conservative} conservative models");
}

/// The longer campaign: `LAGRANGE_GENERATED_COUNT` models (default 500) from
/// `LAGRANGE_GENERATED_SEED` (default 1), up to `LAGRANGE_GENERATED_LINKS` links (default 5).
#[test]
#[ignore = "a campaign: tools/generated/campaign.sh"]
fn campaign_of_generated_models() {
    let seed = env_u64("LAGRANGE_GENERATED_SEED", 1);
    let count = env_u64("LAGRANGE_GENERATED_COUNT", 500);
    let links = env_u64("LAGRANGE_GENERATED_LINKS", 5) as usize;
    let first = env_u64("LAGRANGE_GENERATED_FIRST", 0);
    let (conservative, failures) = campaign(seed, first..first + count, Size { max_links: links });
    eprintln!(
        "{count} models from seed {seed}: {conservative} conservative, {} failures",
        failures.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// Writes `LAGRANGE_GENERATED_COUNT` models (default 12) into `LAGRANGE_GENERATED_MODELS`
/// for `tools/json_sympy/check.sh` and `tools/generated/campaign.sh`; with
/// `LAGRANGE_GENERATED_SKIP_SLOW` set, not the CI seed's slow ones.
#[test]
#[ignore = "writes files: run by tools/json_sympy/check.sh"]
fn write_models() {
    let dir = std::env::var_os("LAGRANGE_GENERATED_MODELS").expect("LAGRANGE_GENERATED_MODELS");
    let dir = std::path::PathBuf::from(dir);
    std::fs::create_dir_all(&dir).expect("the directory");
    let seed = env_u64("LAGRANGE_GENERATED_SEED", SEED);
    let links = env_u64("LAGRANGE_GENERATED_LINKS", 3) as usize;
    let skip_slow = std::env::var_os("LAGRANGE_GENERATED_SKIP_SLOW").is_some();
    for i in 0..env_u64("LAGRANGE_GENERATED_COUNT", 12) {
        if skip_slow && seed == SEED && links == SIZE.max_links && SLOW.contains(&i) {
            continue;
        }
        let m = model(model_seed(seed, i), Size { max_links: links });
        std::fs::write(dir.join(format!("generated-{i:03}.lag")), m.text()).expect("written");
    }
}

#[test]
fn a_seed_gives_the_same_model_and_the_text_reads() {
    let a = model(7, SIZE).text();
    assert_eq!(a, model(7, SIZE).text());
    assert_ne!(a, model(8, SIZE).text());
    for seed in 0..50 {
        let m = model(seed, Size { max_links: 4 });
        if let Err(e) = lagrange::model::load(&m.text()) {
            panic!("{e:?}\n{}", m.text());
        }
    }
}

/// The CI seed's slow models, checked like the others (minutes in all today).
#[test]
#[ignore = "issue 23: these take seconds to minutes to derive"]
fn slow_generated_models() {
    let (_, failures) = campaign(SEED, SLOW.iter().copied(), SIZE);
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// Found by this test (issue 23), minimised: one pendulum, its mass in a frame turned by a
/// constant angle, a dashpot from the origin. The generalized force is
/// `−c (r·ṙ)(r·∂r/∂θ)/|r|²`, a few terms; lagrange takes about 9 s (debug build) and writes a
/// 2,500-character unreduced fraction with 19-digit integers, so the explicit acceleration
/// exceeds the JSON budget. Without the constant angle it takes 0.05 s.
#[test]
#[ignore = "issue 23: slow and unreduced (a damper on a frame with a constant offset)"]
fn a_damper_on_an_offset_frame_gives_a_small_force() {
    let text = "
coordinates th
parameters al
frame N
frame B = N rotated th about z
frame D = B rotated al about z
point G = -0.73*N.x + 0.5*D.x + 0.33*D.y
particle G mass 1
damper 0.4 from origin to G
";
    let analysis = lagrange::Analysis::from_text(text).expect("reads");
    let equations = analysis.equations().expect("derives");
    let force = lagrange::cas::print::to_sympy(equations.forcing()[0]);
    assert!(force.len() < 600, "{} characters: {force}", force.len());
    assert!(equations.accelerations().is_some());
}

/// Found by this test (issue 23), minimised: a double pendulum whose second link is turned
/// by a constant angle written as a number (`th2 + 2`) derives in about 12 s (debug build);
/// with the offset as a parameter (`th2 + al`) 1.6 s, without it 0.01 s. M and f are right
/// and small (under 270 characters an entry), but `Equations::accelerations` is 44,000
/// characters (the JSON writes the factored `adj(M) f / Δ` instead, under 1,100).
#[test]
#[ignore = "issue 23: a numeric angle offset makes a double pendulum take seconds"]
fn a_numeric_offset_on_a_double_pendulum_derives() {
    let text = "
coordinates th1, th2
parameters a, b, c
frame N
frame B = N rotated th1 about z
frame C = B rotated th2 + 2 about z
point O = a*B.x
point G = O + b*C.x + c*C.y
particle G mass 1
particle O mass 1
";
    let analysis = lagrange::Analysis::from_text(text).expect("reads");
    let equations = analysis.equations().expect("derives");
    for a in equations.accelerations().expect("explicit") {
        let text = lagrange::cas::print::to_sympy(*a);
        assert!(text.len() < 2000, "{} characters", text.len());
    }
}
