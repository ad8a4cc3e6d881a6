// Diagnostics: the first `count` words of the PCG32 stream of each key
// (seed, pixel, sample, dimension), to compare with the CPU bit for bit.

struct Params {
    keys: u32,
    count: u32,
}

@group(0) @binding(0) var<storage, read> keys: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read_write> out: array<u32>;
@group(0) @binding(2) var<uniform> params: Params;

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.keys) {
        return;
    }
    let k = keys[gid.x];
    var rng = sample_rng(k.x, k.y, k.z, k.w);
    for (var i = 0u; i < params.count; i++) {
        out[gid.x * params.count + i] = pcg32_next_u32(&rng);
    }
}
