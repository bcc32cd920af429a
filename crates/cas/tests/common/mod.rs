//! Shared test models of the symbolic core.

pub mod nlink;
