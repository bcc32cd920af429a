//! Names as a figure prints them: Greek names as letters, trailing digits and `_x` parts as
//! subscripts (`theta1` → θ₁, `m_A` → m_A stays readable as m with A below).

const GREEK: &[(&str, &str)] = &[
    ("alpha", "α"),
    ("beta", "β"),
    ("gamma", "γ"),
    ("delta", "δ"),
    ("epsilon", "ε"),
    ("zeta", "ζ"),
    ("eta", "η"),
    ("theta", "θ"),
    ("th", "θ"),
    ("iota", "ι"),
    ("kappa", "κ"),
    ("lambda", "λ"),
    ("mu", "μ"),
    ("nu", "ν"),
    ("xi", "ξ"),
    ("pi", "π"),
    ("rho", "ρ"),
    ("sigma", "σ"),
    ("tau", "τ"),
    ("phi", "φ"),
    ("chi", "χ"),
    ("psi", "ψ"),
    ("omega", "ω"),
    ("Gamma", "Γ"),
    ("Delta", "Δ"),
    ("Theta", "Θ"),
    ("Lambda", "Λ"),
    ("Phi", "Φ"),
    ("Psi", "Ψ"),
    ("Omega", "Ω"),
];

const SUBSCRIPT_DIGITS: [char; 10] = ['₀', '₁', '₂', '₃', '₄', '₅', '₆', '₇', '₈', '₉'];

/// A coordinate's or parameter's name as a symbol: `theta2` → `θ₂`, `phi` → `φ`, `x` → `x`.
#[must_use]
pub fn symbol(name: &str) -> String {
    let stem = name.trim_end_matches(|c: char| c.is_ascii_digit());
    let digits = &name[stem.len()..];
    let (head, tail) = match stem.split_once('_') {
        Some((h, t)) => (h, Some(t)),
        None => (stem, None),
    };
    let mut out = GREEK
        .iter()
        .find(|(g, _)| *g == head)
        .map_or_else(|| head.to_owned(), |(_, letter)| (*letter).to_owned());
    if let Some(t) = tail {
        out.push('_');
        out.push_str(&symbol(t));
    }
    out.extend(
        digits
            .chars()
            .filter_map(|c| c.to_digit(10).map(|d| SUBSCRIPT_DIGITS[d as usize])),
    );
    out
}

/// An expression's text with each name written as a [`symbol`] and `*` as a thin space.
#[must_use]
pub fn text(expression: &str) -> String {
    let mut out = String::new();
    let mut word = String::new();
    for c in expression.chars().chain(std::iter::once(' ')) {
        if c.is_alphanumeric() || c == '_' {
            word.push(c);
            continue;
        }
        if !word.is_empty() {
            let starts_with_digit = word.starts_with(|c: char| c.is_ascii_digit());
            out.push_str(&if starts_with_digit {
                word.clone()
            } else {
                symbol(&word)
            });
            word.clear();
        }
        match c {
            '*' => out.push('\u{2009}'),
            ' ' => {}
            _ => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn greek_names_and_subscripts() {
        assert_eq!(symbol("theta"), "θ");
        assert_eq!(symbol("theta2"), "θ₂");
        assert_eq!(symbol("th1"), "θ₁");
        assert_eq!(symbol("x"), "x");
        assert_eq!(symbol("y12"), "y₁₂");
        assert_eq!(symbol("m_alpha"), "m_α");
        assert_eq!(text("m*g"), "m\u{2009}g");
        assert_eq!(text("F0*cos(omega*t)"), "F₀\u{2009}cos(ω\u{2009}t)");
    }
}
