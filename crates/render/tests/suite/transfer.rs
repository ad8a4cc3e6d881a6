//! Transfer functions (Lerzer and Dachsbacher 2025 §3): post-interpolative classification
//! keeps tracking unbiased (its super-voxel majorants bound α over each
//! cell's value range, also where α peaks between voxel values), colour and
//! emission follow the interpolated scalar, pre- and post-interpolative
//! agree where they must (nearest filtering), points are in the file's
//! units, and the combinations that would be wrong are refused.

use fogbank_estimators::{deterministic_marching, ratio_tracking, track_length};
use fogbank_math::{Pcg32, Ray, RaySegment, Vec3};
use fogbank_render::{parse_scene, render, Progress, RenderOptions, Scene};
use fogbank_volume::{MediumView, VolumeAccess};
use std::path::Path;

/// α with a narrow peak between typical voxel values: a majorant taken from
/// the classified voxels alone would miss it.
const PEAKED: &str =
    "opacity = [[0.0, 0.0], [0.30, 0.0], [0.31, 1.0], [0.32, 0.0], [0.5, 0.1], [1.0, 0.6]]";

fn scene(media: &str, extra: &[&str]) -> Result<Scene, String> {
    let text = format!(
        "[camera]\nfrom = [0.0, 0.0, 2.2]\nto = [0.0, 0.0, 0.0]\nfov = 40.0\nwidth = 20\nheight = 16\n\
         [[media]]\n{media}\n"
    );
    let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    let desc = parse_scene(&text, "test", &extra).map_err(|e| e.to_string())?;
    Scene::build(desc, Path::new(env!("CARGO_MANIFEST_DIR"))).map_err(|e| e.to_string())
}

/// Only a thin shell where the value crosses 0.31 is visible: majorants
/// from voxel values are mostly zero.
const SHELL: &str = "opacity = [[0.0, 0.0], [0.30, 0.0], [0.31, 1.0], [0.32, 0.0]]";

fn cloud(transfer: &str) -> String {
    cloud_scaled(transfer, 20.0)
}

fn cloud_scaled(transfer: &str, scale: f32) -> String {
    format!(
        "density = {{ procedural = \"cloud\", resolution = 24, seed = 3 }}\nsigma_t_scale = {scale}\n\
         precision = \"f32\"\n[media.transfer]\n{transfer}\n"
    )
}

#[test]
fn classified_majorants_bound_every_lookup_where_voxel_values_would_not() {
    let s = scene(&cloud(PEAKED), &[]).unwrap();
    let m = &s.world.media[0].medium;
    let MediumView::F32(v) = m.view() else {
        panic!("f32 grid expected")
    };
    let sv = v.supervoxels();
    let d = m.dims();
    let mut rng = Pcg32::new(8, 1);
    let (mut above_voxels, mut n) = (0, 0);
    for _ in 0..200_000 {
        let p = Vec3::new(
            rng.next_f32() * d[0] as f32,
            rng.next_f32() * d[1] as f32,
            rng.next_f32() * d[2] as f32,
        );
        let sigma = v.sigma_t(p, Vec3::ZERO);
        let c = (p / sv.size as f32).floor();
        let cell = sv.get([c.x as i32, c.y as i32, c.z as i32]);
        assert!(
            sigma <= cell.max && sigma >= cell.min,
            "{sigma} outside [{}, {}] at {p}",
            cell.min,
            cell.max
        );
        // The largest classified *voxel* value of this cell's neighbourhood.
        let q = p - Vec3::splat(0.5);
        let voxel_max = (0..8)
            .map(|k| {
                let o = Vec3::new((k & 1) as f32, ((k >> 1) & 1) as f32, (k >> 2) as f32);
                let i = (q.floor() + o).max(Vec3::ZERO).min(Vec3::new(
                    d[0] as f32 - 1.0,
                    d[1] as f32 - 1.0,
                    d[2] as f32 - 1.0,
                ));
                v.scale * v.classify(v.grid.fetch(i.x as i32, i.y as i32, i.z as i32))
            })
            .fold(0.0f32, f32::max);
        above_voxels += (sigma > voxel_max * 1.01 + 1e-3) as u32;
        n += 1;
    }
    // Power: the peak does lie between voxel values at many points.
    assert!(
        above_voxels > n / 1000,
        "only {above_voxels} of {n} lookups exceed their voxels"
    );
}

