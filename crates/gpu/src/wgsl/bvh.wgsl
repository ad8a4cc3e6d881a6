// Surfaces: watertight ray–triangle intersection and the walk of the
// compressed wide BVH, the mirror of fogbank_geometry (triangle.rs,
// wide/traverse.rs; analytic shapes in analytic_shapes.wgsl). The node
// array is the CPU's own (WideBvh::node_words: 80 bytes, five vec4<u32> a
// node); triangles are their corners in its leaf order (slot i holds the
// triangle of leaf slot i). WGSL has
// no f64, so the CPU's double-precision recomputation of edge functions
// that round to exactly zero is absent here: on such rays (a vertex or edge
// hit dead on) the two may pick different triangles of the same fan.
// Triangles with a non-finite corner, which the CPU never hits, are
// uploaded collapsed to a point, so no NaN reaches these tests.


struct TriHit {
    hit: bool,
    t: f32,
    b1: f32,
    b2: f32,
}

struct RayFrame {
    o: vec3<f32>,
    kx: u32,
    ky: u32,
    kz: u32,
    s: vec3<f32>,
}

struct SurfaceHit {
    // u32 max: nothing hit.
    slot: u32,
    t: f32,
    b1: f32,
    b2: f32,
    // The top-level leaf slot of the instance hit (u32 max: a shape of
    // the world's own hierarchy).
    instance: u32,
}

// A ray as a hierarchy's walk reads it.
struct WalkRay {
    o: vec3<f32>,
    d: vec3<f32>,
    inv_d: vec3<f32>,
    f: RayFrame,
    oct_inv: u32,
}

fn walk_ray(o: vec3<f32>, d: vec3<f32>) -> WalkRay {
    let oct_inv = select(4u, 0u, d.x < 0.0) | select(2u, 0u, d.y < 0.0) | select(1u, 0u, d.z < 0.0);
    return WalkRay(o, d, vec3<f32>(1.0) / d, ray_frame(o, d), oct_inv);
}


fn ray_frame(o: vec3<f32>, d: vec3<f32>) -> RayFrame {
    let a = abs(d);
    var kz = 2u;
    if (a.x > a.y) {
        if (a.x > a.z) {
            kz = 0u;
        }
    } else if (a.y > a.z) {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kz + 2u) % 3u;
    if (d[kz] < 0.0) {
        let t = kx;
        kx = ky;
        ky = t;
    }
    let dz = d[kz];
    return RayFrame(o, kx, ky, kz, vec3<f32>(-d[kx] / dz, -d[ky] / dz, 1.0 / dz));
}

fn error_gamma(n: f32) -> f32 {
    let e = 0.5 * 1.1920929e-7;
    return n * e / (1.0 - n * e);
}

fn frame_shear(f: RayFrame, p: vec3<f32>) -> vec3<f32> {
    let q = p - f.o;
    let z = q[f.kz];
    return vec3<f32>(q[f.kx] + f.s.x * z, q[f.ky] + f.s.y * z, z);
}

// fogbank_geometry::triangle::intersect.
fn intersect_triangle(f: RayFrame, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, t_max: f32) -> TriHit {
    let none = TriHit(false, 0.0, 0.0, 0.0);
    let a = frame_shear(f, p0);
    let b = frame_shear(f, p1);
    let c = frame_shear(f, p2);
    let e0 = b.x * c.y - b.y * c.x;
    let e1 = c.x * a.y - c.y * a.x;
    let e2 = a.x * b.y - a.y * b.x;
    if ((e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0)) {
        return none;
    }
    let det = e0 + e1 + e2;
    if (!finite(det) || det == 0.0) {
        return none;
    }
    let z0 = a.z * f.s.z;
    let z1 = b.z * f.s.z;
    let z2 = c.z * f.s.z;
    let t_scaled = e0 * z0 + e1 * z1 + e2 * z2;
    if (det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det)) {
        return none;
    }
    if (det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det)) {
        return none;
    }
    let inv = 1.0 / det;
    let b1 = e1 * inv;
    let b2 = e2 * inv;
    let t = t_scaled * inv;
    let max_z = max(abs(z0), max(abs(z1), abs(z2)));
    let delta_z = error_gamma(3.0) * max_z;
    let max_x = max(abs(a.x), max(abs(b.x), abs(c.x)));
    let max_y = max(abs(a.y), max(abs(b.y), abs(c.y)));
    let delta_x = error_gamma(5.0) * (max_x + max_z);
    let delta_y = error_gamma(5.0) * (max_y + max_z);
    let delta_e = 2.0 * (error_gamma(2.0) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let max_e = max(abs(e0), max(abs(e1), abs(e2)));
    let delta_t = 3.0 * (error_gamma(3.0) * max_e * max_z + delta_e * max_z + delta_z * max_e) * abs(inv);
    if (t <= delta_t || !finite(t) || !finite(b1) || !finite(b2)) {
        return none;
    }
    return TriHit(true, t, b1, b2);
}


