//! The path integrand F and the target p̂ (Lin et al. 2021 Eq. 12–15, 22–23): one
//! evaluation of a stored path along a pixel's primary ray, parameterised by
//! how segments are attenuated. With T̃ (deterministic marching of mip 1)
//! its luminance is the reuse target p̂ (§4.3), a deterministic function of
//! the path and the pixel; with the exact T it is F, used once per pixel in
//! final shading (§4.1, §5.1).
//!
//! Vertex σ_s and σ_a are the full-resolution trilinear values F uses, so
//! p̂ = 0 exactly where F = 0 (checklist, open choices). A shifted vertex
//! outside the medium or at zero density makes the path worth nothing, and
//! so does a segment a surface cuts (both F and p̂ carry the visibility).

use super::path::{PathEnd, PathSample};
use super::surface::SurfaceVertex;
use super::volume::{sigma_t, SegmentT};
use crate::integrators::shared::occluders::visible;
use crate::lights::Light;
use crate::world::World;
use fogbank_math::{Ray, Vec3};

/// Rec. 709 luminance: the scalar target of §6.2.
#[inline]
pub fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// Where light `l` is seen from `x`: (direction, radiance arriving at x
/// before attenuation, distance). Environment and directional lights keep
/// the stored direction `dir` (§4.2), positional lights their position,
/// emitting shapes the stored point `q` on them, in its area measure.
pub fn light_towards(l: &Light, x: Vec3, dir: Vec3, q: Vec3) -> Option<(Vec3, Vec3, f32)> {
    if l.is_environment() {
        return Some((dir, l.le(dir), f32::INFINITY));
    }
    if l.is_shape() {
        return l.toward_point(x, q);
    }
    // Positional and directional lights ignore the random numbers.
    l.sample_li(x, [0.5, 0.5])
        .map(|s| (s.wi, s.radiance, s.distance))
}

/// Radiance of every environment light along `d`.
pub fn environment(world: &World, d: Vec3) -> Vec3 {
    world
        .lights
        .iter()
        .filter(|l| l.is_environment())
        .map(|l| l.le(d))
        .sum()
}

/// The path's contribution along `ray0` (a pixel's primary ray, unit
/// direction) in `world`, each segment attenuated by `tr`: F with the exact
/// T, the reuse target's RGB with T̃.
pub fn evaluate(
    world: &World,
    ray0: &Ray,
    y: &PathSample,
    tr: &mut SegmentT,
    lookups: &mut u32,
) -> Vec3 {
    let m = &world.media[0];
    let full = &m.medium;
    if y.end == PathEnd::Background {
        return background(world, ray0, tr, lookups);
    }
    let hg = m.phase;
    let k = y.k as usize;
    let (mut x, mut d) = (ray0.o, ray0.d);
    // The current vertex when it lies on a surface.
    let mut at: Option<SurfaceVertex> = None;
    let mut f = Vec3::ONE;
    for i in 0..k {
        let last = i + 1 == k;
        // Segment i: from x_i along ω_i to x_{i+1}.
        let Some((next_d, z, g)) = segment(y, i, x, d) else {
            return Vec3::ZERO;
        };
        if i > 0 {
            f *= match &at {
                Some(v) => v.scatter(d, next_d),
                None => Vec3::splat(hg.pdf(-d, next_d)),
            };
        }
        d = next_d;
        let seg = at.map_or(Ray::new(x, d), |v| v.leave(d));
        if y.on_surface(i) {
            // The closest surface along the segment (§4.2).
            let Some(v) = SurfaceVertex::closest(world, &seg) else {
                return Vec3::ZERO;
            };
            let t = if i == 0 {
                tr.eval_primary(full, &seg, v.hit.t, lookups)
            } else {
                tr.eval(full, &seg, v.hit.t, lookups)
            };
            f *= t;
            if last && y.end == PathEnd::Emission {
                f *= v.emitted(world, d);
            }
            x = v.hit.p;
            at = Some(v);
        } else {
            if !visible(world, &seg, z) {
                return Vec3::ZERO;
            }
            x = seg.at(z);
            let sigma = sigma_t(full, x);
            if sigma <= 0.0 {
                return Vec3::ZERO;
            }
            let albedo = m.albedo_at(x);
            let t = if i == 0 {
                tr.eval_primary(full, &seg, z, lookups)
            } else {
                tr.eval(full, &seg, z, lookups)
            };
            f *= g * t;
            if last && y.end == PathEnd::Emission {
                f *= m.emitted(x, albedo) * sigma;
            } else {
                f *= albedo * sigma;
            }
            at = None;
        }
        if f == Vec3::ZERO {
            return Vec3::ZERO;
        }
    }
    if y.end == PathEnd::Light {
        f *= light_end(world, y, (x, d, at.as_ref()), tr, lookups);
    }
    f
}

