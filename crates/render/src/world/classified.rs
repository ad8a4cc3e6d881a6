//! A medium's density classified by its transfer function (Lerzer and Dachsbacher 2025 §3):
//! kept as the scalar for post-interpolative classification per lookup, or
//! replaced by classified extinction, albedo and emission grids.

use super::emission::Emission;
use super::field::Field;
use super::transfer::{Transfer, TransferDesc, TransferLookup, TransferMode};
use crate::error::SceneError;
use fogbank_math::{DAffine3, PiecewiseLinear, Vec3};
use fogbank_volume::{DensityData, Precision};
use std::path::Path;

/// A medium's data after its transfer function: post-interpolative keeps
/// the scalar and classifies per lookup; pre-interpolative replaces it with
/// classified grids (extinction, albedo and emission fields).
pub(crate) struct ClassifiedMedium {
    pub(crate) data: DensityData,
    pub(crate) opacity: Option<PiecewiseLinear<1>>,
    pub(crate) lookup: Option<TransferLookup>,
    pub(crate) albedo_grid: Option<Field>,
    pub(crate) emission: Option<Emission>,
}

pub(crate) fn classify(
    t: &TransferDesc,
    key: &str,
    base: &Path,
    units: Option<(f32, f32)>,
    data: DensityData,
    precision: Precision,
    xf: DAffine3,
) -> Result<ClassifiedMedium, SceneError> {
    let tkey = format!("{key}.transfer");
    if matches!(data, DensityData::Analytic(_)) {
        return Err(SceneError(format!(
            "{tkey}: transfer functions classify voxel grids; `{key}.density` is analytic"
        )));
    }
    let tf = Transfer::build(t, &tkey, base, units, data.value_range())?;
    if tf.mode == TransferMode::Post {
        return Ok(ClassifiedMedium {
            data,
            opacity: Some(tf.opacity.clone()),
            lookup: Some(tf.lookup()),
            albedo_grid: None,
            emission: None,
        });
    }
    let c = tf
        .classify(&data, precision)
        .map_err(|e| SceneError(format!("{tkey}: {e}")))?;
    let source = format!("{tkey} (pre-interpolative)");
    let albedo_grid = Field::from_channels(c.color.into(), xf, source.clone())?;
    let emission = c
        .emission
        .map(|e| Field::from_channels(e.into(), xf, source.clone()))
        .transpose()?
        .map(|grid| Emission::Color {
            radiance: Vec3::ONE,
            grid: Some(grid),
        });
    Ok(ClassifiedMedium {
        data: c.sigma,
        opacity: None,
        lookup: None,
        albedo_grid: Some(albedo_grid),
        emission,
    })
}
