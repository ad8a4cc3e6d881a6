//! Building importance lists (Lerzer and Dachsbacher 2025 §5.1–§5.3, §6.1): one per camera
//! ray, kept in a global pool with per-pixel offset and size, and a fresh
//! one per NEE ray.
//!
//! Camera lists are built on the pixel-centre ray (checklist §1: the paper
//! is silent on sub-pixel jitter) before the first frame: one uniform and
//! `passes − 1` adaptive passes, double-buffered, then frozen. The paper
//! refines them during its first four frames instead, so its first three
//! frames see coarser lists; from then on the lists are the same, and a
//! frozen list makes the estimator unbiased for μ' of that list
//! (acceptance 3). A jittered ray looks its t up from its own entry point.

use super::optimised::{importance_at, RayList};
use super::params::VisOptParams;
use super::sampling;
use super::segments::{self, Segment};
use crate::integrators::shared::occluders;
use crate::world::medium::SceneMedium;
use crate::world::World;
use fogbank_math::{Pcg32, Ray, SampleKey};
use rayon::prelude::*;

/// The camera rays' lists of a whole image.
#[derive(Clone, Debug, Default)]
pub struct CameraLists {
    pub width: u32,
    pub pool: Vec<Segment>,
    /// Per pixel: (offset, size) into `pool`, K(z) and L.
    pub pixels: Vec<(u32, u32, f32, f32)>,
}

impl CameraLists {
    pub fn build(world: &World, p: &VisOptParams, unit: f32, seed: u64) -> CameraLists {
        let (w, h) = (world.camera.width, world.camera.height);
        let m = &world.media[0];
        let per_pixel: Vec<(Vec<Segment>, f32, f32)> = (0..w * h)
            .into_par_iter()
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let ray = world.camera.ray(x as f32 + 0.5, y as f32 + 0.5);
                let mut rng = SampleKey {
                    seed: seed as u32,
                    pixel: i,
                    sample: 0,
                    dimension: 0x7151,
                }
                .rng();
                let t_end = occluders::first_surface(world, &ray);
                camera_list(m, &ray, t_end, p, unit, &mut rng)
            })
            .collect();
        let mut lists = CameraLists {
            width: w,
            pool: Vec::with_capacity(per_pixel.iter().map(|l| l.0.len()).sum()),
            pixels: Vec::with_capacity(per_pixel.len()),
        };
        for (l, kz, len) in per_pixel {
            lists
                .pixels
                .push((lists.pool.len() as u32, l.len() as u32, kz, len));
            lists.pool.extend(l);
        }
        lists
    }

    /// (list, K(z), L) of pixel (x, y).
    pub fn get(&self, x: u32, y: u32) -> (&[Segment], f32, f32) {
        let (o, n, kz, len) = self.pixels[(y * self.width + x) as usize];
        (&self.pool[o as usize..(o + n) as usize], kz, len)
    }

    /// Pixel (x, y)'s list as its camera ray sees it: t = 0 at ray
    /// parameter `origin`, where the ray enters the medium.
    pub fn ray_list(&self, x: u32, y: u32, origin: f32) -> RayList<'_> {
        let (list, big_k_z, length) = self.get(x, y);
        RayList {
            list,
            big_k_z,
            length,
            origin,
            sign: 1.0,
        }
    }

    pub fn memory_bytes(&self) -> usize {
        self.pool.len() * std::mem::size_of::<Segment>() + self.pixels.len() * 16
    }
}

/// The frozen list of one camera ray: (entries, K(z), L).
pub fn camera_list(
    m: &SceneMedium,
    ray: &Ray,
    t_end: f32,
    p: &VisOptParams,
    unit: f32,
    rng: &mut Pcg32,
) -> (Vec<Segment>, f32, f32) {
    let Some((_, t0, t1)) = m.medium.to_index(ray, 0.0, t_end) else {
        return (Vec::new(), 0.0, 0.0);
    };
    let length = (t1 - t0) * unit;
    let d = merge_distance(p, length, p.samples);
    let k_at = |t: f32| {
        let w = ray.at(t0 + t / unit);
        importance_at(m, w, m.sigma_t_smooth(w))
    };
    let (mut list, mut next, mut kz) = (Vec::new(), Vec::new(), 0.0);
    for pass in 0..p.passes {
        let ts = if pass == 0 {
            sampling::uniform(length, p.samples, rng)
        } else {
            sampling::adaptive(&list, length, p.samples, p.gap_share, rng)
        };
        let samples: Vec<(f32, f32)> = ts.iter().map(|&t| (t, k_at(t))).collect();
        kz = segments::merge_within(
            &list,
            &samples,
            d,
            m.importance.tolerance(),
            length,
            &mut next,
        );
        std::mem::swap(&mut list, &mut next);
    }
    (list, kz, length)
}

/// The list of one NEE ray (§5.3): `light_samples` stratified samples, merged,
/// t measured from the light's end `s1` towards the vertex end `s0` (the
/// light plays the camera). `ray` is the world shadow ray.
pub fn light_list(
    m: &SceneMedium,
    ray: &Ray,
    (s0, s1): (f32, f32),
    p: &VisOptParams,
    unit: f32,
    rng: &mut Pcg32,
    out: &mut Vec<Segment>,
) -> (f32, f32) {
    let length = (s1 - s0) * unit;
    let samples = p.light_samples;
    let d = merge_distance(p, length, samples);
    // Per-thread scratch: one list per NEE ray, no allocation per sample.
    thread_local!(static POINTS: std::cell::RefCell<Vec<(f32, f32)>> = const { std::cell::RefCell::new(Vec::new()) });
    POINTS.with_borrow_mut(|pts| {
        pts.clear();
        pts.extend(sampling::strata(length, samples, rng).map(|t| {
            let w = ray.at(s1 - t / unit);
            (t, importance_at(m, w, m.sigma_t_smooth(w)))
        }));
        let kz = segments::merge_within(&[], pts, d, m.importance.tolerance(), length, out);
        (kz, length)
    })
}

/// d of Alg. 1: the key, or 2·L/N so that neighbouring strata merge.
fn merge_distance(p: &VisOptParams, length: f32, n: u32) -> f32 {
    if p.merge_distance > 0.0 {
        p.merge_distance
    } else {
        2.0 * length / n.max(1) as f32
    }
}
