// The per-frame uniform, the device-side accumulation buffers, primary
// rays and the transmittance-estimator switch, shared by every kernel.

// EST_*, FLAG_* and DIM_* come from the generated prelude (contract.rs).

override ESTIMATOR: u32 = 2u;

struct Frame {
    // w: the near clip plane's distance along the view axis.
    cam_origin: vec4<f32>,
    // w: the far clip plane's (infinity without one).
    cam_forward: vec4<f32>,
    cam_right: vec4<f32>,
    cam_up: vec4<f32>,
    background: vec4<f32>,
    tan_half: vec2<f32>,
    width: u32,
    height: u32,
    seed: u32,
    first_sample: u32,
    sample_count: u32,
    media_count: u32,
    pixel_jitter: u32,
    // Estimator options: sample count N, fixed step (0: fixed count), flags.
    est_samples: u32,
    est_step: f32,
    est_flags: u32,
    // Scattering integrators: path length, first Russian-roulette bounce
    // and point_mis's N for the MIS weights. (The distance sampler, the
    // point_mis strategy, the pin mode and the integrator flags are
    // pipeline constants: tracking.wgsl, point_mis_kernel.wgsl.)
    max_depth: u32,
    rr_depth: u32,
    mis_samples: u32,
    // Hansen 2025: the ray-marching step in box edges, k of the majorant masks.
    march_step: f32,
    pin_mask_iterations: u32,
    // First image row of this dispatch: kernels with per-invocation scratch
    // (visopt's NEE lists) render in bands of rows, one scratch slot per
    // pixel of the band.
    tile_y: u32,
    // Chunks of SAMPLES_PER_CHUNK samples run side by side (grid z), and
    // the pixels of this dispatch's band.
    chunks: u32,
    band_pixels: u32,
    // Ratio and residual ratio tracking's roulette threshold (0: off).
    est_roulette: f32,
    pad3: u32,
    pad4: u32,
    pad5: u32,
}

@group(1) @binding(0) var<uniform> frame: Frame;
// Per pixel: the mean radiance (rgb) and the finite sample count (w); the
// sum of squared deviations from the mean, M2 (rgb), and the dropped
// non-finite samples (w). Running moments rather than Σx and Σx²: in f32,
// Σx² − (Σx)²/n loses every digit of a nearly constant pixel's variance
// after a few thousand samples (a deterministic estimator showed
// std 3e-4 where the CPU has 0), while M2 of a constant stays exactly 0.
// The two vec4 of pixel p are accum_moments[2p] and [2p + 1] (one binding:
// the scatter kernel is at the 16 storage buffers a stage may have).
@group(1) @binding(1) var<storage, read_write> accum_moments: array<vec4<f32>>;
@group(1) @binding(2) var<storage, read_write> accum_lookups: array<u32>;
// Per chunk and pixel of a band: (mean, n), (M2, non-finite), (lookups) —
// written by the chunks of a dispatch side by side, then merged into the
// pixel's moments in chunk order (accumulate.wgsl), so the result is the
// same as one chunk per dispatch.
@group(1) @binding(3) var<storage, read_write> accum_chunks: array<vec4<f32>>;

// One invocation's samples of a pixel: count, mean and M2 (Welford).
struct Moments {
    n: f32,
    mean: vec3<f32>,
    m2: vec3<f32>,
}

fn moments_empty() -> Moments {
    return Moments(0.0, vec3<f32>(0.0), vec3<f32>(0.0));
}

fn moments_add(m: ptr<function, Moments>, v: vec3<f32>) {
    (*m).n += 1.0;
    let d = v - (*m).mean;
    (*m).mean += d / (*m).n;
    (*m).m2 += d * (v - (*m).mean);
}

// Merges `b` into the pixel's accumulated moments (Chan, Golub and LeVeque's
// pairwise update) and counts `nonfinite` dropped samples.
fn accumulate_moments(pixel: u32, b: Moments, nonfinite: f32) {
    let a_mean = accum_moments[2u * pixel];
    let a_m2 = accum_moments[2u * pixel + 1u];
    let n = a_mean.w + b.n;
    var mean = a_mean.xyz;
    var m2 = a_m2.xyz;
    if (b.n > 0.0) {
        let d = b.mean - mean;
        mean += d * (b.n / n);
        m2 += b.m2 + d * d * (a_mean.w * b.n / n);
    }
    accum_moments[2u * pixel] = vec4<f32>(mean, n);
    accum_moments[2u * pixel + 1u] = vec4<f32>(m2, a_m2.w + nonfinite);
}

