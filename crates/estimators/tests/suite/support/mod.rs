//! Shared fixtures for the estimator tests: test media and random rays.

use fogbank_math::{DAffine3, Pcg32, Ray, Vec3};
use fogbank_volume::{
    procedural, AnalyticField, AnalyticKind, BrickGrid, DensityData, Filter, Medium,
};

pub fn grid_medium(grid: BrickGrid<f32>, filter: Filter, scale: f32, sv: u32) -> Medium {
    Medium::new(
        DensityData::F32(grid),
        scale,
        filter,
        DAffine3::IDENTITY,
        sv,
    )
}

pub fn cloud(res: u32, seed: u64) -> BrickGrid<f32> {
    procedural::cloud_grid::<f32>(res, seed).unwrap()
}

pub fn analytic_media(n: u32) -> Vec<AnalyticField> {
    [
        AnalyticKind::Empty,
        AnalyticKind::Constant { value: 1.0 },
        AnalyticKind::Ramp {
            base: 0.05,
            gradient: [1.0, 0.5, -0.05],
        },
        AnalyticKind::Sinusoid {
            mean: 1.0,
            amplitude: 0.95,
            frequency: [2.0, 1.0, 3.0],
            phase: 0.4,
        },
        AnalyticKind::Slabs {
            value: 1.0,
            count: 4,
            width: 0.03,
            axis: 0,
        },
    ]
    .into_iter()
    .map(|k| AnalyticField::new(k, n).unwrap())
    .collect()
}

pub fn random_unit(rng: &mut Pcg32) -> Vec3 {
    loop {
        let v = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - Vec3::ONE;
        let l = v.length();
        if l > 1e-3 && l <= 1.0 {
            return v / l;
        }
    }
}

/// Rays through the box `[0, n]`: from outside towards a random interior
/// point, starting inside, axis-parallel, and grazing faces and voxel-centre
/// planes.
pub fn test_rays(n: [u32; 3], count: usize, seed: u64) -> Vec<Ray> {
    let nf = Vec3::new(n[0] as f32, n[1] as f32, n[2] as f32);
    let mut rng = Pcg32::new(seed, 11);
    let mut rays = Vec::with_capacity(count);
    for i in 0..count {
        let inside = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * nf;
        let ray = match i % 5 {
            0 | 1 => {
                let o = nf * 0.5 + random_unit(&mut rng) * nf.length();
                Ray::new(o, (inside - o).normalize())
            }
            2 => Ray::new(inside, random_unit(&mut rng)),
            3 => {
                let a = (rng.next_u32() % 3) as usize;
                let mut d = Vec3::ZERO;
                d[a] = if rng.next_u32().is_multiple_of(2) {
                    1.0
                } else {
                    -1.0
                };
                let mut o = inside;
                o[a] = if d[a] > 0.0 { -1.0 } else { nf[a] + 1.0 };
                Ray::new(o, d)
            }
            _ => {
                // Grazing: on a face or on a plane of voxel centres, travelling
                // within the plane.
                let a = (rng.next_u32() % 3) as usize;
                let mut o = inside;
                o[a] = match rng.next_u32() % 3 {
                    0 => 0.0,
                    1 => nf[a],
                    _ => (rng.next_u32() % n[a]) as f32 + 0.5,
                };
                let mut d = random_unit(&mut rng);
                d[a] = 0.0;
                if d.length() < 1e-3 {
                    d[(a + 1) % 3] = 1.0;
                }
                let d = d.normalize();
                Ray::new(o - d * 2.0 * nf.max_element(), d)
            }
        };
        rays.push(ray);
    }
    rays
}
