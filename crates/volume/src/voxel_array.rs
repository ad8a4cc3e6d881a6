//! Voxels held in memory by the caller rather than read from a file: a
//! numpy array handed over from Python, or values a program computed. A
//! scene refers to one by name (`density = { array = "array:3" }`, see
//! `fogbank_render::world::arrays`) and builds its brick grid from it as it
//! would from a `.vol` file with the same voxels and box.
//!
//! Index convention as everywhere in fogbank: voxel `(i, j, k)` (x fastest
//! in memory order z, y, x) is the cell `[i, i+1) × [j, j+1) × [k, k+1)` of
//! index space `[0, dims]`, placed in the world by `index_to_world`.

use crate::grid::{check_dims, BrickGrid};
use crate::{Result, VolumeError};
use glam::DAffine3;

/// A dense array of voxels with one (a scalar field) or three (RGB albedo,
/// a velocity) values per voxel.
pub trait VoxelArray: Send + Sync + std::fmt::Debug {
    /// Voxel counts (x, y, z).
    fn dims(&self) -> [u32; 3];
    /// Values per voxel: 1 or 3.
    fn channels(&self) -> u32;
    /// Channel `c` of voxel `(i, j, k)`; finite (checked when the array was
    /// made).
    fn value(&self, i: u32, j: u32, k: u32, c: u32) -> f32;
    /// Index space `[0, dims]` → world.
    fn index_to_world(&self) -> DAffine3;
    /// What the array is, for messages (`numpy float32 64×64×64`).
    fn describe(&self) -> String;
}

impl dyn VoxelArray {
    /// Channel `c` as a brick grid: the grid `vol::VolFile::channel_grid`
    /// builds from a `.vol` file holding the same values.
    pub fn channel_grid(&self, c: u32) -> Result<BrickGrid<f32>> {
        if c >= self.channels() {
            return Err(VolumeError::Invalid(format!(
                "channel {c} requested from a {}-channel array",
                self.channels()
            )));
        }
        BrickGrid::from_fn(self.dims(), |i, j, k| self.value(i, j, k, c))
    }
}

/// Voxels owned by fogbank: `data[((k·ny + j)·nx + i)·channels + c]`.
#[derive(Clone, Debug)]
pub struct DenseArray {
    dims: [u32; 3],
    channels: u32,
    data: Vec<f32>,
    index_to_world: DAffine3,
    source: String,
}

impl DenseArray {
    /// Checks the sizes and that every value is finite.
    pub fn new(
        dims: [u32; 3],
        channels: u32,
        data: Vec<f32>,
        index_to_world: DAffine3,
        source: String,
    ) -> Result<DenseArray> {
        let dims = check_dims(dims.map(u64::from))?;
        if !(channels == 1 || channels == 3) {
            return Err(VolumeError::Invalid(format!(
                "{source}: {channels} values per voxel (1 or 3)"
            )));
        }
        let n = dims.iter().map(|&d| d as usize).product::<usize>() * channels as usize;
        if data.len() != n {
            return Err(VolumeError::Invalid(format!(
                "{source}: {} values for {}×{}×{}×{channels}",
                data.len(),
                dims[0],
                dims[1],
                dims[2]
            )));
        }
        if let Some(at) = data.iter().position(|v| !v.is_finite()) {
            return Err(VolumeError::Invalid(format!(
                "{source}: value {} at flat index {at} is not finite",
                data[at]
            )));
        }
        Ok(DenseArray {
            dims,
            channels,
            data,
            index_to_world,
            source,
        })
    }

    /// Channel `c` of a brick grid's voxels, densely (bounded by the
    /// grid's own size check).
    pub fn from_grid(
        grid: &BrickGrid<f32>,
        index_to_world: DAffine3,
        source: String,
    ) -> DenseArray {
        let [nx, ny, nz] = grid.dims();
        let mut data = Vec::with_capacity(nx as usize * ny as usize * nz as usize);
        for k in 0..nz as i32 {
            for j in 0..ny as i32 {
                data.extend((0..nx as i32).map(|i| grid.fetch(i, j, k)));
            }
        }
        DenseArray {
            dims: grid.dims(),
            channels: 1,
            data,
            index_to_world,
            source,
        }
    }

    /// The values, z slowest, then y, x, channel fastest.
    pub fn data(&self) -> &[f32] {
        &self.data
    }
}

impl VoxelArray for DenseArray {
    fn dims(&self) -> [u32; 3] {
        self.dims
    }
    fn channels(&self) -> u32 {
        self.channels
    }
    #[inline]
    fn value(&self, i: u32, j: u32, k: u32, c: u32) -> f32 {
        let [nx, ny, _] = self.dims.map(|d| d as usize);
        self.data[((k as usize * ny + j as usize) * nx + i as usize) * self.channels as usize
            + c as usize]
    }
    fn index_to_world(&self) -> DAffine3 {
        self.index_to_world
    }
    fn describe(&self) -> String {
        self.source.clone()
    }
}

#[cfg(test)]
mod voxel_array_test {
    use super::*;
    use crate::loaders::vol::{parse_vol, write_vol};
    use crate::medium::box_transform;

    #[test]
    fn an_array_builds_the_grid_of_a_vol_file_with_its_voxels() {
        let dims = [11, 7, 5];
        let n = 11 * 7 * 5;
        let data: Vec<f32> = (0..n).map(|x| ((x * 37) % 19) as f32 * 0.25).collect();
        let (lo, hi) = ([-1.0f32, 0.0, 2.0], [1.0f32, 0.5, 3.0]);
        let path = std::env::temp_dir().join("fogbank_voxel_array_test.vol");
        write_vol(
            &path,
            dims,
            1,
            [lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]],
            &data,
        )
        .unwrap();
        let vol = parse_vol(&path, &std::fs::read(&path).unwrap()).unwrap();
        let xf = box_transform(dims, lo.map(f64::from), hi.map(f64::from));
        let a: Box<dyn VoxelArray> =
            Box::new(DenseArray::new(dims, 1, data, xf, "test".into()).unwrap());
        let (g, h) = (a.channel_grid(0).unwrap(), vol.channel_grid(0).unwrap());
        assert_eq!(g.buffers(), h.buffers());
        assert_eq!(a.index_to_world(), vol.index_to_world());
    }

    #[test]
    fn bad_arrays_are_refused_with_the_reason() {
        let xf = DAffine3::IDENTITY;
        let e = |r: Result<DenseArray>| r.unwrap_err().to_string();
        assert!(
            e(DenseArray::new([2, 2, 2], 1, vec![0.0; 7], xf, "a".into())).contains("7 values")
        );
        assert!(e(DenseArray::new([2, 2, 2], 2, vec![0.0; 16], xf, "a".into())).contains("1 or 3"));
        let mut v = vec![0.0; 8];
        v[5] = f32::NAN;
        assert!(e(DenseArray::new([2, 2, 2], 1, v, xf, "a".into())).contains("flat index 5"));
        assert!(e(DenseArray::new([0, 2, 2], 1, vec![], xf, "a".into())).contains("out of range"));
    }
}
