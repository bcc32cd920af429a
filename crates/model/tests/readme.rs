//! The crate documentation's example, kept as a real test: load a model, read its summary,
//! and render the diagnostics of a broken one.

fn main() {
    let source = "coordinates theta
parameters m = 1, l = 0.5, g = 9.81
frame N
point P = l*sin(theta)*N.x - l*cos(theta)*N.y
particle P mass m
gravity -g*N.y
";
    let model = model::load(source).expect("a valid model");
    assert_eq!(model.summary().degrees_of_freedom, 1);
    assert!(model.require_values().is_empty());

    let broken = "coordinates theta\nframe N\npoint P = thta*N.x\n";
    let errors = model::load(broken).unwrap_err();
    let text = model::render(
        &errors.0,
        "pendulum.lag",
        broken,
        model::RenderOptions::default(),
    );
    assert!(text.contains("unknown name `thta`"));
    assert!(text.contains("Did you mean `theta`?"));
    assert!(text.contains("pendulum.lag:3:11"));
}

#[test]
fn readme() {
    main();
}
