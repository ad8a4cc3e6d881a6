//! One [`LightGpu`] record per light, packed per kind as `lights.wgsl`
//! (`light_sample_li`, `light_le`) and `shape_lights.wgsl` read it. Every
//! record starts with the kind's id (`contract::light_id`), its bit trail
//! in the light BVH and its selection CDF entries; the four-float slots
//! `a`–`e` hold, by kind:
//!
//! | kind | a | b | c | d.xy | e |
//! |---|---|---|---|---|---|
//! | constant | – | (radiance, 0) | – | – | – |
//! | envmap | – | – | – | – | – (the map is [`super::environment`]) |
//! | point | (position, 1) | (intensity, 0) | – | – | – |
//! | directional | (direction, 0) | (irradiance, 0) | – | – | – |
//! | spot | (position, 1) | (intensity, 0) | (direction, curve id) | cos falloff start, cos total | – |
//! | area triangle | (p0, area) | (radiance, 0) | (edge 1, side) | – | (edge 2, 0) |
//! | disk | (centre, area) | (radiance, 0) | (half-axis u, side) | – | (half-axis v, 0) |
//! | sphere | (centre, radius) | (radiance, 0) | (0, 0, 0, inward) | – | – |
//!
//! `d.zw` is the selection CDF entry and pmf for points in media; "side"
//! is the sign of n · (a × b), the emitting side.

use crate::contract::v4;
use bytemuck::{Pod, Zeroable};
use fogbank_render::lights::Light;
use glam::Vec3;

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct LightGpu {
    pub(crate) kind: u32,
    /// Emitting triangles in the light BVH: the bit trail from its root
    /// (`LightBvh::trails`).
    pub(crate) trail: u32,
    /// `LightSampler`'s CDF entry and pmf for points on surfaces (`d.zw`:
    /// for points in media).
    pub(crate) surface: [f32; 2],
    pub(crate) a: [f32; 4],
    pub(crate) b: [f32; 4],
    pub(crate) c: [f32; 4],
    pub(crate) d: [f32; 4],
    pub(crate) e: [f32; 4],
}

/// What every record carries whatever its kind: the trail in the light BVH
/// and the selection CDF entry and pmf for points in media and on surfaces.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Selection {
    pub(crate) trail: u32,
    pub(crate) medium: [f32; 2],
    pub(crate) surface: [f32; 2],
}

/// The record of light `l` (the table in the module doc).
pub(crate) fn pack(l: &Light, selection: Selection) -> LightGpu {
    let mut r = LightGpu {
        kind: crate::contract::light_id(l),
        trail: selection.trail,
        surface: selection.surface,
        d: [0.0, 0.0, selection.medium[0], selection.medium[1]],
        ..LightGpu::zeroed()
    };
    match l {
        Light::Constant { radiance } => r.b = v4(*radiance, 0.0),
        Light::Envmap(_) => {}
        Light::Point {
            position,
            intensity,
        } => (r.a, r.b) = (v4(*position, 1.0), v4(*intensity, 0.0)),
        Light::Directional {
            direction,
            irradiance,
        } => (r.a, r.b) = (v4(*direction, 0.0), v4(*irradiance, 0.0)),
        Light::Spot {
            position,
            direction,
            intensity,
            cos_falloff_start,
            cos_total,
            curve,
        } => {
            (r.a, r.b) = (v4(*position, 1.0), v4(*intensity, 0.0));
            r.c = v4(*direction, *curve as u32 as f32);
            (r.d[0], r.d[1]) = (*cos_falloff_start, *cos_total);
        }
        Light::Area(t) => flat(&mut r, [t.p0, t.e1, t.e2, t.n], t.area, t.radiance),
        Light::Disk(l) => flat(&mut r, [l.centre, l.u, l.v, l.n], l.area, l.radiance),
        Light::Sphere(l) => {
            (r.a, r.b) = (v4(l.centre, l.radius), v4(l.radiance, 0.0));
            r.c = [0.0, 0.0, 0.0, l.inward as u32 as f32];
        }
    }
    r
}

/// A flat emitter (triangle, disk) as `shape_lights.wgsl` reads it: origin
/// and area, its two edges or half-axes, and the emitting side `n`
/// relative to their cross product.
fn flat(r: &mut LightGpu, [o, a, b, n]: [Vec3; 4], area: f32, radiance: Vec3) {
    r.a = v4(o, area);
    r.b = v4(radiance, 0.0);
    r.c = v4(a, n.dot(a.cross(b)).signum());
    r.e = v4(b, 0.0);
}
