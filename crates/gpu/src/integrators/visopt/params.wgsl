// Lerzer and Dachsbacher 2025 on the device: the parameters of `visopt` and
// `ament` (visopt/params.rs, ament.rs), the importance rules and visopt's
// frozen camera lists, bind group 3 of both kernels (crates/gpu/src/visopt).

struct VisOptUniform {
    // Eq. 7–8.
    p: f32,
    q: f32,
    r: f32,
    lambda: f32,
    // 2 / the medium's longest world extent: world lengths → [−1, 1]³.
    unit: f32,
    // The gradient lobe's exponent.
    n: f32,
    // ament: Δx in [−1, 1]³ units.
    step: f32,
    // visopt: d of Alg. 1 (0: 2·L/N per ray).
    merge_distance: f32,
    // VISOPT_* bits.
    flags: u32,
    rule_count: u32,
    // First record + 1 of a pre-classified importance field (0: none).
    pre_field: u32,
    light_samples: u32,
    // SCATTERING_* id and path length.
    scattering: u32,
    max_depth: u32,
    // Importance values this close merge (0 post-, 1e-3 pre-interpolative).
    tolerance: f32,
    // Where the camera lists start in `visopt_data` (after the rules).
    lists_first: u32,
}

// world/importance.rs ImportanceRule; ranges are half-open [lo, hi).
struct ImportanceRuleGpu {
    value: f32,
    // RULE_* bits: the predicates the rule has.
    flags: u32,
    // First record of the mask's field.
    mask: u32,
    mask_threshold: f32,
    // σ_t [lo, hi), then the scalar [lo, hi) in the grid's stored units.
    ranges: vec4<f32>,
    // ‖∇σ_t‖ [lo, hi) (xy).
    gradient: vec4<f32>,
    box_lo: vec4<f32>,
    box_hi: vec4<f32>,
    // n·x ≥ c: (n, c).
    half_space: vec4<f32>,
}

@group(3) @binding(0) var<uniform> vo: VisOptUniform;
// One buffer (the kernels are at the 16 storage buffers WebGPU guarantees):
// the rules, 6 words of 4 each (ImportanceRuleGpu), then the camera lists —
// per pixel a header (offset of its first entry in this buffer, entry
// count, K(z), L as bits), then every list's entries (t, l, k, K)
// (CameraLists::pixels and pool).
@group(3) @binding(1) var<storage, read> visopt_data: array<vec4<f32>>;
// Per pixel of the dispatch's band of rows, room for one NEE ray's list
// (Lerzer and Dachsbacher 2025 §6.1's per-thread scratch; a private array would be indexed
// dynamically, which lavapipe compiles for minutes).
@group(3) @binding(2) var<storage, read_write> light_scratch: array<vec4<f32>>;

// The importance rule i.
fn rule_at(i: u32) -> ImportanceRuleGpu {
    let w = 6u * i;
    let head = bitcast<vec4<u32>>(visopt_data[w]);
    return ImportanceRuleGpu(bitcast<f32>(head.x), head.y, head.z, bitcast<f32>(head.w),
        visopt_data[w + 1u], visopt_data[w + 2u], visopt_data[w + 3u],
        visopt_data[w + 4u], visopt_data[w + 5u]);
}

fn vo_flag(bit: u32) -> bool {
    return (vo.flags & bit) != 0u;
}
