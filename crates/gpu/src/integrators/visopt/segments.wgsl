// visopt/segments.rs and lists.rs on the device: K(t) and h(t) of a ray's
// importance list (Lerzer and Dachsbacher 2025 §5.1, Eq. 7 corrected), read from the frozen
// camera lists in `visopt_data` or from the NEE ray's list in
// `light_scratch` (WGSL cannot pass a pointer that may be either, so an
// entry is read through `list_entry`).

const LIST_CAMERA: u32 = 0u;
const LIST_LIGHT: u32 = 1u;

// optimised::RayList: which list, where it lies, and its t axis.
struct RayList {
    source: u32,
    offset: u32,
    size: u32,
    big_k_z: f32,
    length: f32,
    // Ray parameter of t = 0 and the direction t grows in (±1).
    origin: f32,
    sign: f32,
}

fn list_entry(l: RayList, i: u32) -> vec4<f32> {
    if (l.source == LIST_CAMERA) {
        return visopt_data[l.offset + i];
    }
    return light_scratch[l.offset + i];
}

// RayList::t_of: t in [−1, 1]³ units of ray parameter s.
fn list_t(l: RayList, s: f32) -> f32 {
    return clamp((s - l.origin) * l.sign * vo.unit, 0.0, l.length);
}

// segments::integral_at: K(t) = ∫₀ᵗ k̃², the last entry with t_i ≤ t found
// by binary search; inside it K_i + (t − t_i) k_i², in the gap after it
// linear to the next entry's K (or K(z) at L).
fn integral_at(l: RayList, t: f32) -> f32 {
    var lo = 0u;
    var hi = l.size;
    while (lo < hi) {
        let mid = (lo + hi) / 2u;
        if (list_entry(l, mid).x <= t) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    var k0 = 0.0;
    var right = 0.0;
    if (lo > 0u) {
        let s = list_entry(l, lo - 1u);
        if (t <= s.x + s.y) {
            return s.w + (t - s.x) * s.z * s.z;
        }
        k0 = s.w + s.y * s.z * s.z;
        right = s.x + s.y;
    }
    var k1 = l.big_k_z;
    var next_t = l.length;
    if (lo < l.size) {
        let n = list_entry(l, lo);
        k1 = n.w;
        next_t = n.x;
    }
    if (next_t <= right) {
        return max(k1, k0);
    }
    return k0 + (k1 - k0) * clamp((t - right) / (next_t - right), 0.0, 1.0);
}

// segments::h, Lerzer and Dachsbacher 2025 Eq. 7 corrected: (r − q) K(t) + q K(z).
fn list_h(l: RayList, t: f32) -> f32 {
    let k_t = clamp(integral_at(l, t), 0.0, l.big_k_z);
    return max(vo.r * k_t + vo.q * (l.big_k_z - k_t), 0.0);
}

// optimised::factor: μ'/μ at ray parameter s and world point p, σ_t known.
fn list_factor(l: RayList, s: f32, p: vec3<f32>, sigma_t: f32) -> f32 {
    let h = list_h(l, list_t(l, s));
    if (h <= 0.0) {
        return 1.0;
    }
    return mu_factor(importance_at(p, sigma_t), h);
}

// lists::merge_distance: the key, or 2·L/N.
fn merge_distance(length: f32, n: u32) -> f32 {
    if (vo.merge_distance > 0.0) {
        return vo.merge_distance;
    }
    return 2.0 * length / f32(max(n, 1u));
}

// lists::light_list for the world shadow ray `ray` over [s0, s1]: N
// stratified samples from the light's end s1, merged by Alg. 1 into scratch
// slot `slot` and integrated (segments::integrate). The samples come in t
// order and the list starts empty, so no candidate ever falls inside an
// entry of another importance: Alg. 1's split branch never runs and the
// merge is one forward pass.
fn build_light_list(ray: Ray, s0: f32, s1: f32, slot: u32, rng: ptr<function, Pcg32>) -> RayList {
    let n = vo.light_samples;
    let first = slot * n;
    var l = RayList(LIST_LIGHT, first, 0u, 0.0, (s1 - s0) * vo.unit, s1, -1.0);
    let d = merge_distance(l.length, n);
    var count = 0u;
    for (var j = 0u; j < n; j++) {
        let t = min((f32(j) + pcg32_next_f32(rng)) / f32(n) * l.length, l.length);
        let w = ray_at(ray, s1 - t / vo.unit);
        let k = importance_at(w, sigma_smooth(media[0], w));
        if (count > 0u) {
            let c = light_scratch[first + count - 1u];
            let right = c.x + c.y;
            if (abs(c.z - k) <= vo.tolerance) {
                if (t >= c.x && t <= right) {
                    continue;
                }
                if (t - right < d) {
                    light_scratch[first + count - 1u].y = max(right, t) - c.x;
                    continue;
                }
            }
        }
        light_scratch[first + count] = vec4<f32>(t, 0.0, k, 0.0);
        count++;
    }
    l.size = count;
    // segments::integrate: segments add l k², gaps their neighbours' mean
    // importance squared times their length (0 beyond the ends).
    var acc = 0.0;
    var right = 0.0;
    var k_prev = 0.0;
    for (var i = 0u; i < count; i++) {
        let s = light_scratch[first + i];
        let mean = 0.5 * (k_prev + s.z);
        acc += max(s.x - right, 0.0) * mean * mean;
        light_scratch[first + i].w = acc;
        acc += s.y * s.z * s.z;
        right = max(right, s.x + s.y);
        k_prev = s.z;
    }
    let mean = 0.5 * k_prev;
    l.big_k_z = acc + max(l.length - right, 0.0) * mean * mean;
    return l;
}
