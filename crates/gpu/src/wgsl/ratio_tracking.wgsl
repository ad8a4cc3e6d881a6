// fogbank_estimators::ratio_tracking (Novák et al. 2014), with Russian
// roulette below the weight `roulette` (0: off; roulette.rs).
fn ratio_tracking(m: MediumGpu, r: Ray, t0: f32, t1: f32, roulette: f32,
                  rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    return null_collision_walk(m, r, t0, t1, WALK_RATIO, roulette, rng, lookups);
}
