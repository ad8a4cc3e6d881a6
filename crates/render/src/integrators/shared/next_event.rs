//! Direct lighting at a scattering vertex, shared by `direct` and `volpath`:
//! next-event estimation toward one light chosen by `LightSampler` for the
//! vertex kind (medium or surface), combined with
//! phase or BSDF sampling by the balance heuristic for lights a direction
//! can hit (environments, emitting shapes). HG sampling is exact, so the
//! phase pdf equals f.

use super::balance;
use super::context::{MediumVertex, NextEvent, PathContext, SurfaceVertex};
use super::free_flight::{shadow_transmittance_in, ShadowSpan};
use crate::lights::area::SHADOW_SHORTEN;
use crate::lights::sample::{LightSample, LightSampler, Vertex};
use crate::world::World;
use fogbank_math::{Ray, Vec3};

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
    cx: &mut PathContext,
    lights: &LightSampler,
    p: Vec3,
    at: Vertex,
) -> Option<(LightSample, f32)> {
    let (li, pmf) = lights.pick(cx.next_f32(), at, p)?;
    let ls = cx.world.lights[li].sample_li(p, cx.next_2d())?;
    Some((ls, pmf))
}

/// Light-sampling strategy at medium vertex `v`: L_i f T̂ / pdf,
/// MIS-weighted against phase sampling for non-delta lights when `nee.mis`
/// is set and with full weight otherwise (light sampling as the only
/// strategy). The caller multiplies by the path throughput.
pub fn light_sample(cx: &mut PathContext, nee: &NextEvent, v: &MediumVertex) -> Vec3 {
    let Some((ls, pmf)) = pick_light(cx, nee.lights, v.p, Vertex::Medium) else {
        return Vec3::ZERO;
    };
    let f = v.phase.eval(v.d.dot(ls.wi));
    if f <= 0.0 || ls.radiance == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let ray = Ray::new(v.p, ls.wi);
    let tr = shadow_transmittance_in(cx, nee.shadow, ShadowSpan::new(ray, ls.distance, v.medium));
    if ls.is_delta || !nee.mis {
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

/// Phase-sampling strategy at a path's last vertex `v`: the direction `wi`
/// (sampled with pdf `phase_pdf`) is not traced by free-flight sampling but
/// its transmittance to infinity is estimated with the NEE estimator, so the
/// MIS partner of [`light_sample`] is never missing.
pub fn phase_sample_to_environment(
    cx: &mut PathContext,
    nee: &NextEvent,
    v: &MediumVertex,
    wi: Vec3,
    phase_pdf: f32,
) -> Vec3 {
    let ray = Ray::new(v.p, wi);
    let prev = Some(SampledFrom {
        p: v.p,
        pdf: phase_pdf,
        at: Vertex::Medium,
    });
    sampled_direction_to_lights(cx, nee, &ray, prev, v.medium)
}

/// The last vertex's sampled direction (phase function or BSDF; `prev`
/// is `None` for a delta lobe) evaluated toward the lights instead of
/// traced: the first surface that is not an index-matched boundary along
/// `ray` gives its emission, or blocks; with none, the environment. The
/// transmittance up to there is estimated with the NEE estimator. `prev.p`
/// is the vertex (the ray's origin may sit just off a surface); the ray
/// starts in bounded medium `current`.
pub fn sampled_direction_to_lights(
    cx: &mut PathContext,
    nee: &NextEvent,
    ray: &Ray,
    prev: Option<SampledFrom>,
    current: Option<usize>,
) -> Vec3 {
    let world = cx.world;
    if let Some(s) = &world.surfaces {
        if let Some(h) = s.intersect_opaque(ray, f32::INFINITY) {
            let Some((le, li)) = s.emitted(&h, ray.d) else {
                return Vec3::ZERO;
            };
            let w = emitter_weight(world, nee.lights, li, h.p, ray.d, prev);
            let distance = h.t * (1.0 - SHADOW_SHORTEN);
            let tr =
                shadow_transmittance_in(cx, nee.shadow, ShadowSpan::new(*ray, distance, current));
            return le * (w * tr);
        }
    }
    if !world.scene_lights().any(|(_, l)| l.is_environment()) {
        return Vec3::ZERO;
    }
    let le = escaped(world, nee.lights, ray.d, prev);
    if le == Vec3::ZERO {
        return Vec3::ZERO;
    }
    le * shadow_transmittance_in(
        cx,
        nee.shadow,
        ShadowSpan::new(*ray, f32::INFINITY, current),
    )
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

/// Light sampling at surface vertex `v`: L_i f |cos θ_i| T / pdf,
/// MIS-weighted against BSDF sampling for non-delta lights when `nee.mis`
/// is set. The shadow ray leaves from the side of the surface the light is
/// on, in the medium there.
pub fn light_sample_surface(cx: &mut PathContext, nee: &NextEvent, v: &SurfaceVertex) -> Vec3 {
    let hit = v.hit;
    let Some((ls, pmf)) = pick_light(cx, nee.lights, hit.p, Vertex::Surface) else {
        return Vec3::ZERO;
    };
    let wi = v.frame.to_local(ls.wi);
    let f = v.bsdf.eval(v.wo, wi) * wi.z.abs();
    if f == Vec3::ZERO || ls.radiance == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let current = match &cx.world.surfaces {
        Some(s) => s.target_medium(hit, ls.wi, v.medium),
        None => v.medium,
    };
    let ray = hit.spawn(ls.wi);
    let tr = shadow_transmittance_in(cx, nee.shadow, ShadowSpan::new(ray, ls.distance, current));
    if ls.is_delta || !nee.mis {
        ls.radiance * f * (tr / (pmf * if ls.is_delta { 1.0 } else { ls.pdf }))
    } else {
        let light_pdf = pmf * ls.pdf;
        ls.radiance * f * (tr * balance(light_pdf, v.bsdf.pdf(v.wo, wi)) / light_pdf)
    }
}
