//! Estimators on the caller's own rays: transmittance estimates and free
//! flights of one medium along N rays, K samples each, in parallel; what an
//! estimator study needs beyond rendered images (the Python package's
//! `fogbank.transmittance` and `fogbank.sample_distance`).
//!
//! Streams: sample `j` of ray `i` draws from the sample key (seed, pixel
//! `i`, sample `j`, the estimator dimension), the stream the transmittance
//! integrator gives pixel `i`'s sample `j` (`integrators::shared::
//! estimator_rng`). A 1-spp transmittance render through pixel centres is
//! therefore this module's estimates on the camera's rays, bit for bit, and
//! the result never depends on the thread count.
//!
//! Rays are `o + t·d` for `0 ≤ t ≤ t_max` in the caller's parametrisation:
//! `d` need not be a unit vector; distances come back in the same units.

use crate::error::Error;
use crate::renderer::Renderer;
use fogbank_estimators::distance::{analytic_trilinear, equiangular};
use fogbank_estimators::{transmittance, Estimator};
pub use fogbank_estimators::{OptionValue, Options};
use fogbank_math::{Ray, RaySegment, SampleKey, Vec3};
use fogbank_render::integrators::shared::dim;
use fogbank_render::integrators::shared::tracking::sampler_flight;
use fogbank_render::integrators::shared::DistanceSampler;
use fogbank_render::Progress;
pub use fogbank_volume::Medium;
use fogbank_volume::MediumView;
use rayon::prelude::*;
use std::sync::atomic::Ordering;

/// N rays: origins, directions and segment ends, as the caller holds them.
#[derive(Clone, Copy, Debug)]
pub struct Rays<'a> {
    pub origins: &'a [[f32; 3]],
    pub directions: &'a [[f32; 3]],
    pub t_max: &'a [f32],
}

impl Rays<'_> {
    pub fn len(&self) -> usize {
        self.origins.len()
    }

    pub fn is_empty(&self) -> bool {
        self.origins.is_empty()
    }

    /// Refuses arrays of different lengths, more rays than sample keys
    /// address, and non-finite or degenerate rays (naming the first).
    pub fn check(&self, samples: u32) -> Result<(), Error> {
        let n = self.origins.len();
        if self.directions.len() != n || self.t_max.len() != n {
            return Err(Error::invalid(format!(
                "origins ({n}), directions ({}) and t_max ({}) must hold one entry per ray",
                self.directions.len(),
                self.t_max.len()
            )));
        }
        if n as u64 > u32::MAX as u64 {
            return Err(Error::invalid(format!(
                "{n} rays: at most {} per call",
                u32::MAX
            )));
        }
        if samples == 0 {
            return Err(Error::invalid("samples must be at least 1"));
        }
        for i in 0..n {
            let (o, d, t) = (self.origins[i], self.directions[i], self.t_max[i]);
            if !o.iter().all(|x| x.is_finite()) || !d.iter().all(|x| x.is_finite()) {
                return Err(Error::invalid(format!(
                    "ray {i}: origin and direction must be finite"
                )));
            }
            if Vec3::from(d).length_squared() == 0.0 {
                return Err(Error::invalid(format!("ray {i}: direction is zero")));
            }
            if t.is_nan() || t < 0.0 {
                return Err(Error::invalid(format!(
                    "ray {i}: t_max {t} (0 ≤ t_max ≤ inf)"
                )));
            }
        }
        Ok(())
    }

    /// Ray `i` with a unit direction and its segment end in that unit, and
    /// the direction's length (the factor back to the caller's units).
    /// Directions already of unit length (to 1e-6, as normalised ones are)
    /// are used as given, so a camera's own rays are estimated exactly as
    /// it renders them.
    fn unit(&self, i: usize) -> (Ray, f32, f32) {
        let d = Vec3::from(self.directions[i]);
        let len2 = d.length_squared();
        let len = if (len2 - 1.0).abs() <= 1e-6 {
            1.0
        } else {
            len2.sqrt()
        };
        (
            Ray::new(Vec3::from(self.origins[i]), d / len),
            self.t_max[i] * len,
            len,
        )
    }
}