/// The environment behind the medium along a primary ray that escapes
/// (Eq. 1, second term), attenuated by `tr`.
fn background(world: &World, ray0: &Ray, tr: &mut SegmentT, lookups: &mut u32) -> Vec3 {
    let full = &world.media[0].medium;
    let le = environment(world, ray0.d);
    if le == Vec3::ZERO || !visible(world, ray0, f32::INFINITY) {
        return Vec3::ZERO;
    }
    le * tr.eval_primary(full, ray0, f32::INFINITY, lookups)
}

/// The light-sampled end of path `y` at its last vertex `x` (reached along
/// `d`, on surface `at` or in the medium): L_i times the scatter function
/// times the shadow segment's transmittance.
fn light_end(
    world: &World,
    y: &PathSample,
    (x, d, at): (Vec3, Vec3, Option<&SurfaceVertex>),
    tr: &mut SegmentT,
    lookups: &mut u32,
) -> Vec3 {
    let (hg, full) = (world.media[0].phase, &world.media[0].medium);
    let Some(l) = world.lights.get(y.light as usize) else {
        return Vec3::ZERO;
    };
    let Some((wi, li, dist)) = light_towards(l, x, y.light_dir, y.light_point) else {
        return Vec3::ZERO;
    };
    let scatter = match at {
        Some(v) => v.scatter(d, wi),
        None => Vec3::splat(hg.pdf(-d, wi)),
    };
    let shadow = at.map_or(Ray::new(x, wi), |v| v.leave(wi));
    if scatter == Vec3::ZERO || li == Vec3::ZERO || !visible(world, &shadow, dist) {
        return Vec3::ZERO;
    }
    li * scatter * tr.eval(full, &shadow, dist, lookups)
}

/// Segment `i` of path `y` leaving `x` (reached along `d`): its direction,
/// length and the 1/z² of a fixed end (1 otherwise); `None` when a fixed
/// end coincides with `x`.
///
/// On the path's own vertices (its own pixel, or a shift that left x_i in
/// place) the stored ω_i and z_{i+1} rebuild x_{i+1} exactly as the
/// candidate pass found it, so F and p̂ agree with the candidate's weights
/// bit for bit; positions subtracted in f32 would not for tiny segments,
/// where 1/z² amplifies the rounding.
fn segment(y: &PathSample, i: usize, x: Vec3, d: Vec3) -> Option<(Vec3, f32, f32)> {
    let own = i >= 1 && x == y.x[i - 1];
    if y.is_fixed(i) && own {
        Some((y.dir[i - 1], y.z[i], 1.0 / (y.z[i] * y.z[i])))
    } else if y.is_fixed(i) {
        let v = y.x[i] - x;
        let z = v.length();
        if z.is_nan() || z <= 0.0 {
            return None;
        }
        Some((v / z, z, 1.0 / (z * z)))
    } else {
        Some((if i == 0 { d } else { y.dir[i - 1] }, y.z[i], 1.0))
    }
}
