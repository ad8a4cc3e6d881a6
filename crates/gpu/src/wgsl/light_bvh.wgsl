// fogbank_render::lights::bvh and light_bounds: the light BVH over the
// emitting triangles. Its nodes are three vec4s each in `shading` from
// env.bvh_nodes on, their light_bounds::Importance: (centre, φ),
// (normal-cone axis, cos θ_o), (r², d²_min, sin θ_o, the index as an exact
// float: interior node → its second child, leaf → −(light + 1)).
// A light's bit trail (bit k: second child at depth k) is its record's
// `trail`. Lights from env.bvh_first on are picked through the tree.

const NO_LIGHT: u32 = 0xffffffffu;
// The scene picks its emitting triangles through the tree (pipeline
// constant: without one the driver compiles the descent out).
override LIGHT_BVH: bool = false;
const ONE_MINUS_EPSILON: f32 = 0.99999994;

// Node k's second child, or for a leaf its light with BVH_LEAF set.
const BVH_LEAF: u32 = 0x80000000u;
fn light_node_index(k: u32) -> u32 {
    let x = shading[env.bvh_nodes + 3u * k + 2u].w;
    if (x < 0.0) {
        return BVH_LEAF | (u32(-x) - 1u);
    }
    return u32(x);
}

// cos and sin of max(0, θ_a − θ_b) from (cos, sin) of θ_a and θ_b.
fn sub_clamped(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    if (a.x > b.x) {
        return vec2<f32>(1.0, 0.0);
    }
    return vec2<f32>(a.x * b.x + a.y * b.y, a.y * b.x - a.x * b.y);
}

fn sin_of(c: f32) -> f32 {
    return sqrt(max(1.0 - c * c, 0.0));
}

// light_bounds::Importance::of node k at p.
fn light_node_importance(k: u32, p: vec3<f32>) -> f32 {
    let base = env.bvh_nodes + 3u * k;
    let a = shading[base];
    let b = shading[base + 1u];
    let c = shading[base + 2u];
    let to_p = p - a.xyz;
    let d2_centre = dot(to_p, to_p);
    let d2 = max(d2_centre, c.y);
    if (d2_centre <= c.x) {
        return a.w / d2;
    }
    let cos_w = dot(b.xyz, to_p / sqrt(d2_centre));
    let sin2_b = c.x / d2_centre;
    let x = sub_clamped(vec2<f32>(cos_w, sin_of(cos_w)), vec2<f32>(b.w, c.z));
    let cos_p = sub_clamped(x, vec2<f32>(sqrt(max(1.0 - sin2_b, 0.0)), sqrt(sin2_b))).x;
    if (cos_p <= 0.0) {
        return 0.0;
    }
    return max(a.w * cos_p / d2, 0.0);
}

// LightBvh::first_child_probability of interior node k (< 0: neither
// child reaches p). Clamped: GPU division may round i0 / (i0 + 0) past 1.
fn light_first_child(k: u32, p: vec3<f32>) -> f32 {
    let i0 = light_node_importance(k + 1u, p);
    let i1 = light_node_importance(light_node_index(k), p);
    let sum = i0 + i1;
    if (sum > 0.0) {
        return clamp(i0 / sum, 0.0, 1.0);
    }
    return -1.0;
}

// LightBvh::pick: (light, probability within the tree), index
// NO_LIGHT when the descent finds no light reaching p.
fn light_bvh_pick(u_in: f32, p: vec3<f32>) -> LightPick {
    var u = u_in;
    var k = 0u;
    var pmf = 1.0;
    for (var depth = 0u; depth < 32u; depth++) {
        let index = light_node_index(k);
        if ((index & BVH_LEAF) != 0u) {
            return LightPick(index & ~BVH_LEAF, pmf);
        }
        let p0 = light_first_child(k, p);
        if (p0 < 0.0) {
            break;
        }
        if (u < p0) {
            u = min(u / p0, ONE_MINUS_EPSILON);
            pmf *= p0;
            k += 1u;
        } else {
            u = min((u - p0) / (1.0 - p0), ONE_MINUS_EPSILON);
            pmf *= 1.0 - p0;
            k = index;
        }
    }
    return LightPick(NO_LIGHT, 0.0);
}

// LightBvh::pmf: the probability that light_bvh_pick at p returns li.
fn light_bvh_pmf(li: u32, p: vec3<f32>) -> f32 {
    let trail = lights[li].trail;
    if (trail == NO_LIGHT) {
        return 0.0;
    }
    var k = 0u;
    var pmf = 1.0;
    for (var depth = 0u; depth < 32u; depth++) {
        let index = light_node_index(k);
        if ((index & BVH_LEAF) != 0u) {
            return pmf;
        }
        let p0 = light_first_child(k, p);
        if (p0 < 0.0) {
            return 0.0;
        }
        if (((trail >> depth) & 1u) == 0u) {
            pmf *= p0;
            k += 1u;
        } else {
            pmf *= 1.0 - p0;
            k = index;
        }
    }
    return 0.0;
}