/// The stream of sample `j` of ray `i`.
fn stream(seed: u32, i: usize, j: u32) -> fogbank_math::Pcg32 {
    SampleKey {
        seed,
        pixel: i as u32,
        sample: j,
        dimension: dim::ESTIMATOR,
    }
    .rng()
}

/// `samples` transmittance estimates of `e` along each ray through
/// `medium`: row-major N×samples estimates and lookup counts. Stops early
/// (rows left untouched: NaN estimates) when `progress.cancel` is set.
pub fn transmittance_on_rays(
    renderer: &Renderer,
    medium: &Medium,
    e: Estimator,
    rays: Rays,
    samples: u32,
    seed: u32,
    progress: &Progress,
) -> Result<(Vec<f64>, Vec<u32>), Error> {
    rays.check(samples)?;
    let k = samples as usize;
    let mut t = vec![f64::NAN; rays.len() * k];
    let mut lookups = vec![0u32; rays.len() * k];
    renderer.install(|| {
        t.par_chunks_mut(k)
            .zip(lookups.par_chunks_mut(k))
            .enumerate()
            .for_each(|(i, (t, n))| {
                if progress.cancel.load(Ordering::Relaxed) {
                    return;
                }
                let (ray, t_max, _) = rays.unit(i);
                for j in 0..k {
                    let est = transmittance(e, medium, &ray, t_max, &mut stream(seed, i, j as u32));
                    t[j] = est.transmittance as f64;
                    n[j] = est.lookups;
                }
                progress.samples_done.fetch_add(k as u64, Ordering::Relaxed);
            })
    });
    Ok((t, lookups))
}

/// A distance sampler on the caller's rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FlightSampler {
    /// Free flight with density T(t)·σ_t(t) (weight 1): delta,
    /// decomposition or regular tracking.
    Tracking(DistanceSampler),
    /// Exact free flight of the trilinear field (grids only; weight 1).
    AnalyticTrilinear,
    /// Equiangular towards a point: t in the medium's part of the segment
    /// with density ∝ 1/(D² + (t − Δ)²), weight 1/pdf (Kulla & Fajardo
    /// 2012); never escapes while the ray crosses the medium.
    Equiangular { light: Vec3 },
}

impl FlightSampler {
    pub const NAMES: &'static str =
        "delta_tracking, decomposition_tracking, regular_tracking, analytic_trilinear or equiangular";

    /// The sampler `name`; `light` is equiangular's point.
    pub fn parse(name: &str, light: Option<[f32; 3]>) -> Result<FlightSampler, Error> {
        if let Some(s) = DistanceSampler::parse(name) {
            return Ok(FlightSampler::Tracking(s));
        }
        match (name, light) {
            ("analytic_trilinear", _) => Ok(FlightSampler::AnalyticTrilinear),
            ("equiangular", Some(l)) if l.iter().all(|x| x.is_finite()) => {
                Ok(FlightSampler::Equiangular {
                    light: Vec3::from(l),
                })
            }
            ("equiangular", _) => Err(Error::invalid(
                "sampler equiangular: give light=(x, y, z), a finite point",
            )),
            _ => Err(Error::invalid(format!(
                "unknown sampler `{name}` ({})",
                Self::NAMES
            ))),
        }
    }
}

