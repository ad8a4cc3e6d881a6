// fogbank_estimators::pins (Hansen 2025): a pin record, the majorant mask
// (mask.rs), queries along a ray's own chord (chord.rs) and pin tracing
// (pin.rs), draw for draw as on the CPU. Everything is in the medium's
// unit cube (index box scaled to [0, 1]³); ray parameters stay the world's.

// Interval i of a pin at bit 31 − i; t_min = 1 means no attenuation.
struct Pin {
    mask: u32,
    t_min: f32,
}

// pin::canonical: d or −d, whichever points towards +z (then +y, then +x).
fn pin_canonical(d: vec3<f32>) -> vec3<f32> {
    let flip = d.z < 0.0 || (d.z == 0.0 && (d.y < 0.0 || (d.y == 0.0 && d.x < 0.0)));
    return select(d, -d, flip);
}

// mask::sample_mask, Hansen 2025 Eq. 3.11: k bisection steps between an
// all-ones and an all-zeros word, one random word each; the last midpoint.
fn pin_sample_mask(p: f32, iterations: u32, rng: ptr<function, Pcg32>) -> u32 {
    var upper = 0xffffffffu;
    var lower = 0u;
    var p_upper = 1.0;
    var p_lower = 0.0;
    var middle = 0u;
    for (var i = 0u; i < iterations; i++) {
        let u = pcg32_next_u32(rng);
        middle = (u & lower) | (~u & upper);
        let p_middle = 0.5 * (p_lower + p_upper);
        if (p_middle > p) {
            upper = middle;
            p_upper = p_middle;
        } else {
            lower = middle;
            p_lower = p_middle;
        }
    }
    return middle;
}

// Chord: where a query starts among the 32 bits of its own chord.
struct Chord {
    length: f32,
    rel: f32,
    offset: u32,
    reversed: bool,
    valid: bool,
}

// Chord::new on a unit-cube ray: the line's chord through the cube and the
// bit of t_start on it (rel clamped to [0, 0.9999] as the thesis).
fn chord_new(r: Ray, t_start: f32) -> Chord {
    var c = Chord(0.0, 0.0, 0u, false, false);
    let hit = intersect_box(r, vec3<f32>(1.0), -F32_INF, F32_INF);
    let length = hit.y - hit.x;
    if (hit.z == 0.0 || !(length > 0.0)) {
        return c;
    }
    c.length = length;
    c.rel = clamp((t_start - hit.x) / length, 0.0, 0.9999);
    c.offset = u32(c.rel * 32.0);
    c.reversed = any(pin_canonical(r.d) != r.d);
    c.valid = true;
    return c;
}

fn chord_oriented(c: Chord, mask: u32) -> u32 {
    return select(mask, reverseBits(mask), c.reversed);
}

// Chord::sample_distance (the thesis's Fig. 8.2): the first set bit at or
// after the start's, uniform inside it. firstLeadingBit(0) is −1, so the
// empty masks are answered first.
fn chord_sample_distance(c: Chord, collision_mask: u32, max_len: f32, u: f32) -> f32 {
    if (collision_mask == 0u) {
        return NO_HIT;
    }
    let m = chord_oriented(c, collision_mask) << c.offset;
    if (m == 0u) {
        return NO_HIT;
    }
    let d = (f32(31u - firstLeadingBit(m)) + u) * c.length / 32.0;
    return select(NO_HIT, d, d <= max_len);
}

// Chord::count, Hansen 2025 Eq. 3.7's exponent: set bits from the start's bit
// to the bit holding the end, both included.
fn chord_count(c: Chord, mask: u32, max_len: f32) -> u32 {
    if (mask == 0u) {
        return 0u;
    }
    let rel_end = c.rel + max_len / c.length;
    let keep_from = u32(clamp(1.0 - rel_end, 0.0, 0.9999) * 32.0);
    let m = chord_oriented(c, mask);
    return countOneBits((m & (0xffffffffu << keep_from)) << c.offset);
}

