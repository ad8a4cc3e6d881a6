//! Velocity resampling (Lin et al. 2021 §5.2): a pixel whose selected path has no
//! vertex in the medium (a background sample near a silhouette) would
//! otherwise reproject with the background's motion and reuse from the
//! wrong place (Fig. 13's halo). Instead it reprojects through a medium
//! point drawn along its primary ray with probability ∝ p(z) = σ_t·T: each
//! voxel of the conservative mip 1 (the authors' code) is chosen ∝ its mean
//! p(z), then a point uniformly within the voxel's segment. The point only
//! picks which previous reservoir to reuse, so its density need not be
//! known and the choice adds no bias for static scenes.

use fogbank_math::{Pcg32, Ray, Vec3};
use fogbank_volume::{Dda, GridView, Medium, MediumView, Voxel};

/// A medium point on the world `ray` drawn ∝ σ_t·T through the piecewise-
/// constant `mip`, or `None` when the ray sees no medium.
pub fn resample_point(mip: &Medium, ray: &Ray, rng: &mut Pcg32, lookups: &mut u32) -> Option<Vec3> {
    let (r, t0, t1) = mip.to_index(ray, 0.0, f32::INFINITY)?;
    let t = match mip.view() {
        MediumView::F16(v) => pick(&v, &r, t0, t1, rng, lookups),
        MediumView::F32(v) => pick(&v, &r, t0, t1, rng, lookups),
        MediumView::Analytic(_) => unreachable!("restir refuses analytic media"),
    }?;
    Some(ray.at(t))
}

/// Lin et al. 2021 §5.2: one streaming pass over the voxels the index-space ray
/// `r` crosses in `[t0, t1]`, choosing a voxel segment with weight
/// T(entry)·(1 − e^{−σ_t·Δ})/Δ (the mean of σ_t·T over it) by weighted
/// reservoir sampling, then a uniform distance within it.
fn pick<T: Voxel>(
    v: &GridView<'_, T>,
    r: &Ray,
    t0: f32,
    t1: f32,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> Option<f32> {
    let (mut tau, mut w_sum) = (0.0f64, 0.0f64);
    let mut chosen = None;
    for s in Dda::new(r, 1.0, v.grid.dims(), t0, t1) {
        *lookups += 1;
        let sigma_t = v.scale as f64 * v.grid.fetch(s.cell[0], s.cell[1], s.cell[2]) as f64;
        let len = (s.t1 - s.t0) as f64;
        if sigma_t > 0.0 && len > 0.0 {
            let w = (-tau).exp() * -(-sigma_t * len).exp_m1() / len;
            w_sum += w;
            if rng.next_f32() as f64 * w_sum < w {
                chosen = Some((s.t0, s.t1));
            }
        }
        tau += sigma_t * len;
        // Beyond this the remaining weights are below 1e-13 of the first.
        if tau > 30.0 {
            break;
        }
    }
    chosen.map(|(a, b)| a + rng.next_f32() * (b - a))
}

#[cfg(test)]
mod velocity_resampling_test {
    use super::*;
    use fogbank_volume::{medium::unit_box_transform, BrickGrid, DensityData, Filter, Precision};

    /// Two slabs along x, the far one denser: chosen voxels follow the
    /// mean σ_t·T weights (a chi-square test over the voxels).
    #[test]
    fn points_follow_the_mean_free_flight_density_per_voxel() {
        let n = 8;
        let grid = BrickGrid::from_fn([n, 1, 1], |i, _, _| match i {
            1 | 2 => 0.5,
            5 => 2.0,
            _ => 0.0,
        })
        .unwrap();
        let scale = 4.0;
        let m = Medium::new(
            DensityData::from_f32(grid, Precision::F32),
            scale,
            Filter::Nearest,
            unit_box_transform([n, 1, 1]),
            1,
        );
        // World box is [−½, ½] along x; voxels are 1/8 wide.
        let ray = Ray::new(Vec3::new(-1.0, 0.0, 0.0), Vec3::X);
        let dz = 1.0 / n as f64;
        let mut tau = 0.0f64;
        let mut expect = vec![0.0; n as usize];
        for (i, e) in expect.iter_mut().enumerate() {
            let sigma = scale as f64 * [0.0, 0.5, 0.5, 0.0, 0.0, 2.0, 0.0, 0.0][i];
            *e = (-tau).exp() * -(-sigma * dz).exp_m1() / dz;
            tau += sigma * dz;
        }
        let total: f64 = expect.iter().sum();
        let trials = 40_000;
        let mut counts = vec![0u32; n as usize];
        let mut rng = Pcg32::new(3, 1);
        let mut lookups = 0;
        for _ in 0..trials {
            let p = resample_point(&m, &ray, &mut rng, &mut lookups).unwrap();
            let i = ((p.x + 0.5) * n as f32).floor() as usize;
            counts[i] += 1;
        }
        let mut chi2 = 0.0;
        for i in 0..n as usize {
            let e = expect[i] / total * trials as f64;
            if e == 0.0 {
                assert_eq!(counts[i], 0, "voxel {i} is empty");
            } else {
                chi2 += (counts[i] as f64 - e).powi(2) / e;
            }
        }
        // 3 non-empty voxels: 2 degrees of freedom; 13.8 is p = 0.001.
        assert!(chi2 < 13.8, "chi2 {chi2}, counts {counts:?}");
        let miss = Ray::new(Vec3::new(-1.0, 2.0, 0.0), Vec3::X);
        assert!(resample_point(&m, &miss, &mut rng, &mut lookups).is_none());
    }
}
