//! Direct lighting at a scattering vertex, shared by `direct` and `volpath`:
//! next-event estimation toward one light chosen by power, combined with
//! phase sampling by the balance heuristic for lights a direction can hit
//! (environments). HG sampling is exact, so the phase pdf equals f.

use super::balance;
use super::free_flight::shadow_transmittance;
use super::tracking::Shadow;
use crate::lights::sample::LightSampler;
use crate::world::phase::HenyeyGreenstein;
use crate::world::World;
use fogbank_math::{Pcg32, Ray, Vec3};

/// Light-sampling strategy at `p` for a path arriving along direction `d`:
/// L_i f T̂ / pdf, MIS-weighted against phase sampling for non-delta lights.
/// The caller multiplies by the path throughput.
#[allow(clippy::too_many_arguments)]
pub fn light_sample(
    world: &World,
    lights: &LightSampler,
    nee: Shadow,
    p: Vec3,
    d: Vec3,
    hg: &HenyeyGreenstein,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> Vec3 {
    light_sample_weighted(world, lights, nee, p, d, hg, true, rng, lookups)
}

/// [`light_sample`], MIS-weighted against phase sampling when `mis` is set
/// and with full weight otherwise (light sampling as the only strategy).
#[allow(clippy::too_many_arguments)]
pub fn light_sample_weighted(
    world: &World,
    lights: &LightSampler,
    nee: Shadow,
    p: Vec3,
    d: Vec3,
    hg: &HenyeyGreenstein,
    mis: bool,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> Vec3 {
    let Some((li, pmf)) = lights.pick(rng.next_f32()) else {
        return Vec3::ZERO;
    };
    let Some(ls) = world.lights[li].sample_li(p, [rng.next_f32(), rng.next_f32()]) else {
        return Vec3::ZERO;
    };
    let f = hg.eval(d.dot(ls.wi));
    if f <= 0.0 || ls.radiance == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let tr = shadow_transmittance(nee, world, &Ray::new(p, ls.wi), ls.distance, rng, lookups);
    if ls.is_delta || !mis {
        ls.radiance * (f * tr / (pmf * if ls.is_delta { 1.0 } else { ls.pdf }))
    } else {
        let light_pdf = pmf * ls.pdf;
        ls.radiance * (f * tr * balance(light_pdf, f) / light_pdf)
    }
}

/// Σ over the delta lights of L_l f(ω_l) T(ω_l, distance) at `p`, each
/// light's direction sampled once (delta lights have no other): the direct
/// light of the deterministic evaluators (`ament`, visopt's reference).
/// `f` gives the scatter function, `tr` the transmittance toward a light.
pub fn delta_lights(
    world: &World,
    p: Vec3,
    f: impl Fn(Vec3) -> f32,
    mut tr: impl FnMut(Vec3, f32) -> f32,
) -> Vec3 {
    let mut lit = Vec3::ZERO;
    for light in &world.lights {
        let Some(ls) = light.sample_li(p, [0.5, 0.5]) else {
            continue;
        };
        let fv = f(ls.wi);
        if fv > 0.0 {
            lit += ls.radiance * fv * tr(ls.wi, ls.distance);
        }
    }
    lit
}

/// Radiance of the environment lights seen along `d` by a path that left
/// its last vertex by phase sampling with pdf `phase_pdf` (`None`: a camera
/// ray, which no light strategy could have produced).
pub fn escaped(world: &World, lights: &LightSampler, d: Vec3, phase_pdf: Option<f32>) -> Vec3 {
    let mut l = Vec3::ZERO;
    for (li, light) in world.lights.iter().enumerate() {
        if light.is_environment() {
            let w = phase_pdf.map_or(1.0, |p| balance(p, lights.pmf(li) * light.pdf_li(d)));
            l += light.le(d) * w;
        }
    }
    l
}

/// Phase-sampling strategy at a path's last vertex: the direction `wi`
/// (sampled with pdf `phase_pdf`) is not traced by free-flight sampling but
/// its transmittance to infinity is estimated with the NEE estimator, so the
/// MIS partner of [`light_sample`] is never missing.
#[allow(clippy::too_many_arguments)]
pub fn phase_sample_to_environment(
    world: &World,
    lights: &LightSampler,
    nee: Shadow,
    p: Vec3,
    wi: Vec3,
    phase_pdf: f32,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> Vec3 {
    if !world.lights.iter().any(|l| l.is_environment()) {
        return Vec3::ZERO;
    }
    let le = escaped(world, lights, wi, Some(phase_pdf));
    if le == Vec3::ZERO {
        return Vec3::ZERO;
    }
    le * shadow_transmittance(nee, world, &Ray::new(p, wi), f32::INFINITY, rng, lookups)
}
