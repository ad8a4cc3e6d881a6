//! Math and sampling layer of fogbank: the bottom of the crate stack.
//!
//! Everything here is plain data and pure functions so that the WGSL port can
//! mirror it line by line (PCG32 and PCG3D are bit-identical on CPU and GPU).

pub mod bbox;
pub mod chi2;
pub mod erf;
pub mod exact_sum;
pub mod piecewise;
pub mod ray;
pub mod rng;
pub mod sample_data;
pub mod special;
pub mod testdata;
pub mod warp;

pub use bbox::Aabb;
pub use exact_sum::ExactSum;
pub use glam::{DAffine3, DVec3, Vec3};
pub use piecewise::PiecewiseLinear;
pub use ray::Ray;
pub use rng::{pcg3d, Pcg32, SampleKey};
