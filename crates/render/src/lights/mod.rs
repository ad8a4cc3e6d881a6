//! Light sources.

pub mod envmap;
