//! Conservative mips (Lin et al. 2021 §4.1): block means, σ_t* > 0 wherever the
//! trilinear field is positive, and mips as media of their own.

use fogbank_math::{DAffine3, Pcg32, Ray, Vec3};
use fogbank_volume::mip::mip_grid;
use fogbank_volume::{BrickGrid, DensityData, Filter, Medium, Precision};

/// A sparse grid: a few positive voxels in empty space, one dense corner.
fn sparse(dims: [u32; 3], seed: u64) -> BrickGrid<f32> {
    let mut rng = Pcg32::new(seed, 1);
    let picks: Vec<[u32; 3]> = (0..12)
        .map(|_| dims.map(|d| (rng.next_f32() * d as f32) as u32 % d))
        .collect();
    BrickGrid::from_fn(dims, |i, j, k| {
        if picks.contains(&[i, j, k]) {
            0.5 + (i + j + k) as f32 * 0.01
        } else if i < 3 && j < 2 && k < 3 {
            2.0
        } else {
            0.0
        }
    })
    .unwrap()
}

/// The trilinear field of `g` at index-space point `p` (cell-centred,
/// clamped at the edges, as the lookups are).
fn trilinear(g: &BrickGrid<f32>, p: Vec3) -> f32 {
    let q = p - Vec3::splat(0.5);
    let b = q.floor();
    let f = q - b;
    let (i, j, k) = (b.x as i32, b.y as i32, b.z as i32);
    let mut v = 0.0;
    for c in 0..8 {
        let (di, dj, dk) = (c & 1, (c >> 1) & 1, (c >> 2) & 1);
        let w = (if di == 1 { f.x } else { 1.0 - f.x })
            * (if dj == 1 { f.y } else { 1.0 - f.y })
            * (if dk == 1 { f.z } else { 1.0 - f.z });
        v += w * g.fetch(i + di, j + dj, k + dk);
    }
    v
}

#[test]
fn a_mip_voxel_is_the_mean_of_its_block() {
    let dims = [21, 13, 9];
    let g = BrickGrid::<f32>::from_fn(dims, |i, j, k| ((i * 7 + j * 3 + k) % 5) as f32).unwrap();
    for level in [1, 2] {
        let m = mip_grid(dims, |i, j, k| g.fetch(i, j, k), level).unwrap();
        let s = 1 << level;
        assert_eq!(m.dims(), dims.map(|d| d.div_ceil(s)));
        for ck in 0..m.dims()[2] as i32 {
            for cj in 0..m.dims()[1] as i32 {
                for ci in 0..m.dims()[0] as i32 {
                    let (mut sum, mut n) = (0.0f64, 0);
                    for k in ck * s as i32..(ck + 1) * s as i32 {
                        for j in cj * s as i32..(cj + 1) * s as i32 {
                            for i in ci * s as i32..(ci + 1) * s as i32 {
                                if i < dims[0] as i32 && j < dims[1] as i32 && k < dims[2] as i32 {
                                    sum += g.fetch(i, j, k) as f64;
                                    n += 1;
                                }
                            }
                        }
                    }
                    let mean = (sum / n as f64) as f32;
                    if mean > 0.0 {
                        assert!(
                            (m.fetch(ci, cj, ck) - mean).abs() <= 1e-6 * mean,
                            "level {level}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn mips_are_positive_wherever_the_trilinear_field_is() {
    for (seed, dims) in [(1, [24, 24, 24]), (2, [19, 30, 11]), (3, [40, 9, 17])] {
        let g = sparse(dims, seed);
        for level in 1..=3 {
            let m = mip_grid(dims, |i, j, k| g.fetch(i, j, k), level).unwrap();
            let s = (1 << level) as f32;
            let mut rng = Pcg32::new(seed + 10, level as u64);
            let (mut positive, mut zero_where_zero) = (0, 0);
            for _ in 0..200_000 {
                let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32())
                    * Vec3::new(dims[0] as f32, dims[1] as f32, dims[2] as f32);
                let c = (p / s).floor();
                let star = m.fetch(c.x as i32, c.y as i32, c.z as i32);
                if trilinear(&g, p) > 0.0 {
                    positive += 1;
                    assert!(
                        star > 0.0,
                        "σ_t* = 0 at {p} where the trilinear field is positive (level {level})"
                    );
                } else if star == 0.0 {
                    zero_where_zero += 1;
                }
            }
            // The test sees both kinds of points, and the mip is not
            // simply positive everywhere.
            assert!(
                positive > 100 && zero_where_zero > 1000,
                "{positive} {zero_where_zero}"
            );
        }
    }
}

#[test]
fn an_empty_grid_has_empty_mips_and_bad_levels_are_refused() {
    let dims = [17, 8, 8];
    let m = mip_grid(dims, |_, _, _| 0.0, 2).unwrap();
    assert_eq!(m.dense_bricks(), 0);
    assert_eq!(m.fetch(0, 0, 0), 0.0);
    assert!(mip_grid(dims, |_, _, _| 1.0, 0).is_err());
    assert!(mip_grid(dims, |_, _, _| 1.0, 9).is_err());
}

#[test]
fn a_mip_is_a_medium_in_the_same_place() {
    let dims = [32, 16, 24];
    let xf = DAffine3::from_scale(fogbank_math::DVec3::splat(0.03));
    let g = BrickGrid::<f32>::from_fn(dims, |_, _, _| 1.5).unwrap();
    let fine = Medium::new(
        DensityData::from_f32(g, Precision::F16),
        2.0,
        Filter::StochasticTrilinear,
        xf,
        16,
    );
    let ray = Ray::new(
        Vec3::new(-0.1, 0.2, 0.3),
        Vec3::new(1.0, 0.1, 0.05).normalize(),
    );
    let depth = |m: &Medium| {
        let (r, t0, t1) = m.to_index(&ray, 0.0, f32::INFINITY).unwrap();
        let world_len = (t1 - t0) * r.d.length() / m.world_to_index.matrix3.x_axis.length() as f32;
        (
            world_len,
            m.supervoxels
                .cells
                .iter()
                .map(|c| c.max)
                .fold(0.0, f32::max),
        )
    };
    for level in 1..=3 {
        let mip = fine.mip(level, 4).unwrap();
        assert_eq!(mip.filter, Filter::Nearest);
        let (a, b) = (fine.world_bounds(), mip.world_bounds());
        assert!((a.min - b.min).abs().max_element() < 1e-6);
        assert!(
            (a.max - b.max).abs().max_element() < 1e-6,
            "dims divisible by 2^level"
        );
        // A constant grid: same σ_t, same chord.
        let (lf, sf) = depth(&fine);
        let (lm, sm) = depth(&mip);
        assert!(
            (lf - lm).abs() < 1e-4 * lf && (sf - sm).abs() < 1e-6,
            "{lf} {lm} {sf} {sm}"
        );
    }
    let analytic = Medium::new(
        DensityData::Analytic(
            fogbank_volume::AnalyticField::new(
                fogbank_volume::AnalyticKind::Constant { value: 1.0 },
                8,
            )
            .unwrap(),
        ),
        1.0,
        Filter::Nearest,
        xf,
        4,
    );
    assert!(analytic.mip(1, 4).is_err());
}
