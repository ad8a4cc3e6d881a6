//! A deterministic evaluation of what `visopt` estimates, for its
//! unbiasedness test: with the camera lists frozen
//! and light rays unoptimised, single scattering has the expectation
//!
//! ```text
//! L = ∫ₓᶻ T'(t) μ'_t(t) [(1 − a) L_e + a Σ_lights f T_l L_l] dt + T'(z) L_bg
//! ```
//!
//! with T' = exp(−∫ μ'_t) along the camera ray (Eq. 8 from the same list)
//! and T_l = exp(−∫ μ_t) toward each light. Both integrals are midpoint
//! sums with step `step` (world units); `step` small enough that halving it
//! changes nothing measurable is the test's job. Delta lights only (their
//! NEE has no directional randomness) and no environment.

use super::integrator::VisOpt;
use super::optimised::factor;
use super::params::Scattering;
use crate::integrators::shared::next_event::delta_lights;
use crate::world::World;
use fogbank_math::{Ray, Vec3};

impl VisOpt {
    /// The expected radiance of pixel (x, y)'s centre ray, or an error for
    /// settings this evaluation does not cover.
    pub fn expected_pixel(
        &self,
        world: &World,
        x: u32,
        y: u32,
        step: f32,
        shadow_step: f32,
    ) -> Result<Vec3, String> {
        if self.params.scattering != Scattering::Single
            || (self.params.optimise && self.params.light_samples > 0)
        {
            return Err("single scattering with light rays unoptimised only".into());
        }
        if world.lights.iter().any(|l| !l.is_delta()) {
            return Err("delta lights only".into());
        }
        if world.surfaces.is_some() {
            return Err("no surfaces".into());
        }
        let m = &world.media[0];
        let ray = world.camera.ray(x as f32 + 0.5, y as f32 + 0.5);
        let Some((_, t0, t1)) = m.medium.to_index(&ray, 0.0, f32::INFINITY) else {
            return Ok(Vec3::ZERO);
        };
        let (step, shadow_step) = (step / self.unit, shadow_step / self.unit);
        let list = self.lists(world).ray_list(x, y, t0);
        let n = (((t1 - t0) / step).ceil() as usize).max(1);
        let dt = (t1 - t0) / n as f32;
        let (mut tau, mut radiance) = (0.0f64, Vec3::ZERO);
        for i in 0..n {
            let s = t0 + (i as f32 + 0.5) * dt;
            let p = ray.at(s);
            let sigma = m.sigma_t_smooth(p);
            let mu = if self.params.optimise {
                sigma * factor(m, &list, self.weights(), self.unit, s, p, sigma)
            } else {
                sigma
            };
            // Exact over the step for a constant μ': T'(a)(1 − e^{−μ'Δ}).
            let t_before = (-tau).exp() as f32;
            let absorbed = t_before * (1.0 - (-(mu * dt) as f64).exp() as f32);
            tau += (mu * dt) as f64;
            if absorbed <= 0.0 {
                continue;
            }
            let albedo = m.albedo_at(p);
            let lit = delta_lights(
                world,
                p,
                |wi| self.phase(m, p, ray.d, wi),
                |wi, distance| shadow(world, &Ray::new(p, wi), distance, shadow_step),
            );
            radiance += absorbed * (m.emitted(p, albedo) + albedo * lit);
        }
        Ok(radiance)
    }
}

/// exp(−∫ μ_t) over [0, distance] of `ray` by midpoint steps.
fn shadow(world: &World, ray: &Ray, distance: f32, step: f32) -> f32 {
    let m = &world.media[0];
    let Some((_, s0, s1)) = m.medium.to_index(ray, 0.0, distance) else {
        return 1.0;
    };
    let n = (((s1 - s0) / step).ceil() as usize).max(1);
    let ds = (s1 - s0) / n as f32;
    let tau: f64 = (0..n)
        .map(|i| (m.sigma_t_smooth(ray.at(s0 + (i as f32 + 0.5) * ds)) * ds) as f64)
        .sum();
    (-tau).exp() as f32
}
