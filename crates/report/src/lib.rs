//! Report writers: MyST Markdown, LaTeX and JSON renderings of a solved system.
//!
//! Empty until the report issue lands; see `docs/` for the plan.
