//! Issue 17: polar coordinates listed every equilibrium twice — `(r, θ)` and `(−r, θ + π)` put
//! the particle at the same point, and each copy was linearized and printed as an equilibrium
//! of its own. Equilibria are now told apart by the configuration they stand for (every
//! point's position, every body's orientation, `mechanics::configuration`): one of each is
//! kept, the one with a non-negative radius, and the other coordinates are said beside it
//! (`also_at` in JSON).

use lagrange::Analysis;

/// A particle on a spring of rest length `a` from the origin, under gravity, in polar
/// coordinates: it hangs at `r = a + m g/k` straight down, or balances above at `r = a − m g/k`.
const POLAR: &str = "coordinates r, th
parameters m = 1, k = 10, a = 1, g = 9.81
frame N
point P = r*cos(th)*N.x + r*sin(th)*N.y
particle P mass m
spring k from origin to P length a
gravity -g*N.y
";

#[test]
fn polar_coordinates_list_each_equilibrium_once_with_a_non_negative_radius() {
    let analysis = Analysis::from_text(POLAR).unwrap();
    let equilibria = analysis.equilibria().unwrap();
    let found = &equilibria.set.equilibria;
    assert_eq!(found.len(), 2, "{found:?}");
    let half_pi = std::f64::consts::FRAC_PI_2;
    let hanging = found
        .iter()
        .find(|e| (e.values[0] - 1.981).abs() < 1e-6)
        .expect("hanging at r = a + m g/k");
    assert!(
        (hanging.values[1] + half_pi).abs() < 1e-6,
        "{:?}",
        hanging.values
    );
    let above = found
        .iter()
        .find(|e| (e.values[0] - 0.019).abs() < 1e-6)
        .expect("balanced at r = a − m g/k");
    assert!(
        (above.values[1] - half_pi).abs() < 1e-6,
        "{:?}",
        above.values
    );
    // Each has its other coordinates recorded, at −r and the opposite angle.
    assert_eq!(equilibria.set.repeated.len(), 2);
    for repeated in &equilibria.set.repeated {
        let kept = &found[repeated.same_as].values;
        assert!((repeated.values[0] + kept[0]).abs() < 1e-6, "{repeated:?}");
        assert!((repeated.values[1] + kept[1]).abs() < 1e-6, "{repeated:?}");
    }
    // The linearizations stay with their equilibria: hanging is stable, balanced is not.
    let stable: Vec<Option<bool>> = equilibria
        .linearized
        .iter()
        .map(|l| l.as_ref().unwrap().stable)
        .collect();
    let hanging_index = found.iter().position(|e| e.values[0] > 1.0).unwrap();
    assert_eq!(stable[hanging_index], Some(true));
    assert_eq!(stable[1 - hanging_index], Some(false));
    let text = equilibria.to_text();
    assert!(text.contains("also at r = -1.981000"), "{text}");
    let json = equilibria.to_json();
    let also = &json["equilibria"][hanging_index]["also_at"];
    assert!(
        (also[0]["r"].as_f64().unwrap() + 1.981).abs() < 1e-6,
        "{also}"
    );
}

#[test]
fn distinct_configurations_are_all_kept() {
    // A double pendulum's four rest states are four configurations.
    let text = "coordinates th1, th2
parameters m = 1, l = 1, g = 9.81
frame N
point P1 = l*sin(th1)*N.x - l*cos(th1)*N.y
point P2 = P1 + l*sin(th2)*N.x - l*cos(th2)*N.y
particle P1 mass m
particle P2 mass m
gravity -g*N.y
";
    let analysis = Analysis::from_text(text).unwrap();
    let equilibria = analysis.equilibria().unwrap();
    assert_eq!(equilibria.set.equilibria.len(), 4);
    assert!(equilibria.set.repeated.is_empty());
}

/// Issue 17: springs added equilibria where a spring passes through zero length (its force
/// `−k (|d| − a) d/|d|` has no value there). `examples/spring-chain.lag` listed
/// `x = (−1, 0, 1)`, the first mass on the wall's anchor; the search now evaluates the rest
/// equations where they are defined only.
#[test]
fn no_equilibrium_puts_a_spring_at_zero_length() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/spring-chain.lag");
    let analysis = Analysis::from_file(&path).unwrap();
    let equilibria = analysis.equilibria().unwrap();
    assert!(!equilibria.set.equilibria.is_empty());
    for e in &equilibria.set.equilibria {
        // a = 1: the masses sit at 1 + x1, 2 + x2, 3 + x3 between anchors at 0 and 4.
        let x = &e.values;
        let points = [0.0, 1.0 + x[0], 2.0 + x[1], 3.0 + x[2], 4.0];
        for pair in points.windows(2) {
            assert!(
                (pair[1] - pair[0]).abs() > 1e-6,
                "a spring of zero length at {x:?}"
            );
        }
    }
    assert!(equilibria
        .set
        .equilibria
        .iter()
        .any(|e| e.values.iter().all(|v| v.abs() < 1e-9)));
}
