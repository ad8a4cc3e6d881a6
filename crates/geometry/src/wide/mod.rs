//! The CPU's ray-tracing hierarchy: a compressed 8-wide BVH (Ylitie, Karras
//! and Laine 2017, "Efficient incoherent ray traversal on GPUs through
//! compressed wide BVHs"), whose 80-byte nodes hold their eight children's
//! boxes quantised to bytes on a per-node power-of-two grid.
//!
//! Construction is the maintained `obvhs` crate's: PLOC (Meister and
//! Bittner 2018) over the primitives' boxes, reinsertion optimisation
//! (Meister and Bittner 2017), then the SAH-optimal collapse to 8-wide nodes
//! with at most three primitives per leaf. Measured on `bvh-perf`'s 2.06 M
//! triangles it builds in about a second where fogbank's binned-SAH BVH2
//! took 1.4–4.8 s, and its trees trace faster (`docs/results/surfaces/bvh/`).
//!
//! Traversal is fogbank's own ([`traverse`]): obvhs's node test clamps entry
//! distances to an absolute 10⁻⁴ and has no rounding allowance, which loses
//! hits close to a ray's origin and grazing ones; fogbank's decodes each
//! child box widened by a bound on the decoding's rounding and tests it
//! with the same conservative slab test as the BVH2 ([`crate::Bvh`]), over
//! the open interval `(0, t_max)`.

mod traverse;

use fogbank_math::{Aabb, Vec3};
use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
use obvhs::cwbvh::node::CwBvhNode;
use obvhs::ploc::{PlocBuilder, PlocSearchDistance, SortPrecision};

/// Primitives per leaf at most (the node format's limit is 3).
const MAX_LEAF: u32 = 3;

/// The largest coordinate a primitive's box may reach: the surface area of
/// a box of edge 2·10¹⁸ (6 · 4·10³⁶) still fits in f32 (3.4·10³⁸).
pub const MAX_COORD: f32 = 1.0e18;

/// The hierarchy: nodes (root first; empty when there is nothing to hit)
/// and the primitive of each leaf slot.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WideBvh {
    nodes: Vec<CwBvhNode>,
    order: Vec<u32>,
}

impl WideBvh {
    /// Builds over the boxes of primitives `0 .. bounds.len()`. Boxes that
    /// are empty or not finite (NaN or infinite corners) are left out:
    /// nothing can hit them. So are boxes reaching beyond ±[`MAX_COORD`]:
    /// the builder's surface areas of such boxes overflow f32 and fail its
    /// assertions. Deterministic whatever the thread count.
    pub fn new(bounds: &[Aabb]) -> WideBvh {
        let within = |v: Vec3| v.abs().max_element() <= MAX_COORD;
        let kept: Vec<u32> = (0..bounds.len() as u32)
            .filter(|&i| {
                let b = &bounds[i as usize];
                !b.is_empty() && within(b.min) && within(b.max)
            })
            .collect();
        if kept.is_empty() {
            return WideBvh::default();
        }
        let boxes: Vec<obvhs::aabb::Aabb> = kept
            .iter()
            .map(|&i| {
                let b = &bounds[i as usize];
                obvhs::aabb::Aabb::new(b.min.into(), b.max.into())
            })
            .collect();
        // obvhs's "medium" preset, without its debug-build validation pass.
        let mut bvh2 = PlocBuilder::with_capacity(boxes.len()).build(
            PlocSearchDistance::Medium,
            &boxes,
            (0..boxes.len() as u32).collect(),
            SortPrecision::U64,
            3,
        );
        obvhs::bvh2::reinsertion::ReinsertionOptimizer::default().run(&mut bvh2, 0.05, None);
        let cw = bvh2_to_cwbvh(&bvh2, MAX_LEAF, true, false);
        let order = cw
            .primitive_indices
            .iter()
            .map(|&k| kept[k as usize])
            .collect();
        WideBvh {
            nodes: cw.nodes,
            order,
        }
    }

    /// The nodes as the GPU reads them: 20 little-endian words each, in
    /// `obvhs`'s `CwBvhNode` layout (origin p, exponents and inner mask,
    /// child and primitive bases, child meta, then the quantised child
    /// boxes' min x, max x, min y, max y, min z, max z, a byte per child).
    pub fn node_words(&self) -> &[[u32; 20]] {
        bytemuck::cast_slice(&self.nodes)
    }

    /// The primitive in each leaf slot.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Bytes of nodes and leaf slots.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<CwBvhNode>() + self.order.len() * 4
    }

    /// Depth of the deepest node (the root alone is depth 1).
    pub fn depth(&self) -> usize {
        let mut depth = 0;
        let mut stack = Vec::new();
        if !self.nodes.is_empty() {
            stack.push((0usize, 1usize));
        }
        while let Some((i, d)) = stack.pop() {
            depth = depth.max(d);
            let n = &self.nodes[i];
            // Inner children are stored consecutively from child_base_idx.
            let inner = n.imask.count_ones() as usize;
            for c in 0..inner {
                stack.push((n.child_base_idx as usize + c, d + 1));
            }
        }
        depth
    }
}
