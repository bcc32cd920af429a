//! The native module `lagrange._native`: PyO3 glue over the `lagrange` crate, with no
//! mechanics of its own. The pure-Python package `lagrange` (python/lagrange/) wraps it into
//! the documented surface (docs/python.md); this module hands it plain values: strings,
//! JSON text, NumPy arrays.
//!
//! - `analysis::PyAnalysis` (`Analysis` in Python): a model read from a file or text, its
//!   values set, and every result of `lagrange::Analysis` (solution, equations as JSON,
//!   equilibria, linearization, simulation, a sweep on all cores).
//! - `rhs::Rhs`: the compiled right-hand side `(t, (q, q̇)) → (q̇, q̈)` for SciPy's
//!   `solve_ivp`, one call at a time or many states at once.
//!
//! Errors become the Python exceptions of `lagrange._errors` (`ModelError` for the user's
//! mistakes, with the located diagnostic as message and its line and column).

use pyo3::prelude::*;

mod analysis;
mod errors;
mod rhs;

/// The module `lagrange._native`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<analysis::PyAnalysis>()?;
    m.add_class::<rhs::Rhs>()?;
    m.add_function(wrap_pyfunction!(analysis::load_file, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::load_text, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
