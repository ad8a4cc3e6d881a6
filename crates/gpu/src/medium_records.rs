//! Each scene medium's shading record, as `properties.wgsl` reads it from
//! the `shading` buffer: one (albedo, g) vec4 per medium, then three vec4s
//! per medium of its property grids, emission and chromatic channels, then
//! the blackbody table. The grids themselves are records of the media
//! buffer ([`crate::scene_buffers`]); [`MediumGrids`] says where.

use crate::contract::v4;
use fogbank_render::world::emission::Emission;
use fogbank_render::world::medium::SceneMedium;
use fogbank_render::Scene;
use glam::Vec3;

/// Where a scene medium's property grids are in the media buffer (record
/// index + 1; 0: none).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MediumGrids {
    /// The albedo grid's first channel record + 1, and its channel count.
    pub albedo: u32,
    pub albedo_channels: u32,
    /// The emission colour or temperature grid's record + 1.
    pub emission: u32,
    /// The first of the chromatic channels' media + 1, and 1 when their
    /// ratios k vary in space.
    pub chroma: u32,
    pub chroma_varies: u32,
}

/// The `shading` buffer's medium part: (albedo, g) per medium, the
/// extensions (from `EnvParams::props_ext`) and the blackbody table (from
/// `props_blackbody`), in one binding because storage bindings per stage
/// are few.
pub(crate) fn shading_records(scene: &Scene, grids: &[MediumGrids]) -> Vec<[f32; 4]> {
    let mut shading: Vec<[f32; 4]> = (scene.media.iter())
        .map(|m| v4(Vec3::from(m.albedo), m.phase.g))
        .collect();
    for (m, g) in scene.media.iter().zip(grids) {
        shading.extend(extension(m, g));
    }
    shading.extend(blackbody_table());
    shading
}

/// A medium's three extension vec4s, small integers as exact floats:
/// (albedo grid + 1, its channels, emission kind, emission grid + 1),
/// (radiance, temperature scale), (temperature offset, chromatic channels'
/// first record + 1, 1 when their k varies, 0). Emission kind: 0 none,
/// 1 colour, 2 blackbody.
fn extension(m: &SceneMedium, g: &MediumGrids) -> [[f32; 4]; 3] {
    let kind = crate::contract::emission_id(m.emission.as_ref()) as f32;
    let (radiance, scale, offset) = match &m.emission {
        None => (Vec3::ZERO, 1.0, 0.0),
        Some(Emission::Color { radiance, .. }) => (*radiance, 1.0, 0.0),
        Some(Emission::Blackbody {
            radiance,
            scale,
            offset,
            ..
        }) => (*radiance, *scale, *offset),
    };
    [
        [
            g.albedo as f32,
            g.albedo_channels as f32,
            kind,
            g.emission as f32,
        ],
        v4(radiance, scale),
        [offset, g.chroma as f32, g.chroma_varies as f32, 0.0],
    ]
}

/// (first temperature, step, entries, 0), then the RGB of each entry.
fn blackbody_table() -> Vec<[f32; 4]> {
    let (bb_min, bb_step, bb) = fogbank_render::world::blackbody::blackbody_table();
    let mut table: Vec<[f32; 4]> = vec![[bb_min, bb_step, bb.len() as f32, 0.0]];
    table.extend(bb.iter().map(|c| v4(*c, 0.0)));
    table
}
