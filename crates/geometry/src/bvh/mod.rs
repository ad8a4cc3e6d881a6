//! A bounding-volume hierarchy over any primitives that have boxes, built
//! once on the CPU with the binned surface-area heuristic and stored as one
//! flat array of 32-byte nodes that the CPU traversal here and the WGSL one
//! read alike (the layout is the contract; see [`BvhNode`]).
//!
//! fogbank builds its own: the maintained Rust BVH with a GPU-readable
//! layout (`obvhs`) needs glam ≥ 0.33 while the workspace is on 0.30, and a
//! binned SAH build is short enough to own and test against brute force.

mod build;
mod node;
mod traverse;

pub use node::{Bvh, BvhNode};

use fogbank_math::Aabb;

impl Bvh {
    /// Builds over the boxes of primitives `0 .. bounds.len()`.
    pub fn new(bounds: &[Aabb]) -> Bvh {
        build::build(bounds)
    }
}
