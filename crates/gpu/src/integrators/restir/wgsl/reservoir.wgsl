// fogbank_render::integrators::restir::{path, reservoir} on the GPU: a
// volumetric path as a reservoir stores it (Lin et al. 2021 §3.2, §4.2), the
// reservoir of weighted reservoir sampling (§2.5, Eq. 5–7) and its stored
// form. Conventions as the CPU's: w = p̂/p, W = w_sum / (M p̂(y)).

const MAX_K: u32 = 8u;
// PathEnd, in the CPU enum's order.
const END_BACKGROUND: u32 = 0u;
const END_LIGHT: u32 = 1u;
const END_EMISSION: u32 = 2u;
// PathSample::fixed_from of a path whose vertices all follow its directions.
const NONE_FIXED: u32 = 255u;

struct Path {
    end: u32,
    k: u32,
    light: u32,
    fixed_from: u32,
    // z[i]: distance from x_i to x_{i+1}; dir[i] = ω_{i+1}; x[i] = x_{i+1}.
    z: array<f32, 8>,
    dir: array<vec3<f32>, 8>,
    x: array<vec3<f32>, 8>,
    light_dir: vec3<f32>,
    // Bit i: x_{i+1} lies on a surface (PathSample::surface).
    surface: u32,
    // A light end on an emitting shape: its point on the light.
    light_point: vec3<f32>,
}

fn background_path() -> Path {
    var y: Path;
    y.end = END_BACKGROUND;
    y.k = 0u;
    y.light = 0u;
    y.fixed_from = NONE_FIXED;
    y.surface = 0u;
    return y;
}

// PathSample::on_surface: vertex index i (x_{i+1}) lies on a surface.
fn on_surface(y: ptr<function, Path>, i: u32) -> bool {
    return ((*y).surface & (1u << i)) != 0u;
}

// PathSample::is_fixed: vertex index i (x_{i+1}) stays where it was found.
fn is_fixed(y: ptr<function, Path>, i: u32) -> bool {
    return i >= 1u && i >= (*y).fixed_from;
}

struct Reservoir {
    y: Path,
    has_y: bool,
    w_sum: f32,
    m: f32,
    p_hat: f32,
}

fn empty_reservoir() -> Reservoir {
    var r: Reservoir;
    r.y = background_path();
    r.has_y = false;
    r.w_sum = 0.0;
    r.m = 0.0;
    r.p_hat = 0.0;
    return r;
}

// Reservoir::stream (Eq. 7): keeps y with probability w / w_sum; a weight
// that is not finite and positive is never kept.
fn res_stream(r: ptr<function, Reservoir>, y: ptr<function, Path>, w: f32, p_hat: f32, u: f32) -> bool {
    if (!(w > 0.0) || !is_finite1(w)) {
        return false;
    }
    (*r).w_sum += w;
    if (u * (*r).w_sum < w) {
        (*r).y = *y;
        (*r).has_y = true;
        (*r).p_hat = p_hat;
        return true;
    }
    return false;
}

// Reservoir::contribution_weight (Eq. 6, 21); 0 for an empty reservoir.
fn contribution_weight(has_y: bool, w_sum: f32, m: f32, p_hat: f32) -> f32 {
    if (has_y && p_hat > 0.0 && m > 0.0) {
        let w = w_sum / (m * p_hat);
        if (is_finite1(w)) {
            return w;
        }
    }
    return 0.0;
}

// Reservoir::retarget (§4.3): moves the reservoir to a target whose value
// at y is p_hat, keeping W.
fn res_retarget(r: ptr<function, Reservoir>, p_hat: f32) {
    if ((*r).p_hat > 0.0) {
        (*r).w_sum *= p_hat / (*r).p_hat;
    } else {
        (*r).w_sum = 0.0;
    }
    (*r).p_hat = p_hat;
}

