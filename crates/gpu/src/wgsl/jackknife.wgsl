// fogbank_estimators::jackknife: Peters 2025 Eq. 4 from two optical-depth
// estimates X0, X1: cos(|X0 − X1|/2) · exp(−(X0 + X1)/2); the naive
// ablation exp(−X) of one estimate with 2N samples.

fn jackknife(m: MediumGpu, r: Ray, t0: f32, t1: f32, samples: u32, step: f32,
             mean_importance: bool, uniform_jitter: bool,
             rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    var x: array<f32, 9>;
    optical_depths(m, r, t0, t1, samples, step, mean_importance, uniform_jitter, 2u, rng, lookups, &x);
    return jackknife_of(x[0], x[1]);
}

// jackknife::jackknife_transmittance: Peters 2025 Eq. 4.
fn jackknife_of(x0: f32, x1: f32) -> f32 {
    return cos(0.5 * abs(x0 - x1)) * exp(-0.5 * (x0 + x1));
}

fn jackknife_naive(m: MediumGpu, r: Ray, t0: f32, t1: f32, samples: u32, uniform_jitter: bool,
                   rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    var x: array<f32, 9>;
    optical_depths(m, r, t0, t1, 2u * max(samples, 1u), 0.0, false, uniform_jitter, 1u, rng, lookups, &x);
    return exp(-x[0]);
}
