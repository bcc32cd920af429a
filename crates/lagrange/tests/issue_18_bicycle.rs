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
    let lin = a.steady_linearization().expect("the upright steady motion linearizes");
    println!("{lin:#?}");
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
    // The fifth state is the forward speed, which the linear equations leave unchanged.
    assert_eq!(lin.eigenvalues.len(), 5);
    assert_eq!(lin.shape, ["phi", "delta"]);
}
