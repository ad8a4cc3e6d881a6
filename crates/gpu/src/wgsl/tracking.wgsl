// render::integrators::shared::tracking: how one ray finds its next
// collision and how a shadow segment is attenuated — fogbank's unbiased
// samplers and estimators, Hansen 2025's fixed-step ray marching, or pins —
// chosen per ray by the integrator (PinParams::flight / shadow: PinMS mixes
// them by depth). The pin grids are gathered by pin_gather_kernel.wgsl.

// The integrator's per-render choices as pipeline constants
// (kernel_setup::specialisation): the driver then compiles the paths a
// render does not take — pins, marching, the other samplers — out of the
// kernel, where they would otherwise count in every invocation's registers.
// On an H200 the Fig. 1 frame (`direct`, 1080p, 32 spp) took 2.7-5.5x
// longer while they were uniforms (docs/results/gpu.md).
// The distance sampler: SAMPLER_* (delta, decomposition, regular tracking).
override SAMPLER: u32 = 0u;
// Hansen 2025: which rays read pins (PIN_MODE_*).
override PIN_MODE: u32 = 0u;
// INTEGRATOR_* bits: LIGHT_ONLY = volpath's restir_baseline preset;
// RAY_MARCHING = rays without pins march (Hansen 2025's baseline);
// UNQUANTISED = pins traced along each query ray (Fig. 4.5).
override INTEGRATOR_FLAGS: u32 = 0u;

@group(3) @binding(0) var<storage, read> pin_grids: array<PinGridGpu>;
@group(3) @binding(1) var<storage, read> pins: array<vec2<u32>>;

// Kinds of Flight and Shadow (GPU-internal; the CPU has the enum).
const TRACK_UNBIASED: u32 = 0u;
const TRACK_MARCHING: u32 = 1u;
const TRACK_PINS: u32 = 2u;

// PinParams::pick: pins if this ray uses them, else the tracking of rays
// without pins.
fn track_kind(use_pins: bool) -> u32 {
    if (use_pins && PIN_MODE != PIN_MODE_OFF) {
        return TRACK_PINS;
    }
    if ((INTEGRATOR_FLAGS & INTEGRATOR_RAY_MARCHING) != 0u) {
        return TRACK_MARCHING;
    }
    return TRACK_UNBIASED;
}

// PinParams::flight: the ray leaving vertex `depth` (0: the view ray).
fn flight_kind(depth: u32) -> u32 {
    let mode = PIN_MODE;
    return track_kind(mode == PIN_MODE_ALL
        || ((mode == PIN_MODE_SECONDARY || mode == PIN_MODE_MS) && depth >= 1u));
}

// PinParams::shadow: NEE at scattering vertex `vertex` (0: the first).
fn shadow_kind(vertex: u32) -> u32 {
    let mode = PIN_MODE;
    return track_kind(mode == PIN_MODE_ALL || mode == PIN_MODE_SECONDARY
        || (mode == PIN_MODE_MS && vertex >= 1u));
}

// The index-space ray in the unit cube, parameter unchanged.
fn unit_cube_ray(m: MediumGpu, r: Ray) -> Ray {
    let inv = 1.0 / vec3<f32>(m.dims);
    return Ray(r.o * inv, r.d * inv);
}

// tracking::parameter_step: `step` box edges in the ray parameter.
fn march_parameter_step(m: MediumGpu, r: Ray) -> f32 {
    return frame.march_step / max(length(unit_cube_ray(m, r).d), 1e-30);
}

struct PinQuery {
    pin: Pin,
    chord: Chord,
}

// PinSet::query: the pin a query on the unit-cube ray `local` from `t0`
// reads — from the grid at the jittered start, or traced along the ray
// when unquantised — and the chord it reads it along (invalid: no pin).
fn pin_query(mi: u32, m: MediumGpu, local: Ray, t0: f32,
             rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> PinQuery {
    let g = pin_grids[mi];
    var q = PinQuery(Pin(0u, 1.0), Chord(0.0, 0.0, 0u, false, false));
    if (g.present == 0u) {
        return q;
    }
    let p = ray_at(local, t0);
    if ((INTEGRATOR_FLAGS & INTEGRATOR_UNQUANTISED) != 0u) {
        q.pin = pin_trace(m, p, local.d, g.step, rng);
        *lookups += 32u;
        q.chord = chord_new(local, t0);
        return q;
    }
    let j = pin_jitter(g, p, local.d, rng);
    let rec = pins[g.offset + pin_cell(g, j.p, j.d)];
    q.pin = Pin(rec.x, bitcast<f32>(rec.y));
    *lookups += 1u;
    // The author's code reads the jittered ray's chord (same speed).
    q.chord = chord_new(Ray(j.p, j.d * length(local.d)), 0.0);
    return q;
}

// tracking::free_flight in medium `mi` on [t0, t1] of the index ray `r`.
fn tracked_flight(kind: u32, mi: u32, m: MediumGpu, r: Ray, t0: f32, t1: f32,
                  rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    if (kind == TRACK_MARCHING) {
        return march_sample(m, r, t0, t1, march_parameter_step(m, r), rng, lookups);
    }
    if (kind == TRACK_PINS) {
        let q = pin_query(mi, m, unit_cube_ray(m, r), t0, rng, lookups);
        if (!q.chord.valid) {
            return NO_HIT;
        }
        let d = pin_distance(q.pin, q.chord, t1 - t0, frame.pin_mask_iterations, rng);
        if (d < 0.0 || t0 + d > t1) {
            return NO_HIT;
        }
        return t0 + d;
    }
    return unbiased_flight(m, r, t0, t1, rng, lookups);
}

// tracking::transmittance in medium `mi` on [t0, t1] of the index ray `r`.
fn tracked_transmittance(kind: u32, mi: u32, m: MediumGpu, r: Ray, t0: f32, t1: f32,
                         rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    if (kind == TRACK_MARCHING) {
        return march_transmittance(m, r, t0, t1, march_parameter_step(m, r), rng, lookups);
    }
    if (kind == TRACK_PINS) {
        let q = pin_query(mi, m, unit_cube_ray(m, r), t0, rng, lookups);
        if (!q.chord.valid) {
            return 1.0;
        }
        return pin_transmittance(q.pin, q.chord, t1 - t0);
    }
    return estimate(m, r, t0, t1, rng, lookups);
}
