//! Direct lighting at a scattering vertex, shared by `direct` and `volpath`:
//! next-event estimation toward one light chosen by `LightSampler` for the
//! vertex kind (medium or surface), combined with
//! phase or BSDF sampling by the balance heuristic for lights a direction
//! can hit (environments, emitting shapes). HG sampling is exact, so the
//! phase pdf equals f.

use super::balance;
use super::free_flight::shadow_transmittance_in;
use super::tracking::Shadow;
use crate::lights::area::SHADOW_SHORTEN;
use crate::lights::sample::{LightSample, LightSampler, Vertex};
use crate::world::phase::HenyeyGreenstein;
use crate::world::surfaces::{ShadingFrame, SurfaceBsdf, SurfaceHit};
use crate::world::World;
use fogbank_math::{Pcg32, Ray, Vec3};

/// A direction sampled at a path vertex (by the phase function or a
/// non-delta BSDF lobe): the vertex, the direction's solid-angle pdf, and
/// the vertex's kind, on which the light strategy's pick probability
/// depends (MIS weights need it).
#[derive(Clone, Copy, Debug)]
pub struct SampledFrom {
    pub p: Vec3,
    pub pdf: f32,
    pub at: Vertex,
}

/// One light picked for a point of kind `at` and a sample of it seen from
/// `p`, with the pick's probability.
fn pick_light(
    world: &World,
    lights: &LightSampler,
    p: Vec3,
    at: Vertex,
    rng: &mut Pcg32,
) -> Option<(LightSample, f32)> {
    let (li, pmf) = lights.pick(rng.next_f32(), at, p)?;
    let ls = world.lights[li].sample_li(p, [rng.next_f32(), rng.next_f32()])?;
    Some((ls, pmf))
}

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
    light_sample_weighted(world, lights, nee, p, d, hg, true, None, rng, lookups)
}

/// [`light_sample`], MIS-weighted against phase sampling when `mis` is set
/// and with full weight otherwise (light sampling as the only strategy),
/// from a point in bounded medium `current`.
#[allow(clippy::too_many_arguments)]
pub fn light_sample_weighted(
    world: &World,
    lights: &LightSampler,
    nee: Shadow,
    p: Vec3,
    d: Vec3,
    hg: &HenyeyGreenstein,
    mis: bool,
    current: Option<usize>,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> Vec3 {
    let Some((ls, pmf)) = pick_light(world, lights, p, Vertex::Medium, rng) else {
        return Vec3::ZERO;
    };
    let f = hg.eval(d.dot(ls.wi));
    if f <= 0.0 || ls.radiance == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let ray = Ray::new(p, ls.wi);
    let tr = shadow_transmittance_in(nee, world, &ray, ls.distance, current, rng, lookups);
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
/// its last vertex by sampling `prev` (`None`: a camera ray or a delta
/// lobe, which no light strategy could have produced).
pub fn escaped(world: &World, lights: &LightSampler, d: Vec3, prev: Option<SampledFrom>) -> Vec3 {
    let mut l = Vec3::ZERO;
    for (li, light) in world.scene_lights() {
        if light.is_environment() {
            let w = prev.map_or(1.0, |s| {
                balance(s.pdf, lights.pmf(li, s.at, s.p) * light.pdf_li(d))
            });
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
    current: Option<usize>,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> Vec3 {
    let ray = Ray::new(p, wi);
    let prev = Some(SampledFrom {
        p,
        pdf: phase_pdf,
        at: Vertex::Medium,
    });
    sampled_direction_to_lights(world, lights, nee, &ray, prev, current, rng, lookups)
}

/// The last vertex's sampled direction (phase function or BSDF; `prev`
/// is `None` for a delta lobe) evaluated toward the lights instead of
/// traced: the first surface that is not an index-matched boundary along
/// `ray` gives its emission, or blocks; with none, the environment. The
/// transmittance up to there is estimated with the NEE estimator. `prev.p`
/// is the vertex (the ray's origin may sit just off a surface); the ray
/// starts in bounded medium `current`.
#[allow(clippy::too_many_arguments)]
pub fn sampled_direction_to_lights(
    world: &World,
    lights: &LightSampler,
    nee: Shadow,
    ray: &Ray,
    prev: Option<SampledFrom>,
    current: Option<usize>,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> Vec3 {
    if let Some(s) = &world.surfaces {
        if let Some(h) = s.intersect_opaque(ray, f32::INFINITY) {
            let Some((le, li)) = s.emitted(&h, ray.d) else {
                return Vec3::ZERO;
            };
            let w = emitter_weight(world, lights, li, h.p, ray.d, prev);
            let distance = h.t * (1.0 - SHADOW_SHORTEN);
            let tr = shadow_transmittance_in(nee, world, ray, distance, current, rng, lookups);
            return le * (w * tr);
        }
    }
    if !world.scene_lights().any(|(_, l)| l.is_environment()) {
        return Vec3::ZERO;
    }
    let le = escaped(world, lights, ray.d, prev);
    if le == Vec3::ZERO {
        return Vec3::ZERO;
    }
    le * shadow_transmittance_in(nee, world, ray, f32::INFINITY, current, rng, lookups)
}

/// MIS weight of an area light's emission reached at `q` along `d` by a
/// direction sampled at `prev`; 1 when no light strategy could have
/// produced it (camera ray, delta lobe).
pub fn emitter_weight(
    world: &World,
    lights: &LightSampler,
    li: usize,
    q: Vec3,
    d: Vec3,
    prev: Option<SampledFrom>,
) -> f32 {
    match prev {
        Some(s) if world.lights[li].is_shape() => balance(
            s.pdf,
            lights.pmf(li, s.at, s.p) * world.lights[li].pdf_solid(s.p, q, d),
        ),
        _ => 1.0,
    }
}

/// Light sampling at a surface hit: L_i f |cos θ_i| T / pdf, MIS-weighted
/// against BSDF sampling for non-delta lights when `mis` is set. The shadow
/// ray leaves from the side of the surface the light is on, in the medium
/// there (the path arrived in bounded medium `current`).
#[allow(clippy::too_many_arguments)]
pub fn light_sample_surface(
    world: &World,
    lights: &LightSampler,
    nee: Shadow,
    hit: &SurfaceHit,
    frame: &ShadingFrame,
    wo: Vec3,
    bsdf: &SurfaceBsdf,
    mis: bool,
    current: Option<usize>,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> Vec3 {
    let Some((ls, pmf)) = pick_light(world, lights, hit.p, Vertex::Surface, rng) else {
        return Vec3::ZERO;
    };
    let wi = frame.to_local(ls.wi);
    let f = bsdf.eval(wo, wi) * wi.z.abs();
    if f == Vec3::ZERO || ls.radiance == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let current = match &world.surfaces {
        Some(s) => s.target_medium(hit, ls.wi, current),
        None => current,
    };
    let ray = hit.spawn(ls.wi);
    let tr = shadow_transmittance_in(nee, world, &ray, ls.distance, current, rng, lookups);
    if ls.is_delta || !mis {
        ls.radiance * f * (tr / (pmf * if ls.is_delta { 1.0 } else { ls.pdf }))
    } else {
        let light_pdf = pmf * ls.pdf;
        ls.radiance * f * (tr * balance(light_pdf, bsdf.pdf(wo, wi)) / light_pdf)
    }
}