// Set by a kernel that meets an id it has no branch for: the sample is
// then dropped and counted with the non-finite ones instead of running
// another method (reset per sample by accumulate.wgsl).
var<private> sample_invalid: bool;

fn invalid_id() -> f32 {
    sample_invalid = true;
    return 0.0;
}

// By bit pattern: WGSL lets compilers assume floats are finite, so x != x
// may be folded away.
fn is_finite3(v: vec3<f32>) -> bool {
    let e = bitcast<vec3<u32>>(v) & vec3<u32>(0x7f800000u);
    return all(e != vec3<u32>(0x7f800000u));
}

fn is_finite1(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

// integrators::primary_ray + Camera::ray
fn primary_ray(x: u32, y: u32, pixel: u32, sample: u32) -> Ray {
    var j = vec2<f32>(0.5, 0.5);
    if (frame.pixel_jitter != 0u) {
        var cam = sample_rng(frame.seed, pixel, sample, DIM_CAMERA);
        let jx = pcg32_next_f32(&cam);
        let jy = pcg32_next_f32(&cam);
        j = vec2<f32>(jx, jy);
    }
    let fx = f32(x) + j.x;
    let fy = f32(y) + j.y;
    let sx = (2.0 * fx / f32(frame.width) - 1.0) * frame.tan_half.x;
    let sy = (1.0 - 2.0 * fy / f32(frame.height)) * frame.tan_half.y;
    return camera_ray(sx, sy);
}

// Camera::ray at tangent-plane position (sx, sy): starts on the near plane.
fn camera_ray(sx: f32, sy: f32) -> Ray {
    var r: Ray;
    r.d = normalize(frame.cam_forward.xyz + sx * frame.cam_right.xyz + sy * frame.cam_up.xyz);
    r.o = frame.cam_origin.xyz;
    let near = frame.cam_origin.w;
    if (near > 0.0) {
        r.o += r.d * (near / dot(r.d, frame.cam_forward.xyz));
    }
    return r;
}

// Camera::ray_end: where a camera ray's first segment meets the far plane.
fn camera_ray_end(r: Ray) -> f32 {
    let far = frame.cam_forward.w;
    if (far >= F32_INF) {
        return F32_INF;
    }
    return (far - frame.cam_origin.w) / dot(r.d, frame.cam_forward.xyz);
}

// The transmittance of pixel sample (x, y, sample)'s camera ray through all
// media (the CPU's transmittance::along_ray): overlapping media multiply.
fn camera_transmittance(pixel: u32, x: u32, y: u32, sample: u32, lookups: ptr<function, u32>) -> f32 {
    let world = primary_ray(x, y, pixel, sample);
    var rng = sample_rng(frame.seed, pixel, sample, DIM_ESTIMATOR);
    var tr = 1.0;
    for (var i = 0u; i < frame.media_count; i++) {
        let m = media[i];
        var r: Ray;
        let range = to_index_from_camera(m, world, camera_ray_end(world), &r);
        if (range.z != 0.0) {
            tr *= estimate(m, r, range.x, range.y, &rng, lookups);
        }
    }
    return tr;
}

// The scene's transmittance estimator on [t0, t1]. Each call counts its
// lookups from 0, as each CPU estimator call does: the stochastic filter's
// jitter hashes the running count (medium.wgsl), so a count carried over
// from earlier calls, media or samples gave the GPU other jitters than the
// CPU for the same random streams.
fn estimate(m: MediumGpu, r: Ray, t0: f32, t1: f32,
            rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    var count = 0u;
    let t = estimate_with(m, r, t0, t1, rng, &count);
    *lookups += count;
    return t;
}

// estimators::scaled::transmittance_scaled: each channel's transmittance
// through a chromatic medium of one density (channel c: extinction k_c
// times m's) from one walk, for the estimators whose walk does not depend
// on the scale; w = 0 when this one cannot share it (each channel then
// walks its own medium).
fn estimate_rgb(m: MediumGpu, r: Ray, t0: f32, t1: f32, k: vec3<f32>,
                rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> vec4<f32> {
    switch ESTIMATOR {
        case EST_REGULAR_TRACKING: {
            return vec4<f32>(exp(-k * regular_tracking_tau(m, r, t0, t1, lookups)), 1.0);
        }
        case EST_ANALYTIC_TRILINEAR: {
            return vec4<f32>(exp(-k * analytic_trilinear_tau(m, r, t0, t1, lookups)), 1.0);
        }
        case EST_RAY_MARCHING: {
            let clip = (frame.est_flags & FLAG_CLIP) != 0u;
            return vec4<f32>(exp(-k * ray_marching_tau(m, r, t0, t1, frame.est_samples, clip, rng, lookups)), 1.0);
        }
        case EST_JACKKNIFE: {
            // A fixed step's count scales with σ_t: the channels' walks differ.
            if (frame.est_step != 0.0) {
                return vec4<f32>(1.0, 1.0, 1.0, 0.0);
            }
            let uniform = (frame.est_flags & FLAG_UNIFORM_JITTER) != 0u;
            var x: array<f32, 9>;
            optical_depths(m, r, t0, t1, frame.est_samples, 0.0, false, uniform, 2u, rng, lookups, &x);
            return vec4<f32>(jackknife_of(k.x * x[0], k.x * x[1]), jackknife_of(k.y * x[0], k.y * x[1]),
                             jackknife_of(k.z * x[0], k.z * x[1]), 1.0);
        }
        case EST_RATIO_TRACKING: {
            return vec4<f32>(null_collision_walk_rgb(m, r, t0, t1, WALK_RATIO, k, frame.est_roulette, rng, lookups), 1.0);
        }
        case EST_RESIDUAL_RATIO_TRACKING: {
            return vec4<f32>(null_collision_walk_rgb(m, r, t0, t1, WALK_RESIDUAL, k, frame.est_roulette, rng, lookups), 1.0);
        }
        default: {
            return vec4<f32>(1.0, 1.0, 1.0, 0.0);
        }
    }
}

fn estimate_with(m: MediumGpu, r: Ray, t0: f32, t1: f32,
                 rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    let uniform = (frame.est_flags & FLAG_UNIFORM_JITTER) != 0u;
    switch ESTIMATOR {
        case EST_REGULAR_TRACKING: {
            return regular_tracking(m, r, t0, t1, lookups);
        }
        case EST_TRACK_LENGTH: {
            return track_length(m, r, t0, t1, rng, lookups);
        }
        case EST_RATIO_TRACKING: {
            return ratio_tracking(m, r, t0, t1, frame.est_roulette, rng, lookups);
        }
        case EST_ANALYTIC_TRILINEAR: {
            return analytic_trilinear(m, r, t0, t1, lookups);
        }
        case EST_RESIDUAL_RATIO_TRACKING: {
            return residual_ratio_tracking(m, r, t0, t1, frame.est_roulette, rng, lookups);
        }
        case EST_RAY_MARCHING: {
            return ray_marching(m, r, t0, t1, frame.est_samples, (frame.est_flags & FLAG_CLIP) != 0u, rng, lookups);
        }
        case EST_JACKKNIFE: {
            return jackknife(m, r, t0, t1, frame.est_samples, frame.est_step, false, uniform, rng, lookups);
        }
        case EST_JACKKNIFE_NAIVE: {
            return jackknife_naive(m, r, t0, t1, frame.est_samples, uniform, rng, lookups);
        }
        case EST_BIASED_RAY_MARCHING: {
            return biased_ray_marching(m, r, t0, t1, (frame.est_flags & FLAG_DOUBLED) != 0u, rng, lookups);
        }
        case EST_UNBIASED_RAY_MARCHING: {
            return unbiased_ray_marching(m, r, t0, t1, frame.est_samples, rng, lookups);
        }
        case EST_JACKKNIFE_MEAN_IMPORTANCE: {
            return jackknife(m, r, t0, t1, frame.est_samples, 0.0, true, uniform, rng, lookups);
        }
        default: {
            return invalid_id();
        }
    }
}

