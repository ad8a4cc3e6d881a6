//! OpenVDB grid → fogbank brick grid.
//!
//! OpenVDB puts a voxel's value at its integer index coordinate; fogbank puts
//! it at the cell centre. The brick grid therefore starts at the active box's
//! minimum less a one-voxel apron of background (so clamped lookups reproduce
//! the background outside), rounded down to a multiple of 8 so that every
//! OpenVDB leaf becomes exactly one brick, and the index→world map gains a
//! translation by `origin − ½`.

use super::vdb::{GridClass, VdbGrid};
use crate::grid::{BrickGrid, BRICK};
use crate::grid_builder::BrickGridBuilder;
use crate::{Result, VolumeError};
use fogbank_math::{DAffine3, DVec3};
use glam::DMat3;

/// Converts `g`; returns the grid and its index→world transform.
pub fn to_brick_grid(g: VdbGrid) -> Result<(BrickGrid<f32>, DAffine3)> {
    let (b, xf) = to_builder(g)?;
    Ok((b.finish(), xf))
}

/// The builder of `g`'s brick grid, consuming `g`: each leaf's values
/// become their brick's in place (reordered, non-finite values zeroed), so
/// the voxels exist once; finish it with the values' map and precision
/// ([`BrickGridBuilder::finish_converted`]).
pub fn to_builder(g: VdbGrid) -> Result<(BrickGridBuilder, DAffine3)> {
    let (mut b, origin, xf) = outline_builder(&g, g.leaves.iter().map(|l| l.origin))?;
    for leaf in g.leaves {
        let mut values = leaf.values;
        brick_order(&mut values);
        b.adopt(leaf_lo(leaf.origin, origin), values);
    }
    Ok((b, xf))
}

/// The builder of the brick grid of `g`'s tiles and of leaves at
/// `leaf_origins` (`g.leaves` is not read), with the tiles written; the
/// OpenVDB index of the grid's voxel 0 and the index→world map.
pub(crate) fn outline_builder(
    g: &VdbGrid,
    leaf_origins: impl Iterator<Item = [i32; 3]>,
) -> Result<(BrickGridBuilder, [i64; 3], DAffine3)> {
    let mut lo = [i64::MAX; 3];
    let mut hi = [i64::MIN; 3];
    let mut grow = |a: [i32; 3], size: i64| {
        for k in 0..3 {
            lo[k] = lo[k].min(a[k] as i64);
            hi[k] = hi[k].max(a[k] as i64 + size - 1);
        }
    };
    for origin in leaf_origins {
        grow(origin, BRICK as i64);
    }
    for t in &g.tiles {
        if t.active || t.value != g.background {
            grow(t.origin, t.size as i64);
        }
    }
    if lo[0] > hi[0] {
        return Err(VolumeError::Invalid(format!(
            "grid `{}` holds no voxels",
            g.name
        )));
    }
    let origin = lo.map(|v| (v - 1).div_euclid(BRICK as i64) * BRICK as i64);
    let dims: [u64; 3] = std::array::from_fn(|k| (hi[k] + 1 - origin[k] + 1) as u64);
    let mut b = BrickGridBuilder::new(dims, g.background)
        .map_err(|e| VolumeError::Invalid(format!("grid `{}`: {e}", g.name)))?;
    // Tiles and leaves never overlap in a valid tree; tiles go first.
    for t in &g.tiles {
        if t.value != g.background {
            let a = std::array::from_fn(|k| t.origin[k] as i64 - origin[k]);
            let z = std::array::from_fn(|k| a[k] + t.size as i64 - 1);
            b.fill(a, z, t.value);
        }
    }
    Ok((b, origin, index_to_world(&g.index_to_world, origin)))
}

/// The builder voxel of an OpenVDB leaf origin, in a grid whose voxel 0 is
/// OpenVDB index `origin`.
pub(crate) fn leaf_lo(leaf: [i32; 3], origin: [i64; 3]) -> [i64; 3] {
    std::array::from_fn(|k| leaf[k] as i64 - origin[k])
}

/// An OpenVDB leaf's values (z fastest, index x·64 + y·8 + z) in brick
/// order (x fastest), non-finite values zeroed, in place.
pub(crate) fn brick_order(v: &mut [f32; 512]) {
    for x in 0..8 {
        for y in 0..8 {
            for z in x + 1..8 {
                v.swap(x * 64 + y * 8 + z, z * 64 + y * 8 + x);
            }
        }
    }
    for x in v.iter_mut() {
        if !x.is_finite() {
            *x = 0.0;
        }
    }
}

/// The OpenVDB index→world map of rows `m`, from fogbank's voxel centres
/// of a grid starting at OpenVDB index `origin`.
fn index_to_world(m: &[[f64; 4]; 4], origin: [i64; 3]) -> DAffine3 {
    let linear = DMat3::from_cols(
        DVec3::new(m[0][0], m[1][0], m[2][0]),
        DVec3::new(m[0][1], m[1][1], m[2][1]),
        DVec3::new(m[0][2], m[1][2], m[2][2]),
    );
    let vdb = DAffine3::from_mat3_translation(linear, DVec3::new(m[0][3], m[1][3], m[2][3]));
    let shift = DAffine3::from_translation(
        DVec3::new(origin[0] as f64, origin[1] as f64, origin[2] as f64) - 0.5,
    );
    vdb * shift
}

/// Level set → fog volume as OpenVDB's `sdfToFogVolume`: 0 outside, rising
/// linearly through the interior half of the narrow band to 1 inside; the
/// map of a grid of narrow-band half width `background`.
pub fn level_set_fog(background: f32) -> impl Fn(f32) -> f32 + Sync + Copy {
    let w = background.abs().max(f32::MIN_POSITIVE);
    move |phi| (-phi / w).clamp(0.0, 1.0)
}

pub fn is_level_set(g: &VdbGrid) -> bool {
    g.grid_class == GridClass::LevelSet
}
