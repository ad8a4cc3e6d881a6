// The restir frame's parameters (RestirParams of restir/params.rs with the
// frame's regions; the Rust struct is `RestirUniform` in src/restir/uniform.rs).

// surfaces.wgsl's flag word: INTEGRATOR_SURFACES in a scene with shapes.
override INTEGRATOR_FLAGS: u32 = 0u;

// Combination MIS: MIS_TALBOT, MIS_STOCHASTIC, MIS_UNIFORM, MIS_PAIRWISE
// come from ReuseMis::ALL (contract.rs).
// What a path evaluation attenuates segments with.
const MODE_TARGET: u32 = 0u;   // T̃ marched on the reuse mip: p̂ (§4.3)
const MODE_F: u32 = 1u;        // the shading estimator ESTIMATOR: F (§5.1)

struct RestirUniform {
    // Sequences in this dispatch (gid.z) and the first one's index.
    batch: u32,
    first_sequence: u32,
    // Frame within the sequence; 1 when this frame's shading is accumulated.
    frame_index: u32,
    accumulate: u32,
    // Regions of `reservoirs` (each batch·pixels long) this frame uses.
    region_cand: u32,
    region_temporal: u32,
    region_spatial_in: u32,
    region_spatial_out: u32,
    region_prev: u32,
    region_final: u32,
    // 1 when the temporal pass runs this frame (a previous frame exists).
    temporal: u32,
    max_depth: u32,
    candidates: u32,
    mis: u32,
    neighbours: u32,
    radius: f32,
    temporal_cap: f32,
    // Media records: candidate tracking (primary, indirect), NEE T̃, reuse T̃,
    // velocity resampling (mip 1).
    primary_record: u32,
    indirect_record: u32,
    nee_record: u32,
    reuse_record: u32,
    mip1_record: u32,
    nee_transmittance: u32,
    reuse_step: f32,
    rr_depth: u32,
    vertex_reuse: u32,
    reprojection: u32,
    velocity_resampling: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    pad3: u32,
    // The current frame's medium velocity (VelocityGpu of src/restir/uniform.rs)
    // and the seconds since the previous frame.
    velocity_kind: u32,
    velocity_record: u32,
    frame_dt: f32,
    pad4: u32,
    velocity: array<vec4<f32>, 6>,
    // Points 0..32 of the R2 sequence (two per vec4), as neighbours.rs.
    r2: array<vec4<f32>, 16>,
}

@group(3) @binding(0) var<uniform> rp: RestirUniform;

// SampleKey of a pass (frame.rs): dimension 2 + 4·frame + pass.
fn pass_rng(pixel: u32, sequence: u32, pass_id: u32) -> Pcg32 {
    return sample_rng(frame.seed, pixel, sequence, 2u + 4u * rp.frame_index + pass_id);
}

// Camera::ray through the pixel centre (restir ignores pixel jitter).
fn centre_ray(x: u32, y: u32) -> Ray {
    let sx = (2.0 * (f32(x) + 0.5) / f32(frame.width) - 1.0) * frame.tan_half.x;
    let sy = (1.0 - 2.0 * (f32(y) + 0.5) / f32(frame.height)) * frame.tan_half.y;
    return camera_ray(sx, sy);
}

// Slot of `pixel` of sequence `s` (within the batch) in `region`.
fn slot(region: u32, s: u32, pixel: u32) -> u32 {
    let pixels = frame.width * frame.height;
    return (region * rp.batch + s) * pixels + pixel;
}
