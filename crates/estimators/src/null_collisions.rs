//! The tentative (null-collision) process shared by the tracking
//! estimators: a Poisson process along the ray whose rate is constant within
//! each super-voxel (its majorant), restarted per super-voxel since the
//! exponential is memoryless. Each collision reads σ_t once.
//!
//! The collisions' positions depend only on the majorant and the random
//! stream, not on what is read there, so the walk draws several ahead and
//! reads them together in SIMD lanes. `collide` may draw random numbers too (Russian roulette): then
//! the walk rewinds the stream and the lookup count to just after that
//! collision and goes on from there one collision at a time, so the result
//! is bit for bit the sequential walk's.

use crate::lookup::{count_and_jitter, sample_exponential, sigma_t_at};
use fogbank_math::{Pcg32, Ray, RaySegment, Vec3};
use fogbank_volume::{Dda, SuperVoxel, VolumeAccess};

/// Tentative collisions drawn ahead and read in one lanes call.
const AHEAD: usize = 8;
/// Expected collisions in a super-voxel (σ̄ · length) below which the walk
/// reads them one at a time.
const MIN_AHEAD: f32 = 4.0;

/// What a tracking estimator makes of the tentative process.
/// `rate(cell, length)` gives a super-voxel's rate and a value handed to
/// its collisions (e.g. a control extinction); `collide(t, μ, rate, value,
/// rng)` handles one tentative collision at `t` and returns `false` to stop
/// the walk. `draws`: the random numbers `collide` draws at a collision
/// where the walk goes on (ratio tracking 0, delta tracking's real-or-null
/// choice 1); a collision that draws otherwise ends the round.
pub struct Tracking<R, C> {
    pub draws: u32,
    pub rate: R,
    pub collide: C,
}

/// Walks `[t0, t1]` with the tentative collisions of `tracking`. Returns
/// whether the walk reached `t1`.
#[inline(always)]
pub fn walk<V: VolumeAccess, R, C>(
    v: &V,
    seg: &RaySegment,
    rng: &mut Pcg32,
    lookups: &mut u32,
    tracking: Tracking<R, C>,
) -> bool
where
    R: FnMut(&SuperVoxel, f32) -> (f32, f32),
    C: FnMut(f32, f32, f32, f32, &mut Pcg32) -> bool,
{
    let (ray, t0, t1) = (&seg.ray, seg.t0, seg.t1);
    let Tracking {
        draws,
        mut rate,
        mut collide,
    } = tracking;
    let sv = v.supervoxels();
    // Reading ahead until a round finds `collide` drawing; one at a time
    // after that (a roulette that draws at every collision would discard
    // each round).
    let mut ahead = true;
    for s in Dda::new(ray, sv.size as f32, sv.dims, t0, t1) {
        let (sigma_maj, value) = rate(sv.get(s.cell), s.t1 - s.t0);
        if sigma_maj <= 0.0 {
            continue;
        }
        // Few collisions expected here: a round's set-up would cost more
        // than its lanes save.
        let mut one_by_one = !ahead || sigma_maj * (s.t1 - s.t0) < MIN_AHEAD;
        let mut t = s.t0;
        loop {
            if one_by_one {
                t += sample_exponential(rng, sigma_maj);
                if t >= s.t1 {
                    break;
                }
                let sigma_t = sigma_t_at(v, ray.at(t), rng, lookups);
                if !collide(t, sigma_t, sigma_maj, value, rng) {
                    return false;
                }
                continue;
            }
            let segment = (s.t1, sigma_maj, draws);
            match round(v, ray, &mut t, segment, rng, lookups, |t, sigma_t, rng| {
                collide(t, sigma_t, sigma_maj, value, rng)
            }) {
                Round::Stopped => return false,
                Round::Drew => (ahead, one_by_one) = (false, true),
                Round::Read => {}
                Round::Left => break,
            }
        }
    }
    true
}

/// How a round of collisions drawn ahead ended.
enum Round {
    /// All were handled; more may follow in this super-voxel.
    Read,
    /// All were handled and the next lies past the super-voxel.
    Left,
    /// `collide` drew other than `draws` random numbers; the walk is just
    /// after that collision.
    Drew,
    /// `collide` stopped the walk.
    Stopped,
}

/// Draws up to [`AHEAD`] collisions in `(t, t_end)` as the sequential walk
/// would (keeping the stream and the lookup count after each, and skipping
/// the `draws` numbers `collide` will take), reads them in lanes, and hands
/// them to `collide` in order. Where `collide` draws otherwise, or stops,
/// the stream, the count and `t` are set to what they are after that
/// collision and the rest of the round is dropped.
#[inline(always)]
fn round<V: VolumeAccess>(
    v: &V,
    ray: &Ray,
    t: &mut f32,
    (t_end, sigma_maj, draws): (f32, f32, u32),
    rng: &mut Pcg32,
    lookups: &mut u32,
    mut collide: impl FnMut(f32, f32, &mut Pcg32) -> bool,
) -> Round {
    let mut p = [Vec3::ZERO; AHEAD];
    let mut u = [Vec3::ZERO; AHEAD];
    let mut at = [0.0f32; AHEAD];
    // (stream `collide` starts from, stream it should leave, lookup count)
    let mut state: [(Pcg32, Pcg32, u32); AHEAD] =
        std::array::from_fn(|_| (rng.clone(), rng.clone(), 0));
    let (mut n, mut left) = (0, false);
    while n < AHEAD {
        *t += sample_exponential(rng, sigma_maj);
        if *t >= t_end {
            left = true;
            break;
        }
        u[n] = count_and_jitter(v, rng, lookups);
        (p[n], at[n]) = (ray.at(*t), *t);
        state[n].0 = rng.clone();
        for _ in 0..draws {
            rng.next_u32();
        }
        (state[n].1, state[n].2) = (rng.clone(), *lookups);
        n += 1;
    }
    let mut sigma = [0.0f32; AHEAD];
    if n > 0 {
        let u: &[Vec3] = if v.needs_jitter() { &u[..n] } else { &[] };
        v.sigma_t_lanes(&p[..n], u, &mut sigma[..n]);
    }
    for i in 0..n {
        let mut r = state[i].0.clone();
        let go = collide(at[i], sigma[i], &mut r);
        if !go || r != state[i].1 {
            (*rng, *lookups, *t) = (r, state[i].2, at[i]);
            return if go { Round::Drew } else { Round::Stopped };
        }
    }
    if left {
        Round::Left
    } else {
        Round::Read
    }
}
