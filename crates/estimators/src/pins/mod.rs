//! Pin transmittance sampling (Hansen 2025, Hansen 2025): lines through the
//! medium ("pins") stored as a 32-bit ratio bitmask Ĩ and the minimum
//! interval transmittance t_min, indexed by a 5D grid over position and
//! direction; distance sampling by the most significant bit of Ĩ AND H
//! (a fresh majorant mask H of density 1 − t_min) and transmittance
//! t_min^popcount(Ĩ). Everything happens in the medium's unit cube (its
//! index box scaled to [0, 1]³), with ray parameters kept in world units.
//!
//! One concept per file: [`pin`] builds a pin (§3.1, §3.7, Eq. 3.5),
//! [`mask`] draws majorant masks (§3.8, Eq. 3.11), [`chord`] answers
//! queries along a ray (§3.4.2–§3.5, §3.9, Eq. 3.7), [`grid`] stores and
//! finds pins (§3.6, §3.7, §3.10), [`reference`] holds the exact discrete
//! reference and the row samplers of Fig. 3.4 (§3.4.1–§3.4.3).

pub mod chord;
pub mod grid;
pub mod mask;
pub mod pin;
pub mod reference;

pub use chord::Chord;
pub use grid::{PinGrid, PinGridSpec, MIN_STREAM_SPACING};
pub use mask::sample_mask;
pub use pin::{Pin, UnitCube, INTERVALS};