/// One sampled distance: `t` (∞ on escape) in the caller's units, the
/// weight the sample carries and the lookups it took.
fn flight(
    s: FlightSampler,
    medium: &Medium,
    rays: &Rays,
    i: usize,
    rng: &mut fogbank_math::Pcg32,
) -> Result<(f64, f64, u32), Error> {
    let (ray, t_max, len) = rays.unit(i);
    let (t, weight, lookups) = match s {
        FlightSampler::Tracking(d) => {
            let f = sampler_flight(d, medium, &ray, t_max, rng);
            (f.t, 1.0, f.lookups)
        }
        FlightSampler::AnalyticTrilinear => {
            let Some((r, t0, t1)) = medium.to_index(&ray, 0.0, t_max) else {
                return Ok((f64::INFINITY, 1.0, 0));
            };
            let f = match medium.view() {
                MediumView::F16(v) => {
                    analytic_trilinear::sample_tracked(&v, &RaySegment::new(r, t0, t1), rng)
                        .free_flight()
                }
                MediumView::F32(v) => {
                    analytic_trilinear::sample_tracked(&v, &RaySegment::new(r, t0, t1), rng)
                        .free_flight()
                }
                MediumView::Analytic(_) => {
                    return Err(Error::invalid(
                        "sampler analytic_trilinear: the medium is analytic, not a grid",
                    ))
                }
            };
            (f.t, 1.0, f.lookups)
        }
        FlightSampler::Equiangular { light } => {
            let Some((_, t0, t1)) = medium.to_index(&ray, 0.0, t_max) else {
                return Ok((f64::INFINITY, 1.0, 0));
            };
            let (t, pdf) = equiangular::sample(&ray, light, t0, t1, rng.next_f32());
            // pdf per unit length; in the caller's units it is pdf·len.
            (Some(t), 1.0 / (pdf as f64 * len as f64), 0)
        }
    };
    let t = t.map_or(f64::INFINITY, |t| t as f64 / len as f64);
    Ok((t, weight, lookups))
}

/// Row-major N×samples free flights.
#[derive(Clone, Debug, PartialEq)]
pub struct Flights {
    /// Distances in the caller's units, ∞ on escape.
    pub t: Vec<f64>,
    /// The weight each sample carries (1 for free-flight samplers).
    pub weight: Vec<f64>,
    pub lookups: Vec<u32>,
}

/// `samples` distances of `sampler` along each ray through `medium`:
/// row-major N×samples distances (∞ on escape), weights and lookups.
pub fn sample_distance_on_rays(
    renderer: &Renderer,
    medium: &Medium,
    sampler: FlightSampler,
    rays: Rays,
    samples: u32,
    seed: u32,
    progress: &Progress,
) -> Result<Flights, Error> {
    rays.check(samples)?;
    if sampler == FlightSampler::AnalyticTrilinear
        && matches!(medium.view(), MediumView::Analytic(_))
    {
        return Err(Error::invalid(
            "sampler analytic_trilinear: the medium is analytic, not a grid",
        ));
    }
    let k = samples as usize;
    let n = rays.len() * k;
    let (mut t, mut w, mut lookups) = (vec![f64::NAN; n], vec![f64::NAN; n], vec![0u32; n]);
    renderer.install(|| {
        t.par_chunks_mut(k)
            .zip(w.par_chunks_mut(k))
            .zip(lookups.par_chunks_mut(k))
            .enumerate()
            .try_for_each(|(i, ((t, w), n))| {
                if progress.cancel.load(Ordering::Relaxed) {
                    return Ok(());
                }
                for j in 0..k {
                    (t[j], w[j], n[j]) =
                        flight(sampler, medium, &rays, i, &mut stream(seed, i, j as u32))?;
                }
                progress.samples_done.fetch_add(k as u64, Ordering::Relaxed);
                Ok::<(), Error>(())
            })
    })?;
    Ok(Flights {
        t,
        weight: w,
        lookups,
    })
}

/// The rays through the pixel centres of `scene`'s camera, row by row (ray
/// `y·width + x`), ending on its far plane: the rays a transmittance render
/// with `render.pixel_jitter = false` estimates along.
pub fn camera_rays(scene: &fogbank_render::Scene) -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<f32>) {
    let cam = &scene.camera;
    let n = cam.width as usize * cam.height as usize;
    let (mut o, mut d, mut t) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    for y in 0..cam.height {
        for x in 0..cam.width {
            let r = cam.ray(x as f32 + 0.5, y as f32 + 0.5);
            o.push(r.o.to_array());
            d.push(r.d.to_array());
            t.push(cam.ray_end(&r));
        }
    }
    (o, d, t)
}