#[test]
fn post_classified_transmittance_is_unbiased_against_fine_marching() {
    // Fine super-voxels, so that the bounds matter.
    let s = scene(&cloud_scaled(SHELL, 400.0), &["media.0.supervoxel=2"]).unwrap();
    let m = &s.world.media[0].medium;
    let MediumView::F32(v) = m.view() else {
        panic!()
    };
    // Power: majorants from the classified voxel values alone (what a
    // pre-classified grid would have) miss α's peak between voxel values,
    // and track-length tracking through them is measurably biased.
    let d = m.dims();
    let naive =
        fogbank_volume::SuperVoxelGrid::build(d, 1, 1, |i, j, k| v.classify(v.grid.fetch(i, j, k)))
            .scaled(v.scale);
    let naive_view = fogbank_volume::GridView {
        supervoxels: &naive,
        ..v
    };
    let mut worst_naive_z = 0.0f64;
    let mut rng = Pcg32::new(3, 7);
    let n = 40_000;
    for r in 0..6 {
        let o = Vec3::new(-1.0, -0.1 + 0.04 * r as f32, 0.05 - 0.02 * r as f32);
        let world = Ray::new(o, Vec3::new(1.0, 0.02 * r as f32, -0.01).normalize());
        let Some((ray, t0, t1)) = m.to_index(&world, 0.0, f32::INFINITY) else {
            panic!("ray {r} misses")
        };
        let seg = RaySegment::new(ray, t0, t1);
        let (tau, _) = deterministic_marching::optical_depth(&v, &seg, 1.0 / 256.0);
        let exact = (-tau).exp();
        for (name, f) in [
            (
                "track_length",
                track_length::transmittance::<_> as fn(&_, &RaySegment, &mut Pcg32) -> _,
            ),
            ("ratio_tracking", |v, seg, rng| {
                ratio_tracking::transmittance(v, seg, rng, 0.0)
            }),
        ] {
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let t = f(&v, &seg, &mut rng).transmittance as f64;
                sum += t;
                sum2 += t * t;
            }
            let mean = sum / n as f64;
            let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
            assert!(
                (mean - exact).abs() < 4.5 * se + 1e-4,
                "ray {r} {name}: {mean} vs {exact} (se {se}, τ {tau})"
            );
        }
        assert!(tau > 0.02, "ray {r} sees little of the medium (τ {tau})");
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let t =
                track_length::transmittance(&naive_view, &RaySegment::new(ray, t0, t1), &mut rng)
                    .transmittance as f64;
            sum += t;
            sum2 += t * t;
        }
        let mean = sum / n as f64;
        let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        worst_naive_z = worst_naive_z.max((mean - exact).abs() / se);
    }
    assert!(
        worst_naive_z > 6.0,
        "voxel-value majorants are not caught (worst z {worst_naive_z})"
    );
}

#[test]
fn colour_and_emission_follow_the_interpolated_scalar() {
    let s = scene(
        &cloud(&format!(
            "{PEAKED}\ncolor = [[0.0, 1.0, 0.0, 0.0], [1.0, 0.0, 0.5, 1.0]]\n\
             emission = [[0.0, 0.0, 0.0, 0.0], [1.0, 2.0, 1.0, 0.0]]\nemission_scale = 3.0"
        )),
        &["media.0.albedo=[1.0, 0.5, 1.0]"],
    )
    .unwrap();
    let m = &s.world.media[0];
    let mut rng = Pcg32::new(1, 1);
    for _ in 0..100 {
        let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - Vec3::splat(0.5);
        let x = m.scalar_at(p);
        let a = m.albedo_at(p);
        let colour = Vec3::new(1.0 - x, 0.5 * x, x) * Vec3::new(1.0, 0.5, 1.0);
        assert!(
            (a - colour).abs().max_element() < 1e-5,
            "{a} vs {colour} at s = {x}"
        );
        let e = m.emitted(p, a);
        let expected = (Vec3::ONE - a) * Vec3::new(2.0 * x, x, 0.0) * 3.0;
        assert!(
            (e - expected).abs().max_element() < 1e-4,
            "{e} vs {expected}"
        );
    }
}

