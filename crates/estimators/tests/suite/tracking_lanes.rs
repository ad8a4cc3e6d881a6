//! The tracking walk reads its tentative collisions ahead in SIMD lanes
//! (`null_collisions::walk`); this holds it to the sequential
//! walk bit for bit: the same collisions and σ_t seen in the same order,
//! the same random stream and lookup count after, the same outcome — also
//! when `collide` draws random numbers (Russian roulette) or stops.

use crate::support;

use fogbank_estimators::lookup::{sample_exponential, sigma_t_at};
use fogbank_estimators::null_collisions::{walk, Tracking};
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::{
    Dda, DensityData, Filter, Medium, MediumView, Precision, SuperVoxel, VolumeAccess,
};
use support::*;

/// The walk as it was before lanes: one collision at a time.
fn walk_sequential<V: VolumeAccess>(
    v: &V,
    seg: &RaySegment,
    rng: &mut Pcg32,
    lookups: &mut u32,
    mut rate: impl FnMut(&SuperVoxel, f32) -> (f32, f32),
    mut collide: impl FnMut(f32, f32, f32, f32, &mut Pcg32) -> bool,
) -> bool {
    let (ray, sv) = (&seg.ray, v.supervoxels());
    for s in Dda::new(ray, sv.size as f32, sv.dims, seg.t0, seg.t1) {
        let (sigma_maj, value) = rate(sv.get(s.cell), s.t1 - s.t0);
        if sigma_maj <= 0.0 {
            continue;
        }
        let mut t = s.t0;
        loop {
            t += sample_exponential(rng, sigma_maj);
            if t >= s.t1 {
                break;
            }
            let sigma_t = sigma_t_at(v, ray.at(t), rng, lookups);
            if !collide(t, sigma_t, sigma_maj, value, rng) {
                return false;
            }
        }
    }
    true
}

/// Everything a walk leaves behind.
#[derive(Debug, PartialEq)]
struct Trace {
    reached: bool,
    seen: Vec<(u32, u32)>,
    rng: Pcg32,
    lookups: u32,
}

/// Collides of every kind: 0 draws at some collisions and stops at others
/// (chosen by the bits of t and σ_t, so both walks choose alike); 1–3 ratio
/// tracking with roulette at 0, 0.1 and 0.6; 4 delta tracking (one draw
/// per collision); 5 one draw per collision as a rule, none or two at
/// some, stopping at others.
fn trace<V: VolumeAccess>(v: &V, seg: RaySegment, seed: u64, kind: u32, lanes: bool) -> Trace {
    let mut rng = Pcg32::new(seed, 3);
    let mut lookups = 0;
    let mut seen = Vec::new();
    let mut weight = [1.0f32];
    let collide = |t: f32, sigma_t: f32, sigma_maj: f32, _: f32, rng: &mut Pcg32| {
        seen.push((t.to_bits(), sigma_t.to_bits()));
        let bits = sigma_t.to_bits() ^ t.to_bits();
        match kind {
            0 => {
                if bits.is_multiple_of(7) {
                    rng.next_u32();
                }
                !bits.is_multiple_of(53)
            }
            4 => rng.next_f32() * sigma_maj >= sigma_t,
            5 => {
                let n = if bits.is_multiple_of(11) {
                    2
                } else if bits.is_multiple_of(5) {
                    0
                } else {
                    1
                };
                for _ in 0..n {
                    rng.next_u32();
                }
                !bits.is_multiple_of(97)
            }
            k => {
                weight[0] *= 1.0 - sigma_t / sigma_maj;
                let threshold = [0.0, 0.0, 0.1, 0.6][k as usize];
                weight != [0.0]
                    && fogbank_estimators::roulette::roulette(&mut weight, [1.0], threshold, rng)
            }
        }
    };
    let rate = |s: &SuperVoxel, _: f32| (s.max, 0.0);
    let draws = if kind >= 4 { 1 } else { 0 };
    let reached = if lanes {
        let tracking = Tracking {
            draws,
            rate,
            collide,
        };
        walk(v, &seg, &mut rng, &mut lookups, tracking)
    } else {
        walk_sequential(v, &seg, &mut rng, &mut lookups, rate, collide)
    };
    Trace {
        reached,
        seen,
        rng,
        lookups,
    }
}

fn media() -> Vec<Medium> {
    let mut out = Vec::new();
    for (scale, filter) in [
        (2.0, Filter::Trilinear),
        (60.0, Filter::StochasticTrilinear),
        (400.0, Filter::Trilinear),
        (30.0, Filter::Nearest),
    ] {
        out.push(grid_medium(cloud(40, 5), filter, scale, 8));
        out.push(Medium::new(
            DensityData::from_f32(cloud(40, 5), Precision::F16),
            scale,
            filter,
            fogbank_math::DAffine3::IDENTITY,
            4,
        ));
    }
    out
}

#[test]
fn lanes_walk_is_the_sequential_walk_bit_for_bit() {
    let (mut rounds, mut drew_or_stopped) = (0, 0);
    for m in media() {
        for (i, ray) in test_rays(m.dims(), 60, 17).iter().enumerate() {
            let Some((r, t0, t1)) = m.to_index(ray, 0.0, f32::INFINITY) else {
                continue;
            };
            for kind in 0..6 {
                let (a, b) = match m.view() {
                    MediumView::F32(v) => (
                        trace(&v, RaySegment::new(r, t0, t1), i as u64, kind, true),
                        trace(&v, RaySegment::new(r, t0, t1), i as u64, kind, false),
                    ),
                    MediumView::F16(v) => (
                        trace(&v, RaySegment::new(r, t0, t1), i as u64, kind, true),
                        trace(&v, RaySegment::new(r, t0, t1), i as u64, kind, false),
                    ),
                    MediumView::Analytic(_) => unreachable!(),
                };
                assert_eq!(a, b, "ray {i}, kind {kind}");
                rounds += a.seen.len();
                drew_or_stopped += (a.rng != Pcg32::new(i as u64, 3) && kind != 1) as usize;
            }
        }
    }
    assert!(
        rounds > 20_000 && drew_or_stopped > 100,
        "{rounds} collisions, {drew_or_stopped}"
    );
}
