// fogbank_estimators::pins::grid (Hansen 2025 §3.6, §3.7, §3.10): the 5D grid's
// cell of a point and direction, a point and direction uniform in a cell
// (gather), and the lookup jitter, as PinGridSpec does them.

const PIN_TAU: f32 = 6.2831853;
const PIN_HALF_PI: f32 = 1.5707964;

// One medium's grid (a PinGridSpec and where its pins start).
struct PinGridGpu {
    offset: u32,
    positions: u32,
    phi: u32,
    theta: u32,
    jitter_position: f32,
    jitter_direction: f32,
    step: f32,
    present: u32,
}

fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    if (l > 0.0 && l < F32_INF) {
        return v / l;
    }
    return vec3<f32>(0.0);
}

// PinGridSpec::direction_bin: flipped to +z, binned in φ and θ.
fn pin_direction_bin(g: PinGridGpu, dir: vec3<f32>) -> u32 {
    let d = normalize_or_zero(pin_canonical(dir));
    let theta = acos(clamp(d.z, -1.0, 1.0));
    var phi = atan2(d.y, d.x);
    if (phi < 0.0) {
        phi += PIN_TAU;
    }
    let ip = min(u32(phi / PIN_TAU * f32(g.phi)), g.phi - 1u);
    let it = min(u32(theta / PIN_HALF_PI * f32(g.theta)), g.theta - 1u);
    return it * g.phi + ip;
}

// PinGridSpec::cell: position first, then direction.
fn pin_cell(g: PinGridGpu, p: vec3<f32>, d: vec3<f32>) -> u32 {
    let n = g.positions;
    let c = min(vec3<u32>(clamp(p, vec3<f32>(0.0), vec3<f32>(1.0)) * f32(n)), vec3<u32>(n - 1u));
    let pos = (c.z * n + c.y) * n + c.x;
    return pos * (g.phi * g.theta) + pin_direction_bin(g, d);
}

struct PinLine {
    p: vec3<f32>,
    d: vec3<f32>,
}

fn pin_next_vec3(rng: ptr<function, Pcg32>) -> vec3<f32> {
    let x = pcg32_next_f32(rng);
    let y = pcg32_next_f32(rng);
    let z = pcg32_next_f32(rng);
    return vec3<f32>(x, y, z);
}

// PinGridSpec::sample_in_cell (gather, §3.7): uniform in the cell's
// position and (φ, θ) ranges.
fn pin_sample_in_cell(g: PinGridGpu, index: u32, rng: ptr<function, Pcg32>) -> PinLine {
    let dirs = g.phi * g.theta;
    let pos = index / dirs;
    let dir = index % dirs;
    let n = g.positions;
    let c = vec3<f32>(f32(pos % n), f32((pos / n) % n), f32(pos / (n * n)));
    let p = (c + pin_next_vec3(rng)) / f32(n);
    let ip = dir % g.phi;
    let it = dir / g.phi;
    let phi = (f32(ip) + pcg32_next_f32(rng)) / f32(g.phi) * PIN_TAU;
    let theta = (f32(it) + pcg32_next_f32(rng)) / f32(g.theta) * PIN_HALF_PI;
    let d = vec3<f32>(sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta));
    return PinLine(p, d);
}

// PinGridSpec::jitter (§3.9, the author's apply_jitter): position by
// j_p(½ − U³)/P, direction by j_d(½ − U³)/θ-bins, renormalised.
fn pin_jitter(g: PinGridGpu, p: vec3<f32>, d: vec3<f32>, rng: ptr<function, Pcg32>) -> PinLine {
    if (g.jitter_position <= 0.0 && g.jitter_direction <= 0.0) {
        return PinLine(p, d);
    }
    let up = vec3<f32>(0.5) - pin_next_vec3(rng);
    let pj = clamp(p + g.jitter_position * up / f32(g.positions), vec3<f32>(0.0), vec3<f32>(1.0));
    let ud = vec3<f32>(0.5) - pin_next_vec3(rng);
    let dj = normalize_or_zero(d) + g.jitter_direction * ud / f32(g.theta);
    if (dot(dj, dj) > 0.0) {
        return PinLine(pj, normalize(dj));
    }
    return PinLine(pj, d);
}
