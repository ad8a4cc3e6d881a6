//! `restir`'s WGSL: the scattering prelude without the per-sample entry
//! point, then its passes, one file each under `wgsl/`.

use crate::shaders;

const PARAMS: &str = include_str!("wgsl/params.wgsl");
const RESERVOIR: &str = include_str!("wgsl/reservoir.wgsl");
const VOLUME: &str = include_str!("wgsl/volume.wgsl");
const SURFACE: &str = include_str!("wgsl/surface.wgsl");
const TARGET: &str = include_str!("wgsl/target.wgsl");
const CANDIDATES: &str = include_str!("wgsl/candidates.wgsl");
const COMBINE: &str = include_str!("wgsl/combine.wgsl");
const TEMPORAL: &str = include_str!("wgsl/temporal.wgsl");
const SPATIAL: &str = include_str!("wgsl/spatial.wgsl");
const SHADE: &str = include_str!("wgsl/shade.wgsl");

/// The scattering prelude without the per-sample entry point, then the
/// passes (entry points `candidates`, `reproject`, `temporal`, `spatial`,
/// `shade`, `reduce`).
pub(crate) fn source() -> String {
    [
        &shaders::estimators(),
        shaders::FRAME,
        shaders::PHASE,
        shaders::LIGHTS,
        shaders::SHAPE_LIGHTS,
        shaders::PROPERTIES,
        shaders::LIGHT_BVH,
        shaders::DISTANCE_TRILINEAR,
        &shaders::surfaces(),
        shaders::OCCLUDERS,
        PARAMS,
        RESERVOIR,
        VOLUME,
        SURFACE,
        TARGET,
        CANDIDATES,
        COMBINE,
        TEMPORAL,
        SPATIAL,
        SHADE,
    ]
    .join("\n")
}

