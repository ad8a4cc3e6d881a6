//! Indices of refraction: numbers, or the names of Mitsuba 3's table.

use crate::error::SceneError;
use serde::{Deserialize, Serialize};

/// Mitsuba 3's named indices of refraction (`include/mitsuba/render/ior.h`).
pub const IOR_TABLE: [(&str, f32); 23] = [
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// An IOR as a number or a name from [`IOR_TABLE`].
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum IorDesc {
    Value(f32),
    Name(String),
}

impl IorDesc {
    pub fn value(&self, key: &str) -> Result<f32, SceneError> {
        let v = match self {
            IorDesc::Value(v) => *v,
            IorDesc::Name(n) => IOR_TABLE
                .iter()
                .find(|(name, _)| name.eq_ignore_ascii_case(n))
                .map(|(_, v)| *v)
                .ok_or_else(|| {
                    SceneError(format!(
                        "{key}: unknown IOR `{n}` (known: {})",
                        IOR_TABLE.map(|(n, _)| n).join(", ")
                    ))
                })?,
        };
        if !(v.is_finite() && v > 0.0) {
            return Err(SceneError(format!("{key}: IOR {v} is not positive")));
        }
        Ok(v)
    }
}

pub fn ior(name: &str) -> IorDesc {
    IorDesc::Name(name.into())
}
