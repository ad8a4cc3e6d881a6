//! Volume data layer of fogbank.

pub mod error;
pub mod loaders;

pub use error::{Result, VolumeError};
