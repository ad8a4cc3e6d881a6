//! Light sources.

pub mod envmap;
pub mod sample;
