// Diagnostics: pin queries along unit-cube rays (pins.wgsl), to compare with
// fogbank_estimators::pins::Chord query by query. Per query: the popcount
// exponent, MSB distance sampling with the given collision mask and u, and
// Chord::distance with a fresh majorant mask from Pcg32(query, 7).

struct ChordQuery {
    o: vec3<f32>,
    t_start: f32,
    d: vec3<f32>,
    max_len: f32,
    mask: u32,
    t_min: f32,
    u: f32,
    iterations: u32,
}

@group(1) @binding(0) var<storage, read> queries: array<ChordQuery>;
@group(1) @binding(1) var<storage, read_write> answers: array<vec4<u32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= arrayLength(&queries)) {
        return;
    }
    let q = queries[i];
    let c = chord_new(Ray(q.o, q.d), q.t_start);
    if (!c.valid) {
        answers[i] = vec4<u32>(0xffffffffu, 0u, 0u, 0u);
        return;
    }
    var rng = pcg32_new(vec2<u32>(i, 0u), vec2<u32>(7u, 0u));
    let pin = Pin(q.mask, q.t_min);
    answers[i] = vec4<u32>(
        chord_count(c, q.mask, q.max_len),
        bitcast<u32>(chord_sample_distance(c, q.mask, q.max_len, q.u)),
        bitcast<u32>(pin_distance(pin, c, q.max_len, q.iterations, &rng)),
        bitcast<u32>(pin_transmittance(pin, c, q.max_len)));
}
