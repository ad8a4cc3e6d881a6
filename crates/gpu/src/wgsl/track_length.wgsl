// fogbank_estimators::track_length: 1 if delta tracking escapes, else 0.
fn track_length(m: MediumGpu, r: Ray, t0: f32, t1: f32,
                rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    return null_collision_walk(m, r, t0, t1, WALK_TRACK_LENGTH, rng, lookups);
}
