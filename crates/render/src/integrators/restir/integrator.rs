//! The built `restir` integrator: its parameters with the scene's mips and
//! light selection, the reuse target p̂ and final shading. The passes are
//! `impl Restir` blocks in their own files.

use super::params::RestirParams;
use super::path::PathSample;
use super::primary::PrimaryT;
use super::reservoir::Reservoir;
use super::target::{evaluate, luminance};
use super::volume::{Mips, SegmentT};
use crate::error::SceneError;
use crate::integrators::plugin::Integrator;
use crate::integrators::shared::{estimator_rng, occluders, PixelSample};
use crate::lights::sample::LightSampler;
use crate::world::World;
use fogbank_estimators::estimator::AnalyticTrilinear;
use fogbank_estimators::Estimator;
use fogbank_math::{Pcg32, Ray, SampleKey, Vec3};
use fogbank_volume::DensityData;

/// Shapes join paths as surface vertices ([`super::surface`]) when no
/// BSDF has a delta lobe (paths end by light sampling alone) and under
/// direction reuse (a vertex kept fixed on a surface would need its area
/// measure).
fn surfaces_check(world: &World, p: &RestirParams) -> Result<(), SceneError> {
    let Some(s) = &world.surfaces else {
        return Ok(());
    };
    if let Some(i) = s
        .shapes
        .iter()
        .position(|sh| !sh.material.passes_light() && sh.material.has_delta_lobe())
    {
        return Err(SceneError(format!(
            "integrator \"restir\" ends paths by light sampling alone, which cannot follow the smooth (delta) lobe of shapes.{i}'s BSDF; make it rough (roughplastic, roughconductor, roughdielectric) or diffuse, or use volpath"
        )));
    }
    if p.vertex_reuse {
        return Err(SceneError(
            "integrator \"restir\": shift = \"vertex\" keeps vertices fixed in space, which on surfaces is not built; use the default direction shift with shapes".into(),
        ));
    }
    Ok(())
}

/// What a frame's passes read: the world of that frame, its medium's mips
/// and its light selection, and (built by [`super::frame::Sequence`]) the
/// reuse T̃ of its pixels' primary rays.
#[derive(Clone, Copy)]
pub struct FrameData<'a> {
    pub world: &'a World,
    pub mips: &'a Mips,
    pub lights: &'a LightSampler,
    pub primary: Option<&'a PrimaryT>,
}

/// The ray through the centre of pixel `(x, y)`: ReSTIR's passes reuse one
/// path per pixel across passes and frames, so its camera rays are not
/// jittered.
pub fn pixel_ray(world: &World, (x, y): (u32, u32)) -> Ray {
    world.camera.ray(x as f32 + 0.5, y as f32 + 0.5)
}

/// The built integrator (for the scene's world as built).
#[derive(Clone, Debug)]
pub struct Restir {
    pub params: RestirParams,
    pub mips: Mips,
    pub lights: LightSampler,
}

impl Restir {
    pub fn new(p: &RestirParams, world: &World) -> Result<Restir, SceneError> {
        if world.media.len() != 1 {
            return Err(SceneError(format!(
                "integrator \"restir\" renders scenes with exactly one medium (this one has {})",
                world.media.len()
            )));
        }
        occluders::check(world, "restir")?;
        surfaces_check(world, p)?;
        let m = &world.media[0].medium;
        if matches!(m.data, DensityData::Analytic(_)) {
            return Err(SceneError(
                "integrator \"restir\" needs a voxel grid (its mips); procedural \"cloud\" and \"explosion\" and files are grids, analytic media are not".into(),
            ));
        }
        if m.opacity.is_some() {
            return Err(SceneError(
                "integrator \"restir\" does not classify: its mips hold extinction, so give the medium's transfer `mode = \"pre\"` or use volpath".into(),
            ));
        }
        let mut params = p.clone();
        // §5.3: Q = 10 with surfaces.
        params.temporal_cap =
            Some(
                p.temporal_cap
                    .unwrap_or(if world.surfaces.is_some() { 10.0 } else { 4.0 }),
            );
        Ok(Restir {
            params,
            mips: Mips::build(m, p.reuse_bc4.then_some(p.reuse_mip))?,
            lights: LightSampler::new(&world.lights, world.radius(), world.light_selection),
        })
    }

    /// The frame data of the scene's own (static) world.
    pub fn data<'a>(&'a self, world: &'a World) -> FrameData<'a> {
        FrameData {
            world,
            mips: &self.mips,
            lights: &self.lights,
            primary: None,
        }
    }

    /// The reuse target p̂ of the pixel with primary ray `ray` at path `y`:
    /// luminance of the path with T̃ marched on mip `reuse_mip` (§4.3, §5.1).
    /// With the pixel's index (`ray` its centre ray) and the frame's
    /// primary-ray tables, the first segment's T̃ comes from the table (the
    /// same value).
    pub fn p_hat(
        &self,
        data: &FrameData,
        pixel: Option<usize>,
        ray: &Ray,
        y: &PathSample,
        lookups: &mut u32,
    ) -> f32 {
        let full = &data.world.media[0].medium;
        let mut tr = SegmentT::Marched {
            medium: data.mips.reuse(full, self.params.reuse_mip),
            step: self.params.reuse_step,
            primary: data.primary.zip(pixel),
        };
        luminance(evaluate(data.world, ray, y, &mut tr, lookups)).max(0.0)
    }

    /// Final shading (Eq. 21): F(y)·W with unbiased transmittance on every
    /// segment at full resolution.
    pub fn shade(
        &self,
        data: &FrameData,
        ray: &Ray,
        res: &Reservoir<PathSample>,
        rng: &mut Pcg32,
        lookups: &mut u32,
    ) -> Vec3 {
        let (Some(y), w) = (res.y, res.contribution_weight()) else {
            return Vec3::ZERO;
        };
        if w <= 0.0 {
            return Vec3::ZERO;
        }
        let mut tr = match self.params.estimator {
            Estimator::AnalyticTrilinear(AnalyticTrilinear) => SegmentT::Exact,
            estimator => SegmentT::Estimated { estimator, rng },
        };
        evaluate(data.world, ray, &y, &mut tr, lookups) * w
    }
}

impl Integrator for Restir {
    /// One pixel without reuse (plain RIS over M walks, then shading): what
    /// a per-pixel caller gets; reuse needs whole frames ([`super::frame::Sequence`]).
    fn sample(&self, world: &World, x: u32, y: u32, key: SampleKey) -> PixelSample {
        let data = self.data(world);
        let mut rng = estimator_rng(key);
        let ray = pixel_ray(world, (x, y));
        let mut lookups = 0;
        let res = self.candidates(&data, None, &ray, &mut rng, &mut lookups);
        let radiance = self.shade(&data, &ray, &res, &mut rng, &mut lookups);
        PixelSample { radiance, lookups }
    }

    fn estimator(&self) -> Option<Estimator> {
        Some(self.params.estimator)
    }

    fn estimator_mut(&mut self) -> Option<&mut Estimator> {
        Some(&mut self.params.estimator)
    }
}