// The stored form, one per pixel and sequence in each region of
// `reservoirs`. Besides the reservoir it carries what one pass leaves the
// next within a frame (the temporal pass's reprojection and stream, the
// lookups so far, the shaded radiance).
struct Stored {
    // end | k << 4 | fixed_from << 8 | has_y << 16 | surface bits << 17;
    // light; the previous
    // frame's pixel picked by reprojection; lookups so far this frame.
    head: vec4<u32>,
    // w_sum, M, p̂(y), and p̂ of the previous pixel's target at y (temporal).
    w: vec4<f32>,
    // Temporal reprojection: what the pixel saw, an index-space medium
    // point (w = 1), a world direction (w = 0) or nothing (w = −1).
    seen: vec4<f32>,
    // Temporal: the two pixel-pick numbers; final shading: valid (1) or not.
    aux: vec4<f32>,
    // Temporal: the pass's PCG32 (state, inc) after reprojection's draws.
    rng: vec4<u32>,
    // Final shading: the radiance F(y)·W.
    shaded: vec4<f32>,
    light_dir: vec4<f32>,
    // The point on an emitting shape.
    light_point: vec4<f32>,
    z: array<vec4<f32>, 2>,
    // Eight xyz triples packed in 24 floats each.
    dir: array<vec4<f32>, 6>,
    x: array<vec4<f32>, 6>,
}

@group(3) @binding(1) var<storage, read_write> reservoirs: array<Stored>;

fn get3(a: ptr<function, array<vec4<f32>, 6>>, i: u32) -> vec3<f32> {
    var v: vec3<f32>;
    for (var c = 0u; c < 3u; c++) {
        let f = 3u * i + c;
        v[c] = (*a)[f / 4u][f % 4u];
    }
    return v;
}

fn set3(a: ptr<function, array<vec4<f32>, 6>>, i: u32, v: vec3<f32>) {
    for (var c = 0u; c < 3u; c++) {
        let f = 3u * i + c;
        (*a)[f / 4u][f % 4u] = v[c];
    }
}

fn load_reservoir(index: u32) -> Reservoir {
    let s = reservoirs[index];
    var r: Reservoir;
    r.y.end = s.head.x & 0xfu;
    r.y.k = (s.head.x >> 4u) & 0xfu;
    r.y.fixed_from = (s.head.x >> 8u) & 0xffu;
    r.has_y = ((s.head.x >> 16u) & 1u) != 0u;
    r.y.surface = (s.head.x >> 17u) & 0xffu;
    r.y.light = s.head.y;
    r.w_sum = s.w.x;
    r.m = s.w.y;
    r.p_hat = s.w.z;
    r.y.light_dir = s.light_dir.xyz;
    r.y.light_point = s.light_point.xyz;
    var dir = s.dir;
    var x = s.x;
    for (var i = 0u; i < MAX_K; i++) {
        r.y.z[i] = s.z[i / 4u][i % 4u];
        r.y.dir[i] = get3(&dir, i);
        r.y.x[i] = get3(&x, i);
    }
    return r;
}

// Writes the reservoir part of slot `index` (its other fields are kept).
fn store_reservoir(index: u32, r: ptr<function, Reservoir>) {
    let y = (*r).y;
    reservoirs[index].head.x = (y.end & 0xfu) | ((y.k & 0xfu) << 4u)
        | ((y.fixed_from & 0xffu) << 8u) | (select(0u, 1u, (*r).has_y) << 16u)
        | ((y.surface & 0xffu) << 17u);
    reservoirs[index].head.y = y.light;
    reservoirs[index].w = vec4<f32>((*r).w_sum, (*r).m, (*r).p_hat, 0.0);
    reservoirs[index].light_dir = vec4<f32>(y.light_dir, 0.0);
    reservoirs[index].light_point = vec4<f32>(y.light_point, 0.0);
    var z: array<vec4<f32>, 2>;
    var dir: array<vec4<f32>, 6>;
    var x: array<vec4<f32>, 6>;
    for (var i = 0u; i < MAX_K; i++) {
        z[i / 4u][i % 4u] = y.z[i];
        set3(&dir, i, y.dir[i]);
        set3(&x, i, y.x[i]);
    }
    reservoirs[index].z = z;
    reservoirs[index].dir = dir;
    reservoirs[index].x = x;
}
