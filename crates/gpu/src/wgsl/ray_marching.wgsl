// fogbank_estimators::ray_marching: exp(−X) from N equidistant samples
// sharing one jitter, over the ray or (clip) its tight non-empty segment.

fn ray_marching(m: MediumGpu, r: Ray, t0: f32, t1: f32, samples: u32, clip: bool,
                rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    return exp(-ray_marching_tau(m, r, t0, t1, samples, clip, rng, lookups));
}

// ray_marching::optical_depth: the marched τ̂.
fn ray_marching_tau(m: MediumGpu, r: Ray, t0: f32, t1: f32, samples: u32, clip: bool,
                    rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    var a = t0;
    var b = t1;
    if (clip) {
        let p = od_prepare(m, r, t0, t1, true);
        if (p.total <= 0.0) {
            return 0.0;
        }
        a = p.t_min;
        b = p.t_max;
    }
    let n = max(samples, 1u);
    let dt = (b - a) / f32(n);
    let u = pcg32_next_f32(rng);
    var sum = 0.0;
    for (var i = 0u; i < n; i++) {
        sum += sigma_t_at(m, ray_at(r, a + (f32(i) + u) * dt), rng, lookups);
    }
    return sum * dt;
}
