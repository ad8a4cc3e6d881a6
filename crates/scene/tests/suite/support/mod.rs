//! Helpers shared by this crate's tests.

pub mod mitsuba_agreement;
/// The same image, as `fogbank-render`'s tests compare them.
#[path = "../../../../render/tests/suite/support/same_image.rs"]
pub mod same_image;