// Chord::distance (§3.4.3): Ĩ AND a fresh majorant mask of density 1 − t_min.
fn pin_distance(pin: Pin, c: Chord, max_len: f32, iterations: u32,
                rng: ptr<function, Pcg32>) -> f32 {
    if (pin.mask == 0u) {
        return NO_HIT;
    }
    let h = pin_sample_mask(1.0 - pin.t_min, iterations, rng);
    let u = pcg32_next_f32(rng);
    return chord_sample_distance(c, pin.mask & h, max_len, u);
}

// Chord::transmittance, Hansen 2025 Eq. 3.7: t_min^popcount (by products, so
// 0^0 = 1 as powi gives).
fn pin_transmittance(pin: Pin, c: Chord, max_len: f32) -> f32 {
    let n = chord_count(c, pin.mask, max_len);
    var t = 1.0;
    for (var i = 0u; i < n; i++) {
        t *= pin.t_min;
    }
    return t;
}

// The world length of an index-space vector: the inverse of the world →
// index rows by cofactors (WGSL has no matrix inverse).
fn index_to_world_length(m: MediumGpu, v: vec3<f32>) -> f32 {
    let r0 = m.w2i0.xyz;
    let r1 = m.w2i1.xyz;
    let r2 = m.w2i2.xyz;
    let c0 = cross(r1, r2);
    let det = dot(r0, c0);
    return length(c0 * v.x + cross(r2, r0) * v.y + cross(r0, r1) * v.z) / abs(det);
}

// pin::interval_transmittances: t_i of the 32 equal intervals of the chord
// start → end, each marched in ⌈length/step⌉ sub-steps sharing one jitter.
// The lookup count starts at 0 per pin, as the CPU's (it keys the
// stochastic filter).
fn pin_interval_transmittances(m: MediumGpu, start: vec3<f32>, end: vec3<f32>, step: f32,
                               rng: ptr<function, Pcg32>, t: ptr<function, array<f32, 32>>) {
    let dims = vec3<f32>(m.dims);
    let delta = (end - start) / 32.0;
    let world_len = index_to_world_length(m, delta * dims);
    let n = clamp(u32(ceil(length(delta) / max(step, 1e-6))), 1u, 65536u);
    var lookups = 0u;
    for (var i = 0u; i < 32u; i++) {
        let u = pcg32_next_f32(rng);
        var sum = 0.0;
        for (var j = 0u; j < n; j++) {
            let s = (f32(i) + (f32(j) + u) / f32(n)) / 32.0;
            sum += sigma_t_at(m, (start + (end - start) * s) * dims, rng, &lookups);
        }
        (*t)[i] = exp(-(sum / f32(n)) * world_len);
    }
}

// Pin::trace + Pin::from_transmittances, Hansen 2025 Eq. 3.5: the line
// through `point` along `direction` (either sign), its ratio bitmask with
// P(bit i) = (1 − t_i)/(1 − t_min); a clear line is Pin(0, 1).
fn pin_trace(m: MediumGpu, point: vec3<f32>, direction: vec3<f32>, step: f32,
             rng: ptr<function, Pcg32>) -> Pin {
    let clear = Pin(0u, 1.0);
    let d = pin_canonical(direction);
    let d2 = dot(d, d);
    if (!(d2 > 0.0)) {
        return clear;
    }
    var line: Ray;
    line.o = clamp(point, vec3<f32>(0.0), vec3<f32>(1.0));
    line.d = d;
    let hit = intersect_box(line, vec3<f32>(1.0), -F32_INF, F32_INF);
    if (hit.z == 0.0 || !(hit.y > hit.x)) {
        return clear;
    }
    var t: array<f32, 32>;
    pin_interval_transmittances(m, ray_at(line, hit.x), ray_at(line, hit.y), step, rng, &t);
    var t_min = 1.0;
    for (var i = 0u; i < 32u; i++) {
        t_min = min(t_min, t[i]);
    }
    t_min = max(t_min, 0.0);
    if (t_min >= 1.0) {
        return clear;
    }
    var mask = 0u;
    for (var i = 0u; i < 32u; i++) {
        let p = (1.0 - clamp(t[i], 0.0, 1.0)) / (1.0 - t_min);
        if (pcg32_next_f32(rng) < p) {
            mask |= 1u << (31u - i);
        }
    }
    return Pin(mask, t_min);
}
