//! Numbers only: compiled evaluators, integrators, root finding and eigenproblems.
//!
//! This crate knows the symbolic core (`cas`) and nothing of mechanics. It is empty until the
//! simulation issue lands; see `docs/` for the plan.
