// Gather population of one medium's pin grid (Hansen 2025 §3.7, PinGrid::gather):
// every 5D cell traces its own pin through a point and direction uniform in
// the cell, from its own stream Pcg32(seed, cell), so the grid is the CPU's
// up to floating-point rounding of the marched transmittances.

struct GatherParams {
    seed: vec2<u32>,
    medium: u32,
    count: u32,
}

@group(1) @binding(0) var<uniform> gather_params: GatherParams;
@group(1) @binding(1) var<storage, read> gather_grids: array<PinGridGpu>;
@group(1) @binding(2) var<storage, read_write> gathered: array<vec2<u32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>,
        @builtin(num_workgroups) groups: vec3<u32>) {
    let cell = gid.x + gid.y * groups.x * 64u;
    if (cell >= gather_params.count) {
        return;
    }
    let g = gather_grids[gather_params.medium];
    var rng = pcg32_new(gather_params.seed, vec2<u32>(cell, 0u));
    let line = pin_sample_in_cell(g, cell, &rng);
    let pin = pin_trace(media[gather_params.medium], line.p, line.d, g.step, &rng);
    gathered[g.offset + cell] = vec2<u32>(pin.mask, bitcast<u32>(pin.t_min));
}