// 1 + 2γ₃ rounded to f32, as the CPU's SLAB_GROW.
const SLAB_GROW: f32 = 1.0000003576;

// Byte k of a node's child_meta (words 6 and 7) or of a quantised plane
// (words 8 … 19, two words per plane set).
fn node_byte(lo: u32, hi: u32, c: u32) -> u32 {
    return (select(lo, hi, c >= 4u) >> (8u * (c & 3u))) & 0xffu;
}

// The hit mask of node `i`'s children whose boxes the ray enters in
// (0, t_max) (WideBvh's node_hits): an entered inner child sets bit 24 +
// (its slot ^ the ray's octant), an entered leaf its primitives' bits from
// its first slot offset. Each box is decoded as p + q·e and widened by the
// CPU's bound on decoding and quantisation, so neither misses a box the
// other enters. An axis the ray runs parallel to (|d| < 1e-30) is decided
// by the origin lying in the slab, never from 0·∞ = NaN: GPU compilers may
// assume NaN and infinities away (an NVIDIA H100 folded such a NaN test and
// missed rays grazing box planes that lavapipe hit).
fn wide_node_hits(o: vec3<f32>, d: vec3<f32>, inv_d: vec3<f32>, w0: vec4<u32>, w1: vec4<u32>,
                  planes: array<vec2<u32>, 6>, oct_inv: u32, t_max: f32) -> u32 {
    let p = bitcast<vec3<f32>>(w0.xyz);
    var hits = 0u;
    for (var c = 0u; c < 8u; c++) {
        let child = node_byte(w1.z, w1.w, c);
        if (child == 0u) {
            continue;
        }
        var near = 0.0;
        var far = min(t_max * SLAB_GROW, 3.4028235e38);
        var parallel_miss = false;
        for (var a = 0u; a < 3u; a++) {
            let e = bitcast<f32>(((w0.w >> (8u * a)) & 0xffu) << 23u);
            let margin = (abs(p[a]) + 256.0 * e) * (4.0 * 1.1920929e-7);
            let q_lo = f32(node_byte(planes[2u * a].x, planes[2u * a].y, c));
            let q_hi = f32(node_byte(planes[2u * a + 1u].x, planes[2u * a + 1u].y, c));
            if (abs(d[a]) < 1e-30) {
                let lo = q_lo * e + (p[a] - margin);
                let hi = q_hi * e + (p[a] + margin);
                parallel_miss = parallel_miss || o[a] < lo || o[a] > hi;
                continue;
            }
            let ta = (q_lo * e + (p[a] - margin - o[a])) * inv_d[a];
            let tb = (q_hi * e + (p[a] + margin - o[a])) * inv_d[a];
            near = max(near, min(ta, tb));
            far = min(far, max(ta, tb) * SLAB_GROW);
        }
        if (parallel_miss || near > far) {
            continue;
        }
        // Inner children's meta is 0b001_11xxx (24 + slot); a leaf's is its
        // primitive count in unary above its first slot offset.
        var index = child & 0x1fu;
        if ((child & 0x18u) == 0x18u) {
            index = index ^ oct_inv;
        }
        hits |= (child >> 5u) << index;
    }
    return hits;
}

