//! Issue 15: in the terminal a matrix printed as `M0 = [3, 0.5] [0.5, 0.25]`, its rows run
//! together on one line. Each row now has a line of its own, the columns aligned, in tall
//! brackets, and a symbolic matrix and its value stand side by side.

use lagrange::Analysis;

#[test]
fn matrices_print_one_row_a_line_with_their_columns_aligned() {
    let seed = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/seed");
    let cart = Analysis::from_file(&seed.join("7.1-cart-pendulum.lag")).expect("7.1");
    let text = cart.solution(None).expect("a solution").document.to_text();
    // The symbolic M0 fits beside its value since its entry m_B ℓ cos(asin(C/(m_B g ℓ))) is
    // written √(m_B² g² ℓ² − C²)/g (positive parameters, docs/solve.md).
    assert!(
        text.contains(
            "  M0 = ⎡m_A + m_B             √(m_B² g² ℓ² − C²)/g⎤ = ⎡3    0.5 ⎤\n       \
             ⎣√(m_B² g² ℓ² − C²)/g  m_B ℓ²              ⎦   ⎣0.5  0.25⎦\n"
        ),
        "{text}"
    );
    assert!(
        text.contains("  B0 = ⎡1  0⎤ = ⎡1  0⎤\n       ⎣0  1⎦   ⎣0  1⎦\n"),
        "{text}"
    );
    assert!(!text.contains("] ["), "{text}");
    assert!(text.lines().all(|l| l.chars().count() <= 80), "{text}");
}
