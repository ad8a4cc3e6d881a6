//! Spatially varying medium properties other than extinction (albedo,
//! emission colour, temperature): a grid placed in the world like the
//! density, looked up with trilinear interpolation at scattering vertices.

use crate::desc::{DensityDesc, SceneError};
use fogbank_math::{DAffine3, Vec3};
use fogbank_volume::loaders::vol;
use fogbank_volume::{DensityData, Precision};
use std::path::Path;

#[derive(Clone, Debug)]
pub struct Field {
    /// One channel (a scalar, splatted to RGB) or three (RGB).
    channels: Vec<DensityData>,
    world_to_index: DAffine3,
    dims: [u32; 3],
    pub source: String,
}

impl Field {
    /// Loads the grid `d` of scene key `key`; `to_world` is the medium's
    /// placement, applied after the file's own transform, so property grids
    /// line up with a density grid from the same kind of file.
    pub fn load(
        d: &DensityDesc,
        key: &str,
        base: &Path,
        to_world: DAffine3,
    ) -> Result<Field, SceneError> {
        let (channels, file_xf, source) = match &d.vol {
            // A 3-channel .vol without `channel` is an RGB grid (Mitsuba's
            // convention for albedo).
            Some(f) if d.channel.is_none() => {
                let path = base.join(f);
                let v = vol::read_vol(&path).map_err(|e| SceneError(format!("{key}: {e}")))?;
                let n = if v.channels == 3 { 3 } else { 1 };
                let channels = (0..n)
                    .map(|c| {
                        v.channel_grid(c)
                            .map(|g| DensityData::from_f32(g, Precision::F32))
                            .map_err(|e| SceneError(format!("{key}: {e}")))
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                (channels, v.index_to_world(), path.display().to_string())
            }
            _ => {
                let (data, xf, source) = crate::scene::density(d, key, base, Precision::F32)?;
                (vec![data], xf, source)
            }
        };
        let xf = to_world * file_xf;
        if xf.matrix3.determinant().abs() < 1e-30 {
            return Err(SceneError(format!("{key}: transform is singular")));
        }
        Ok(Field {
            dims: channels[0].dims(),
            channels,
            world_to_index: xf.inverse(),
            source,
        })
    }

    /// The channel grids and the world → index map, for GPU upload.
    pub fn parts(&self) -> (&[DensityData], DAffine3) {
        (&self.channels, self.world_to_index)
    }

    pub fn channel_count(&self) -> usize {
        self.channels.len()
    }

    /// Trilinearly interpolated value at world point `p`; zero outside the
    /// grid's box, like the density.
    pub fn eval(&self, p: Vec3) -> Vec3 {
        let q = self.world_to_index.transform_point3(p.as_dvec3()).as_vec3();
        let d = Vec3::new(
            self.dims[0] as f32,
            self.dims[1] as f32,
            self.dims[2] as f32,
        );
        if !(q.cmpge(Vec3::ZERO).all() && q.cmple(d).all()) {
            return Vec3::ZERO;
        }
        let one = |c: &DensityData| match c {
            DensityData::F16(g) => g.trilinear(q),
            DensityData::F32(g) => g.trilinear(q),
            DensityData::Analytic(a) => a.density(q / a.n as f32),
        };
        match self.channels.as_slice() {
            [c] => Vec3::splat(one(c)),
            [r, g, b] => Vec3::new(one(r), one(g), one(b)),
            _ => unreachable!("fields have one or three channels"),
        }
    }
}
