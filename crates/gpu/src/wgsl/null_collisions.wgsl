// fogbank_estimators::null_collisions::walk for the two estimators that
// share it, over super-voxel majorants: track-length (stop at the first
// real collision) and ratio tracking (multiply by 1 − μ/μ̄ at each event).

const WALK_TRACK_LENGTH: u32 = 0u;
const WALK_RATIO: u32 = 1u;

fn null_collision_walk(m: MediumGpu, r: Ray, t0: f32, t1: f32, mode: u32,
                       rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    var tr = 1.0;
    var dda = dda_new(r, m.sv_size, m.sv_dims, t0, t1);
    var s: DdaStep;
    while (dda_next(&dda, &s)) {
        let sigma_bar = supervoxel(m, s.cell).y;
        if (sigma_bar <= 0.0) {
            continue;
        }
        var t = s.t0;
        loop {
            t += -log(1.0 - pcg32_next_f32(rng)) / sigma_bar;
            if (t >= s.t1) {
                break;
            }
            let mu = sigma_t(m, ray_at(r, t), rng, lookups);
            if (mode == WALK_TRACK_LENGTH) {
                if (!(pcg32_next_f32(rng) * sigma_bar >= mu)) {
                    return 0.0;
                }
            } else {
                tr *= 1.0 - mu / sigma_bar;
                if (tr == 0.0) {
                    return 0.0;
                }
            }
        }
    }
    return tr;
}
