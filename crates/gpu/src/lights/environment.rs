//! The environment map and the light table's header (`EnvParams`, the
//! uniform `lights.wgsl` reads first): the map's size, integral and
//! world-to-map rotation, how many lights there are and which of them may
//! be environments, where the medium records, the blackbody table and the
//! light BVH start in the `shading` buffer.

use crate::contract::v4;
use crate::GpuError;
use bytemuck::{Pod, Zeroable};
use fogbank_render::lights::Light;
use fogbank_render::Scene;

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct EnvParams {
    pub(crate) to_local: [[f32; 4]; 3],
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) light_count: u32,
    pub(crate) integral: f32,
    pub(crate) pickable: u32,
    /// Where the medium extensions and the blackbody table start in the
    /// `shading` buffer (after one (albedo, g) per medium).
    pub(crate) props_ext: u32,
    pub(crate) props_blackbody: u32,
    /// Lights before this index may be environments (none after: the
    /// emitting triangles of shapes follow the scene's lights).
    pub(crate) environments: u32,
    /// 1: read the map bilinearly (Mitsuba's lookup).
    pub(crate) bilinear: u32,
    /// Lights from this index on are picked through the light BVH
    /// (`light_count`: no tree), whose nodes start at this vec4 of the
    /// `shading` buffer.
    pub(crate) bvh_first: u32,
    pub(crate) bvh_nodes: u32,
    pub(crate) pad: u32,
}

/// The environment map's texels (RGB + pad) and its sampling CDFs; a
/// one-texel black map without one.
pub(crate) struct EnvMap {
    pub(crate) rgb: Vec<[f32; 4]>,
    pub(crate) cdf: Vec<f32>,
}

/// The header for `scene` (`pickable`: whether any light can be picked)
/// and its environment map; the GPU takes one map per scene.
pub(crate) fn environment(scene: &Scene, pickable: bool) -> Result<(EnvParams, EnvMap), GpuError> {
    let mut env = EnvParams {
        to_local: [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ],
        width: 1,
        height: 1,
        light_count: scene.lights.len() as u32,
        integral: 0.0,
        pickable: pickable as u32,
        props_ext: scene.media.len() as u32,
        props_blackbody: 4 * scene.media.len() as u32,
        environments: scene
            .lights
            .iter()
            .rposition(|l| l.is_environment())
            .map_or(0, |i| i as u32 + 1),
        bilinear: 0,
        bvh_first: scene.lights.len() as u32,
        bvh_nodes: 0,
        pad: 0,
    };
    let mut map = EnvMap {
        rgb: vec![[0.0f32; 4]],
        cdf: vec![0.0f32, 1.0, 0.0, 1.0],
    };
    let mut maps = scene
        .lights
        .iter()
        .enumerate()
        .filter_map(|(i, l)| match l {
            Light::Envmap(e) => Some((i, e)),
            _ => None,
        });
    if let Some((_, e)) = maps.next() {
        let (rgb, cdf, to_local, integral) = e.gpu_layout();
        env.width = e.width() as u32;
        env.height = e.height() as u32;
        env.integral = integral;
        env.bilinear = e.is_bilinear() as u32;
        env.to_local = [
            v4(to_local.row(0), 0.0),
            v4(to_local.row(1), 0.0),
            v4(to_local.row(2), 0.0),
        ];
        map = EnvMap { rgb, cdf };
    }
    if let Some((i, _)) = maps.next() {
        return Err(GpuError(format!(
            "lights.{i}: the GPU backend takes one environment map per scene"
        )));
    }
    Ok((env, map))
}
