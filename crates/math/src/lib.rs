//! Math and sampling layer of fogbank: the bottom of the crate stack.
//!
//! Everything here is plain data and pure functions so that the WGSL port can
//! mirror it line by line (PCG32 and PCG3D are bit-identical on CPU and GPU).
//!
//! Modules:
//! - geometry: `ray` (rays with an unnormalised direction, `t` a world distance) and
//!   `bbox` (axis-aligned boxes with a robust slab test);
//! - sampling: `rng` (PCG32 streams keyed by pixel, sample index and dimension; the
//!   PCG3D hash), `warp` (the unit square to other domains, for BSDF and light sampling)
//!   and `piecewise` (piecewise-linear transfer functions, as ParaView's);
//! - numerics: `erf` (the error function, its complement and inverse in f32, as in
//!   WGSL), `special` (adaptive Simpson quadrature, the regularised incomplete gamma
//!   function), `chi2` (chi-square tests of samplers against their pdfs) and `exact_sum`
//!   (order-independent sums in 256-bit fixed point);
//! - data: `sample_data` (where the volume files of scenes, experiments and tests are)
//!   and `testdata` (the policy for tests that need files outside the repository).

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
pub use ray::{Ray, RaySegment};
pub use rng::{pcg3d, Pcg32, SampleKey};
