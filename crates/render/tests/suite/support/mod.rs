//! Helpers shared by this crate's tests.

pub mod mitsuba_agreement;
pub mod same_image;
