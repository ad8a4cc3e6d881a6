// Diagnostics: pick_light and light_pmf_at (lights.wgsl, light_bvh.wgsl)
// at query points, to compare with LightSampler::pick and ::pmf. Per
// query (point, u): [light (NO_LIGHT: none), its pmf as bits,
// light_pmf_at of it as bits, 0].

@group(3) @binding(0) var<storage, read> pick_queries: array<vec4<f32>>;
@group(3) @binding(1) var<storage, read_write> pick_answers: array<vec4<u32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= arrayLength(&pick_queries)) {
        return;
    }
    let q = pick_queries[i];
    let l = pick_light(q.w, false, q.xyz);
    var pmf_at = 0.0;
    if (l.index != NO_LIGHT) {
        pmf_at = light_pmf_at(l.index, false, q.xyz);
    }
    pick_answers[i] = vec4<u32>(l.index, bitcast<u32>(l.pmf), bitcast<u32>(pmf_at), 0u);
}
