// Surfaces: watertight ray–triangle intersection and BVH traversal, the
// mirror of fogbank_geometry (triangle.rs, bvh/traverse.rs; analytic
// shapes in analytic_shapes.wgsl). The node array
// is the same 32-byte layout the CPU builds; triangles are their corners in
// the BVH's leaf order (slot i holds the triangle of leaf entry i). WGSL has
// no f64, so the CPU's double-precision recomputation of edge functions
// that round to exactly zero is absent here: on such rays (a vertex or edge
// hit dead on) the two may pick different triangles of the same fan.
// Triangles with a non-finite corner, which the CPU never hits, are
// uploaded collapsed to a point, so no NaN reaches these tests.

struct BvhNode {
    min: vec3<f32>,
    count: u32,
    max: vec3<f32>,
    index: u32,
}


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
}

const BVH_STACK: u32 = 64u;

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

// Entry distance into the node's box within (0, t_max), or -1 (Traversal::
// enter). An axis the ray runs parallel to (d = ±0) constrains nothing when
// the origin lies in the closed slab and excludes the box otherwise; it is
// decided from d itself, never from 0·∞ = NaN as on the CPU: GPU compilers
// may assume NaN and infinities away (an NVIDIA H100 folded such a NaN
// test and missed rays grazing box planes that lavapipe hit). Directions
// below 1e-30 count as parallel (their 1/d would overflow). `t_max` is
// finite (at most f32::MAX); it grows by the rounding allowance too, so
// that a box whose entry rounds just past a hit found in a neighbouring
// triangle (a shared edge: the same point, t one ulp apart) is still entered.
fn node_enter(o: vec3<f32>, d: vec3<f32>, inv_d: vec3<f32>, n: BvhNode, t_max: f32) -> f32 {
    var t0 = 0.0;
    var t1 = min(t_max * SLAB_GROW, 3.4028235e38);
    for (var a = 0u; a < 3u; a++) {
        if (abs(d[a]) < 1e-30) {
            if (o[a] < n.min[a] || o[a] > n.max[a]) {
                return -1.0;
            }
            continue;
        }
        let ta = (n.min[a] - o[a]) * inv_d[a];
        let tb = (n.max[a] - o[a]) * inv_d[a];
        t0 = max(t0, min(ta, tb));
        t1 = min(t1, max(ta, tb) * SLAB_GROW);
    }
    return select(-1.0, t0, t0 <= t1);
}

// Stack traversal, nearer child first (fogbank_geometry's Bvh::walk, which
// also keeps each waiting far child's entry distance to drop it once a
// nearer hit is found; here that would double the stack's registers):
// the closest hit in (0, t_max), or with `any` the first hit found; with
// `opaque`, triangles that let light through (surface_passes) are skipped.
// The kernel that includes this file declares `bvh_nodes` and provides
// surface_corner(slot, k), surface_passes(slot), surface_is_analytic(slot)
// and surface_analytic(slot) (analytic_shapes.wgsl).
fn bvh_trace(o: vec3<f32>, d: vec3<f32>, t_max_in: f32, any: bool, opaque: bool) -> SurfaceHit {
    var best = SurfaceHit(0xffffffffu, 0.0, 0.0, 0.0);
    if (arrayLength(&bvh_nodes) == 0u) {
        return best;
    }
    // An empty hierarchy (no triangles: the binding still holds one node)
    // is a root with count 0 and index 0, which no built hierarchy has (an
    // inner root's children start at 1). Its box, of infinities, is never
    // tested: GPU compilers may assume infinities away, and on an NVIDIA
    // H100 the root then "entered" and the walk descended into node 0
    // forever.
    let root = bvh_nodes[0];
    if (root.count == 0u && root.index == 0u) {
        return best;
    }
    var t_max = t_max_in;
    let f = ray_frame(o, d);
    let inv_d = vec3<f32>(1.0) / d;
    if (node_enter(o, d, inv_d, root, t_max) < 0.0) {
        return best;
    }
    var stack: array<u32, 64>;
    var top = 0u;
    var node = 0u;
    loop {
        let n = bvh_nodes[node];
        var descend = false;
        if (n.count > 0u) {
            for (var slot = n.index; slot < n.index + n.count; slot++) {
                if (opaque && surface_passes(slot)) {
                    continue;
                }
                var h: TriHit;
                if (surface_is_analytic(slot)) {
                    h = intersect_analytic(surface_analytic(slot), o, d, t_max);
                } else {
                    h = intersect_triangle(f, surface_corner(slot, 0u), surface_corner(slot, 1u),
                                           surface_corner(slot, 2u), t_max);
                }
                if (h.hit) {
                    t_max = h.t;
                    best = SurfaceHit(slot, h.t, h.b1, h.b2);
                    if (any) {
                        return best;
                    }
                }
            }
        } else {
            let l = n.index;
            let r = n.index + 1u;
            let tl = node_enter(o, d, inv_d, bvh_nodes[l], t_max);
            let tr = node_enter(o, d, inv_d, bvh_nodes[r], t_max);
            if (tl >= 0.0 && tr >= 0.0) {
                let near_left = tl <= tr;
                stack[top] = select(l, r, near_left);
                top += 1u;
                node = select(r, l, near_left);
                descend = true;
            } else if (tl >= 0.0) {
                node = l;
                descend = true;
            } else if (tr >= 0.0) {
                node = r;
                descend = true;
            }
        }
        if (descend) {
            continue;
        }
        if (top == 0u) {
            break;
        }
        top -= 1u;
        node = stack[top];
    }
    return best;
}