/// Nearest filtering classifies one voxel value per point, so pre- and
/// post-interpolative media are the same field: the exact (regular
/// tracking) transmittance images agree bit for bit.
#[test]
fn pre_and_post_agree_bitwise_under_nearest_filtering() {
    let image = |mode: &str| {
        let s = scene(
            &cloud(&format!("{PEAKED}\nmode = \"{mode}\"")),
            &[
                "media.0.filter=\"nearest\"",
                "integrator.estimator=\"regular_tracking\"",
            ],
        )
        .unwrap();
        let opts = RenderOptions::new(1, 1);
        render(&s, &opts, &Progress::default()).film.mean()
    };
    let (post, pre) = (image("post"), image("pre"));
    assert_eq!(post, pre);
    assert!(post.iter().any(|p| p[0] < 0.9));
    // And trilinear pre differs from trilinear post (the peak is lost).
    let tri = |mode: &str| {
        let s = scene(
            &cloud(&format!("{PEAKED}\nmode = \"{mode}\"")),
            &[
                "media.0.filter=\"trilinear\"",
                "integrator.estimator=\"ratio_tracking\"",
            ],
        )
        .unwrap();
        let m = &s.world.media[0].medium;
        let MediumView::F32(v) = m.view() else {
            panic!()
        };
        let ray = Ray::new(Vec3::new(-1.0, 0.01, 0.02), Vec3::X);
        let (r, t0, t1) = m.to_index(&ray, 0.0, f32::INFINITY).unwrap();
        deterministic_marching::optical_depth(&v, &RaySegment::new(r, t0, t1), 1.0 / 64.0).0
    };
    let (a, b) = (tri("post"), tri("pre"));
    assert!((a - b).abs() > 0.01 * a.max(b), "post τ {a}, pre τ {b}");
}

#[test]
fn nifti_points_are_in_file_units() {
    let file = "../volume/tests/fixtures/sci/oblique_i16.nii.gz";
    let v =
        fogbank_volume::loaders::nifti::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join(file), 0)
            .unwrap();
    // A ramp in file units across part of the data's range.
    let (lo, hi) = v.range().unwrap();
    let (a, b) = (lo + 0.3 * (hi - lo), lo + 0.7 * (hi - lo));
    let s = scene(
        &format!("density = {{ nifti = \"{file}\" }}\nprecision = \"f32\"\n[media.transfer]\nopacity = [[{a}, 0.0], [{b}, 1.0]]"),
        &[],
    )
    .unwrap();
    let m = &s.world.media[0].medium;
    let MediumView::F32(view) = m.view() else {
        panic!()
    };
    let [nx, ny, _] = v.dims.map(|d| d as usize);
    let mut inside = 0;
    for (idx, &x) in v.values.iter().enumerate() {
        let (i, j, k) = (idx % nx, (idx / nx) % ny, idx / (nx * ny));
        let p = Vec3::new(i as f32 + 0.5, j as f32 + 0.5, k as f32 + 0.5);
        let expected = ((x - a) / (b - a)).clamp(0.0, 1.0);
        let got = view.sigma_t(p, Vec3::ZERO);
        assert!(
            (got - expected).abs() < 1e-4,
            "voxel {i},{j},{k} = {x}: α {got}, expected {expected}"
        );
        inside += (expected > 0.0 && expected < 1.0) as u32;
    }
    assert!(inside > 5, "the ramp covers only {inside} voxels");
}

#[test]
fn wrong_combinations_are_refused_with_the_key() {
    let err = |media: &str, extra: &[&str]| scene(media, extra).err().unwrap_or_default();
    let e = err(&cloud(PEAKED), &["media.0.filter=\"stochastic_trilinear\""]);
    assert!(
        e.contains("media.0.filter") && e.contains("pre-interpolative"),
        "{e}"
    );
    let e = err(
        &cloud(PEAKED),
        &["integrator.estimator=\"analytic_trilinear\""],
    );
    assert!(e.contains("analytic_trilinear"), "{e}");
    let e = err(
        "density = { procedural = \"sphere\" }\n[media.transfer]\nopacity = [[0, 1]]",
        &[],
    );
    assert!(
        e.contains("media.0.transfer") && e.contains("analytic"),
        "{e}"
    );
    let e = err(
        &cloud(PEAKED),
        &[
            "integrator.type=\"restir\"",
            "integrator.estimator=\"ratio_tracking\"",
        ],
    );
    assert!(e.contains("restir") && e.contains("mode = \"pre\""), "{e}");
    let e = err(
        &format!(
            "{}\n[media.emission]\ncolor = [1.0, 1.0, 1.0]",
            cloud(PEAKED)
        ),
        &[],
    );
    assert!(
        e.contains("media.0.transfer") && e.contains("emission"),
        "{e}"
    );
    // Pre mode keeps the jittered filter legal.
    assert!(scene(&cloud(&format!("{PEAKED}\nmode = \"pre\"")), &[]).is_ok());
}
