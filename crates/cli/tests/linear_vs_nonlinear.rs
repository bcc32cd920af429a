//! For small amplitudes the linearized free response (`lagrange linearize --initial`, a sum of
//! modes in closed form) agrees with the nonlinear simulation (`lagrange simulate`) of the
//! same start: the seed's 7.1 about its stable equilibrium, both modes excited.

mod common;
use common::lagrange;
use lagrange::cas;

#[test]
fn small_oscillations_follow_the_modes() {
    let amplitude = 0.01;
    let o = lagrange(&[
        "linearize",
        "examples/seed/7.1-cart-pendulum.lag",
        "--equilibrium",
        "0",
        "--initial",
        &format!("theta={amplitude}"),
        "--format",
        "json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let response = &json["linearized"][0]["free_response"];
    let parse = |q: &str| {
        let text = response[q].as_str().expect("a closed form");
        cas::parse(text, &cas::ParseContext::new()).expect("it reads back")
    };
    let (x_lin, theta_lin) = (parse("x"), parse("theta"));

    let o = lagrange(&[
        "simulate",
        "examples/seed/7.1-cart-pendulum.lag",
        "--set",
        "x=0",
        "--set",
        &format!("theta={amplitude}"),
        "--t-end",
        "4",
        "--output-step",
        "0.25",
        "--rtol",
        "1e-10",
        "--atol",
        "1e-12",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let (t_col, x_col, theta_col) = (column("t"), column("x"), column("theta"));
    let mut checked = 0;
    for line in lines {
        let row: Vec<f64> = line
            .split(',')
            .map(|v| v.parse().expect("a number"))
            .collect();
        let t = row[t_col];
        let at = |e: cas::Expr| e.eval(&|_| Some(t)).expect("a function of t only");
        // The nonlinear terms are O(amplitude³): 1e-6 here, against responses of 1e-2.
        assert!(
            (row[theta_col] - at(theta_lin)).abs() < 2e-5,
            "θ at t = {t}"
        );
        assert!((row[x_col] - at(x_lin)).abs() < 2e-5, "x at t = {t}");
        checked += 1;
    }
    assert_eq!(checked, 17);
}
