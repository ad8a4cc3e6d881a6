//! Traversal of the compressed wide BVH (Ylitie et al. 2017, Algorithm 1):
//! a node's hit children and leaf primitives are kept as bit masks ("node
//! groups" and "primitive groups"), children are visited in the order that
//! the ray's octant gives (near to far along each axis), and node groups
//! with children left wait on a stack. Closest hit shrinks `t_max` as hits
//! are found; any hit stops at the first.

use super::WideBvh;
use crate::bvh::traverse::{grown, Walk, SLAB_GROW};
use fogbank_math::Ray;
use obvhs::cwbvh::node::CwBvhNode;

/// Entries the stack holds before it spills to the heap (a well-formed
/// 8-wide tree of any size needs far fewer; a degenerate one may not).
const STACK: usize = 64;

/// Byte `b` of every 8-byte lane set: one mask bit per child.
const BYTES: u64 = 0x0101_0101_0101_0101;

/// A node group (`base`: index of the first inner child; `hits`: inner
/// children still to visit in bits 24–31, the node's inner-child mask in
/// bits 0–7) or a primitive group (`base`: first leaf slot; `hits`: slots
/// still to test in bits 0–23).
#[derive(Clone, Copy, Default)]
struct Group {
    base: u32,
    hits: u32,
}

/// The ray's octant, inverted, in every byte: children are ordered by it.
fn octant_inv4(ray: &Ray) -> u32 {
    let bit = |c: f32, b: u32| if c < 0.0 { 0 } else { b };
    (bit(ray.d.x, 4) | bit(ray.d.y, 2) | bit(ray.d.z, 1)) * 0x0101_0101
}

/// For each child (byte), the bits it sets in a node's hit mask when its
/// box is hit (one for an inner child, one per primitive for a leaf, none
/// for an empty slot), and where they go: an inner child's bit 24 + its
/// slot in traversal order, a leaf's primitives from its first slot.
fn child_bits(n: &CwBvhNode, oct_inv4: u32) -> (u64, u64) {
    let meta = u64::from_le_bytes(n.child_meta);
    // Inner children have meta 0b001_11xxx (24 + slot, flagged in bit 5).
    let inner = (meta & (meta << 1)) & (BYTES << 4);
    let inner_bytes = (inner >> 4) * 0xff;
    let oct = (oct_inv4 as u64) | ((oct_inv4 as u64) << 32);
    let index = (meta ^ (oct & inner_bytes)) & (BYTES * 0x1f);
    let bits = (meta >> 5) & (BYTES * 0x07);
    (bits, index)
}

/// A ray prepared for the child-box tests. A direction component of zero
/// gets the reciprocal ±`f32::MAX` instead of ±∞: a box plane through the
/// origin then gives the distance 0 (not 0 · ∞ = NaN) and any other plane
/// ±∞ or a distance beyond every finite `t_max`, so the slab test needs no
/// NaN case.
struct WideRay {
    o: [f32; 3],
    inv_d: [f32; 3],
    oct_inv4: u32,
}

impl WideRay {
    fn new(ray: &Ray) -> WideRay {
        let inv = |d: f32| match d {
            0.0 => f32::MAX.copysign(d),
            d => 1.0 / d,
        };
        WideRay {
            o: ray.o.to_array(),
            inv_d: [inv(ray.d.x), inv(ray.d.y), inv(ray.d.z)],
            oct_inv4: octant_inv4(ray),
        }
    }
}

