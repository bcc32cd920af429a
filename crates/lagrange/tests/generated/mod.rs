//! Test support for the property test on generated models (issue 23): a generator of random
//! models as people write them ([`generate`]), each held both as model text and as plain
//! geometry ([`model`]), an independent numeric route from that geometry to `M q̈ = f`
//! ([`route`]) by automatic differentiation ([`dual`]), and the checks that hold lagrange's
//! derivation against it ([`check`]).

pub mod check;
pub mod dual;
pub mod generate;
pub mod model;
pub mod route;
