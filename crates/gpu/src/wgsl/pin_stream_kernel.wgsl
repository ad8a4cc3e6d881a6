// The pin stream of one medium's grid before a pass (Hansen 2025 §3.4.4, §3.7;
// PinGrid::stream): stream pin i draws from Pcg32(seed, i) a uniform point,
// a direction U³ − ½ and an offset U·spacing, is traced like a gathered
// pin, and is written into the cells of points `spacing` apart along its
// chord from that offset. Pins run in parallel and a cell two pins cross
// keeps either (the thesis's tolerated write races; the CPU keeps the later
// pin), so the grid is the CPU's except in such cells.

struct StreamParams {
    seed: vec2<u32>,
    medium: u32,
    count: u32,
    spacing: f32,
    min_spacing: f32,
    _pad: vec2<u32>,
}

@group(1) @binding(0) var<uniform> stream_params: StreamParams;
@group(1) @binding(1) var<storage, read> stream_grids: array<PinGridGpu>;
@group(1) @binding(2) var<storage, read_write> streamed: array<vec2<u32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>,
        @builtin(num_workgroups) groups: vec3<u32>) {
    let i = gid.x + gid.y * groups.x * 64u;
    if (i >= stream_params.count) {
        return;
    }
    let g = stream_grids[stream_params.medium];
    var rng = pcg32_new(stream_params.seed, vec2<u32>(i, 0u));
    // StreamLine::draw.
    let p = pin_next_vec3(&rng);
    let d = pin_next_vec3(&rng) - vec3<f32>(0.5);
    let offset = pcg32_next_f32(&rng) * stream_params.spacing;
    // UnitCube::chord: ends ordered towards +z.
    let dc = pin_canonical(d);
    if (!(dot(dc, dc) > 0.0)) {
        return;
    }
    var line: Ray;
    line.o = clamp(p, vec3<f32>(0.0), vec3<f32>(1.0));
    line.d = dc;
    let hit = intersect_box(line, vec3<f32>(1.0), -F32_INF, F32_INF);
    if (hit.z == 0.0 || !(hit.y > hit.x)) {
        return;
    }
    let start = ray_at(line, hit.x);
    let end = ray_at(line, hit.y);
    let pin = pin_trace(media[stream_params.medium], p, d, g.step, &rng);
    let record = vec2<u32>(pin.mask, bitcast<u32>(pin.t_min));
    let len = length(end - start);
    let advance = max(stream_params.spacing, stream_params.min_spacing);
    var s = offset;
    while (s <= len) {
        let q = start + (end - start) * (s / len);
        streamed[g.offset + pin_cell(g, q, d)] = record;
        s += advance;
    }
}
