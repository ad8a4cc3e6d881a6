// fogbank_estimators::track_length: 1 if delta tracking escapes, else 0.
fn track_length(m: MediumGpu, r: Ray, t0: f32, t1: f32,
                rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    if (delta_tracking_sample(m, r, t0, t1, rng, lookups) == NO_HIT) {
        return 1.0;
    }
    return 0.0;
}
