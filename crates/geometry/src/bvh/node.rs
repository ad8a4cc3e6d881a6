//! The BVH's data: the flat node array and the primitive order of its
//! leaves.

use bytemuck::{Pod, Zeroable};
use fogbank_math::{Aabb, Vec3};

/// One node: its box, and either two children (`count == 0`: at
/// `index` and `index + 1`) or `count` primitives (leaf: entries
/// `index .. index + count` of [`Bvh::order`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub min: [f32; 3],
    pub count: u32,
    pub max: [f32; 3],
    pub index: u32,
}

impl BvhNode {
    pub fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::from(self.min), Vec3::from(self.max))
    }

    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// The hierarchy: nodes (root first; empty when there is nothing to hit)
/// and the primitive indices in leaf order. Primitives with empty boxes
/// (all corners NaN) are left out: nothing can hit them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    pub nodes: Vec<BvhNode>,
    pub order: Vec<u32>,
}

impl Bvh {
    /// Depth of the deepest leaf (the root alone is depth 1).
    pub fn depth(&self) -> usize {
        fn rec(nodes: &[BvhNode], i: usize) -> usize {
            let n = &nodes[i];
            if n.is_leaf() {
                1
            } else {
                1 + rec(nodes, n.index as usize).max(rec(nodes, n.index as usize + 1))
            }
        }
        if self.nodes.is_empty() {
            0
        } else {
            rec(&self.nodes, 0)
        }
    }
}
