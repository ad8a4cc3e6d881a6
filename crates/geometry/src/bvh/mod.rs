//! A binary bounding-volume hierarchy over any primitives that have boxes,
//! built once on the CPU with the binned surface-area heuristic and stored
//! as one flat array of 32-byte nodes ([`BvhNode`]). The renderer finds
//! media through it, and `bvh-perf` measures it as the baseline; surfaces
//! are traced, on the CPU and the GPU alike, through the wide BVH
//! ([`crate::wide`]).

mod build;
mod node;
pub(crate) mod traverse;

pub use node::{Bvh, BvhNode};
pub use traverse::Walk;

use fogbank_math::Aabb;

impl Bvh {
    /// Builds over the boxes of primitives `0 .. bounds.len()`.
    pub fn new(bounds: &[Aabb]) -> Bvh {
        build::build(bounds)
    }
}
