//! Mechanics over `cas` expressions: frames, points, bodies, energies and Lagrange's equations.
//!
//! Empty until the equations-of-motion issue lands; see `docs/` for the plan.