#[inline(always)]
fn min(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

#[inline(always)]
fn max(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// The hit mask of node `n`'s children whose boxes the ray enters in
/// `(0, t_max)`. Each box is decoded as `p + q · e` (q·e is exact: e is a
/// power of two) and widened by a bound on the rounding of that sum and of
/// the builder's quantisation, so that decoding never shrinks a box; the
/// slabs of all eight children are tested side by side (the loops over
/// children vectorise).
#[inline(always)]
fn node_hits(n: &CwBvhNode, r: &WideRay, t_max: f32) -> u32 {
    let mut near = [0.0f32; 8];
    let mut far = [grown(t_max); 8];
    let q_lo = [&n.child_min_x, &n.child_min_y, &n.child_min_z];
    let q_hi = [&n.child_max_x, &n.child_max_y, &n.child_max_z];
    for a in 0..3 {
        let e = f32::from_bits((n.e[a] as u32) << 23);
        let margin = (n.p[a].abs() + 256.0 * e) * (4.0 * f32::EPSILON);
        let (lo_base, hi_base) = (n.p[a] - margin - r.o[a], n.p[a] + margin - r.o[a]);
        let inv = r.inv_d[a];
        for c in 0..8 {
            let ta = (q_lo[a][c] as f32 * e + lo_base) * inv;
            let tb = (q_hi[a][c] as f32 * e + hi_base) * inv;
            near[c] = max(near[c], min(ta, tb));
            far[c] = min(far[c], max(ta, tb) * SLAB_GROW);
        }
    }
    let (bits8, index8) = child_bits(n, r.oct_inv4);
    let mut mask = 0u32;
    for c in 0..8 {
        let bits = (bits8 >> (8 * c)) as u32 & 0xff;
        if near[c] <= far[c] {
            mask |= bits << ((index8 >> (8 * c)) as u32 & 0xff);
        }
    }
    mask
}

/// The node of node `n`'s inner child in slot `slot`: inner children are
/// stored consecutively from `child_base_idx`, in slot order.
#[inline(always)]
fn inner_child(n: &CwBvhNode, slot: u32) -> u32 {
    n.child_base_idx + (n.imask as u32 & !(u32::MAX << slot)).count_ones()
}

/// Highest set bit of a non-zero word.
fn top_bit(x: u32) -> u32 {
    31 - x.leading_zeros()
}

/// The traversal stack: fixed entries, then the heap.
struct Stack {
    fixed: [Group; STACK],
    top: usize,
    spill: Vec<Group>,
}

impl Stack {
    fn push(&mut self, g: Group) {
        if self.top < STACK {
            self.fixed[self.top] = g;
            self.top += 1;
        } else {
            self.spill.push(g);
        }
    }

    fn pop(&mut self) -> Option<Group> {
        if let Some(g) = self.spill.pop() {
            return Some(g);
        }
        self.top = self.top.checked_sub(1)?;
        Some(self.fixed[self.top])
    }
}

impl Walk for WideBvh {
    /// Visits the leaf slots of every leaf box the ray enters before
    /// `t_max`; `visit` may lower `t_max` and returns true to stop. Where
    /// the processor has AVX2 the eight children's slabs are tested in one
    /// 256-bit lane each (the same arithmetic, so the same answers).
    fn walk(&self, ray: &Ray, t_max: &mut f32, visit: impl FnMut(u32, &mut f32) -> bool) {
        #[cfg(target_arch = "x86_64")]
        if is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2, checked just above.
            return unsafe { self.walk_avx2(ray, t_max, visit) };
        }
        self.walk_any(ray, t_max, visit)
    }
}

impl WideBvh {
    /// Asks the memory system for the inner children the ray enters (bits
    /// of `entered`, in traversal order) while the node's leaf primitives
    /// are tested: a walk through a tree larger than the cache otherwise
    /// stalls on every node it reads.
    #[inline(always)]
    fn prefetch_children(&self, n: &CwBvhNode, mut entered: u32, oct_inv: u32) {
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (n, &mut entered, oct_inv);
        #[cfg(target_arch = "x86_64")]
        while entered != 0 {
            let k = entered.trailing_zeros();
            entered &= entered - 1;
            if let Some(c) = self.nodes.get(inner_child(n, k ^ oct_inv) as usize) {
                use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
                let p = c as *const CwBvhNode as *const i8;
                // SAFETY: a prefetch is a hint that never faults; both
                // addresses lie in the node (80 bytes: two cache lines).
                unsafe {
                    _mm_prefetch(p, _MM_HINT_T0);
                    _mm_prefetch(p.add(79), _MM_HINT_T0);
                }
            }
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn walk_avx2(
        &self,
        ray: &Ray,
        t_max: &mut f32,
        visit: impl FnMut(u32, &mut f32) -> bool,
    ) {
        self.walk_any(ray, t_max, visit)
    }

    #[inline(always)]
    fn walk_any(&self, ray: &Ray, t_max: &mut f32, mut visit: impl FnMut(u32, &mut f32) -> bool) {
        if self.nodes.is_empty() {
            return;
        }
        // Finite from here on (see Traversal::enter_box).
        *t_max = t_max.min(f32::MAX);
        let r = WideRay::new(ray);
        let oct_inv4 = r.oct_inv4;
        let mut stack = Stack {
            fixed: [Group::default(); STACK],
            top: 0,
            spill: Vec::new(),
        };
        // The root as the one inner child of a virtual node at index 0.
        let mut nodes = Group {
            base: 0,
            hits: 0x8000_0000,
        };
        let mut prims = Group::default();
        loop {
            while prims.hits != 0 {
                let k = top_bit(prims.hits);
                prims.hits &= !(1 << k);
                if visit(prims.base + k, t_max) {
                    return;
                }
            }
            if nodes.hits & 0xff00_0000 != 0 {
                let hits_imask = nodes.hits;
                let k = top_bit(hits_imask);
                nodes.hits &= !(1 << k);
                if nodes.hits & 0xff00_0000 != 0 {
                    stack.push(nodes);
                }
                // The child's slot in the node, and its place among the
                // node's inner children (stored consecutively).
                let slot = (k - 24) ^ (oct_inv4 & 0xff);
                let below = (hits_imask & !(u32::MAX << slot)).count_ones();
                let n = &self.nodes[(nodes.base + below) as usize];
                let hits = node_hits(n, &r, *t_max);
                self.prefetch_children(n, hits >> 24, oct_inv4 & 0xff);
                nodes = Group {
                    base: n.child_base_idx,
                    hits: (hits & 0xff00_0000) | n.imask as u32,
                };
                prims = Group {
                    base: n.primitive_base_idx,
                    hits: hits & 0x00ff_ffff,
                };
            } else {
                nodes = Group::default();
            }
            if prims.hits == 0 && nodes.hits & 0xff00_0000 == 0 {
                match stack.pop() {
                    Some(g) => nodes = g,
                    None => return,
                }
            }
        }
    }
}