// The stack walk of the wide BVH (Ylitie et al. 2017, Algorithm 1, as
// WideBvh::walk): hit leaves' primitives are tested first, then the inner
// children in the order the ray's octant gives, node groups with children
// left waiting on the stack. The closest hit in (0, t_max), or with `any`
// the first hit found; with `opaque`, triangles that let light through
// (surface_passes) are skipped. The world's hierarchy is walked first
// (nodes from 0); with instances (surface_instance_base() != 0) then the
// top level (Instances::intersect_where), whose leaf slots are instances:
// at each, the top level's waiting node and leaf groups go on the stack
// above a floor, the ray is carried into the group's space and the group's
// hierarchy walked down to that floor, then the world ray resumes (the
// nodes of every hierarchy in one array from their bases, leaf slots
// likewise). The kernel that includes this file declares `bvh_nodes`
// (array<vec4<u32>>) and provides surface_corner(slot, k),
// surface_passes(slot), surface_is_analytic(slot), surface_analytic(slot)
// (analytic_shapes.wgsl), surface_instance_base(), surface_tlas_base(),
// instance_bases(i) and instance_object_ray(i, o, d). An empty hierarchy
// is one node of zeros: no children, nothing hit.
fn bvh_trace(o: vec3<f32>, d: vec3<f32>, t_max_in: f32, any: bool, opaque: bool) -> SurfaceHit {
    let none = 0xffffffffu;
    var best = SurfaceHit(none, 0.0, 0.0, 0.0, none);
    if (arrayLength(&bvh_nodes) < 5u) {
        return best;
    }
    var t_max = t_max_in;
    let world = walk_ray(o, d);
    var r = world;
    // 0: the world's hierarchy, 1: the top level, 2: an instance's group.
    var tree = 0u;
    var node_base = 0u;
    var slot_base = 0u;
    var instance = none;
    var floor = 0u;
    // Node groups: x the first inner child's node, y the children still to
    // visit in bits 24-31 over the node's inner mask in bits 0-7. Leaf
    // groups (waiting only at an instance): x the first slot, y the slots
    // left in bits 0-23.
    var stack: array<vec2<u32>, BVH_STACK>;
    var top = 0u;
    // The root as the one inner child of a virtual node at index 0.
    var nodes = vec2<u32>(0u, 0x80000000u);
    var prims = vec2<u32>(0u, 0u);
    loop {
        while (prims.y != 0u) {
            let k = firstLeadingBit(prims.y);
            prims.y &= ~(1u << k);
            if (tree == 1u) {
                // An instance: its group's hierarchy, in the group's space.
                if ((nodes.y & 0xff000000u) != 0u && top < BVH_STACK) {
                    stack[top] = nodes;
                    top += 1u;
                }
                if (prims.y != 0u && top < BVH_STACK) {
                    stack[top] = prims;
                    top += 1u;
                }
                floor = top;
                instance = prims.x + k;
                let bases = instance_bases(instance);
                r = instance_object_ray(instance, o, d);
                tree = 2u;
                node_base = bases.x;
                slot_base = bases.y;
                nodes = vec2<u32>(0u, 0x80000000u);
                prims = vec2<u32>(0u, 0u);
                break;
            }
            let slot = slot_base + prims.x + k;
            if (opaque && surface_passes(slot)) {
                continue;
            }
            var h: TriHit;
            if (surface_is_analytic(slot)) {
                h = intersect_analytic(surface_analytic(slot), r.o, r.d, t_max);
            } else {
                h = intersect_triangle(r.f, surface_corner(slot, 0u), surface_corner(slot, 1u),
                                       surface_corner(slot, 2u), t_max);
            }
            if (h.hit) {
                t_max = h.t;
                best = SurfaceHit(slot, h.t, h.b1, h.b2, select(none, instance, tree == 2u));
                if (any) {
                    return best;
                }
            }
        }
        if ((nodes.y & 0xff000000u) != 0u) {
            let hits_imask = nodes.y;
            let k = firstLeadingBit(hits_imask);
            nodes.y &= ~(1u << k);
            if ((nodes.y & 0xff000000u) != 0u && top < BVH_STACK) {
                stack[top] = nodes;
                top += 1u;
            }
            // The child's slot, and its place among the inner children.
            let slot = (k - 24u) ^ r.oct_inv;
            let below = countOneBits(hits_imask & ~(0xffffffffu << slot));
            let n = 5u * (node_base + nodes.x + below);
            let w0 = bvh_nodes[n];
            let w1 = bvh_nodes[n + 1u];
            let w2 = bvh_nodes[n + 2u];
            let w3 = bvh_nodes[n + 3u];
            let w4 = bvh_nodes[n + 4u];
            let planes = array<vec2<u32>, 6>(w2.xy, w2.zw, w3.xy, w3.zw, w4.xy, w4.zw);
            let hits = wide_node_hits(r.o, r.d, r.inv_d, w0, w1, planes, r.oct_inv, t_max);
            nodes = vec2<u32>(w1.x, (hits & 0xff000000u) | (w0.w >> 24u));
            prims = vec2<u32>(w1.y, hits & 0x00ffffffu);
        } else {
            nodes = vec2<u32>(0u, 0u);
        }
        if (prims.y == 0u && (nodes.y & 0xff000000u) == 0u) {
            if (tree == 2u && top == floor) {
                // The group is done: back to the top level's world ray.
                tree = 1u;
                r = world;
                node_base = surface_tlas_base();
                slot_base = 0u;
                instance = none;
            }
            if (top == 0u) {
                if (tree != 0u || surface_instance_base() == 0u) {
                    break;
                }
                tree = 1u;
                node_base = surface_tlas_base();
                nodes = vec2<u32>(0u, 0x80000000u);
                continue;
            }
            top -= 1u;
            let e = stack[top];
            if ((e.y & 0xff000000u) != 0u) {
                nodes = e;
            } else {
                prims = e;
            }
        }
    }
    return best;
}
