//! Issue 18: the Whipple bicycle benchmark (Meijaard et al. 2007) from its model file, by
//! Kane's method about the upright steady motion: the eigenvalues of Table 2 at v = 5 m/s,
//! the canonical matrices M, C1, K0, K2 of its equations (A1)-(A4), and the weave, capsize
//! and bifurcation speeds found by a sweep.

use std::path::Path;

use lagrange::{Analysis, ChangeKind};

fn bicycle() -> Analysis {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/whipple-bicycle.lag");
    match Analysis::from_file(&path) {
        Ok(a) => a,
        Err(e) => panic!("the bicycle model does not load: {e}"),
    }
}

#[test]
fn table_2_eigenvalues_at_five_metres_per_second() {
    let mut a = bicycle();
    a.set_value("v", 5.0).expect("v is a parameter");
    let lin = a
        .steady_linearization()
        .expect("the upright steady motion linearizes");
    let expected = [
        (-14.07838969279822, 0.0),
        (-0.77534188219585, 4.46486771378823),
        (-0.77534188219585, -4.46486771378823),
        (-0.32286642900409, 0.0),
    ];
    for (re, im) in expected {
        let near = lin
            .eigenvalues
            .iter()
            .any(|(r, i)| (r - re).abs() < 1e-10 && (i - im).abs() < 1e-10);
        assert!(near, "no eigenvalue {re} + {im} i in {:?}", lin.eigenvalues);
    }
    // The fifth state is the forward speed (the rear wheel's rate), which the linear
    // equations leave unchanged and which changes nothing in them.
    assert_eq!(lin.eigenvalues.len(), 4);
    assert_eq!(lin.decoupled, ["thetaR_d"]);
    assert_eq!(lin.shape, ["phi", "delta"]);
}

fn assert_matrix(name: &str, got: &[Vec<f64>], expected: [[f64; 2]; 2], digits: f64) {
    for i in 0..2 {
        for j in 0..2 {
            let e = expected[i][j];
            assert!(
                (got[i][j] - e).abs() <= digits,
                "{name}[{i}][{j}] = {} where the paper prints {e}",
                got[i][j]
            );
        }
    }
}

#[test]
fn canonical_matrices_equal_the_papers() {
    let a = bicycle();
    assert_eq!(a.steady_speed_parameter().as_deref(), Some("v"));
    let form = a.canonical_form("v").expect("the canonical form at v = 5");
    assert_eq!(form.coordinates, ["phi", "delta"]);
    // Meijaard et al. (2007), equations (A 1)-(A 4), to the digits printed there.
    let m = [
        [80.81722, 2.31941332208709],
        [2.31941332208709, 0.29784188199686],
    ];
    let c1 = [
        [0.0, 33.86641391492494],
        [-0.85035641456978, 1.68540397397560],
    ];
    let k0 = [
        [-80.95, -2.59951685249872],
        [-2.59951685249872, -0.80329488458618],
    ];
    let k2 = [[0.0, 76.59734589573222], [0.0, 2.65431523794604]];
    assert_matrix("M", &form.mass, m, 1e-11);
    assert_matrix("C1", &form.c1, c1, 1e-11);
    assert_matrix("K0", &form.k0, k0, 1e-11);
    assert_matrix("K2", &form.k2, k2, 1e-11);
}

#[test]
fn sweep_finds_weave_capsize_and_bifurcation_speeds() {
    let a = bicycle();
    let sweep = a.steady_sweep("v", 0.0, 10.0, 101).expect("the sweep");
    assert!(sweep.steps.iter().all(|(_, l)| l.is_ok()));
    let changes = a.steady_crossings(&sweep).expect("the stability changes");
    let find = |kind: ChangeKind| -> Vec<f64> {
        changes
            .iter()
            .filter(|c| c.kind == kind)
            .map(|c| c.at)
            .collect()
    };
    let (weave, capsize, bifurcation) = (
        find(ChangeKind::Oscillatory),
        find(ChangeKind::Real),
        find(ChangeKind::Coalescence),
    );
    assert_eq!(weave.len(), 1, "{changes:?}");
    assert_eq!(capsize.len(), 1, "{changes:?}");
    assert!(
        (weave[0] - 4.29238253634111).abs() < 1e-8,
        "weave at {}",
        weave[0]
    );
    assert!(
        (capsize[0] - 6.02426201538837).abs() < 1e-8,
        "capsize at {}",
        capsize[0]
    );
    assert!(
        bifurcation
            .iter()
            .any(|v| (v - 0.68428307889246).abs() < 1e-8),
        "bifurcation speed not among {bifurcation:?}"
    );
    // Stable between the weave and capsize speeds, unstable below and above.
    for (v, lin) in &sweep.steps {
        let lin = lin.as_ref().expect("linearized");
        let leading = lin
            .eigenvalues
            .iter()
            .map(|(re, _)| *re)
            .fold(f64::MIN, f64::max);
        let stable = leading < 1e-9;
        assert_eq!(
            stable,
            *v > 4.2924 && *v < 6.0243,
            "v = {v}: {:?}",
            lin.eigenvalues
        );
    }
}

#[test]
fn state_matrix_equals_sympys_bicycle_test() {
    // The lean and steer rows of the state matrix in (phi, delta, phi_d, delta_d) as SymPy's
    // own bicycle test stores them (sympy/physics/mechanics/tests/test_kane3.py,
    // test_bicycle, checked there to 1e-12 at v = 0..5).
    let row_phi = |v: f64| {
        [
            9.48977444677355,
            -0.891197738059089 * v * v - 0.571523173729245,
            -0.105522449805691 * v,
            -0.330515398992311 * v,
        ]
    };
    let row_delta = |v: f64| {
        [
            11.7194768719633,
            -1.97171508499972 * v * v + 30.9087533932407,
            3.67680523332152 * v,
            -3.08486552743311 * v,
        ]
    };
    let mut a = bicycle();
    for v in [0.0, 1.0, 2.0, 3.0, 4.0, 5.0] {
        a.set_value("v", v).expect("v is a parameter");
        let lin = a.steady_linearization().expect("linearizes");
        let at = |name: &str| lin.states.iter().position(|s| s == name).expect("a state");
        let cols = [at("phi"), at("delta"), at("phi_d"), at("delta_d")];
        for (state, expected) in [("phi_d", row_phi(v)), ("delta_d", row_delta(v))] {
            let row = &lin.state_matrix[at(state)];
            for (c, e) in cols.iter().zip(expected) {
                assert!(
                    (row[*c] - e).abs() < 1e-11,
                    "v = {v}, {state}: {} against {e}",
                    row[*c]
                );
            }
        }
    }
}
