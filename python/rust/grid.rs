//! `fogbank.Grid`: a voxel grid from a numpy array (or read from a volume
//! file), usable wherever a scene takes a field: density, albedo, emission,
//! temperature, importance mask or velocity (`scene.set("media.0.density",
//! grid)`).
//!
//! Layout: a 3D array is indexed `[z, y, x]` (x varies fastest in a
//! C-ordered array, as in `.vol` files, NIfTI read by nibabel transposed,
//! and OpenVDB's dense copies); a 4D array `[z, y, x, 3]` holds three
//! values per voxel (RGB albedo, a velocity). float16, float32 and float64
//! are read in place, C- or F-ordered or any strided view, without a copy
//! (other byte orders and unaligned buffers are copied once). Every value
//! must be finite; it is checked when the grid is made, and a value made
//! non-finite afterwards reads as 0.
//!
//! Placement: voxel `(i, j, k)` is the cell `[i, i+1)×[j, j+1)×[k, k+1)`
//! of index space, mapped onto `bbox` (default: fogbank's box for grids
//! without one, `[-½, ½]` along the longest axis, centred, keeping aspect,
//! as for `.raw` files and procedural media), then by `to_world` (a 4×4
//! affine matrix), then by the medium's own `to_world`; or by
//! `index_to_world` alone (index space straight to the world).

use crate::errors::{guarded, invalid};
use fogbank::volumes::{box_transform, check_dims, register_array, unit_box_transform, VoxelArray};
use glam::{DAffine3, DMat3, DVec3};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use std::sync::Arc;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Dtype {
    F16,
    F32,
    F64,
}

/// A numpy array's memory, read in place.
#[derive(Debug)]
struct NumpyVoxels {
    /// Keeps the memory alive.
    owner: Py<PyAny>,
    address: usize,
    /// Byte strides of the z, y, x and channel axes.
    strides: [isize; 4],
    dims: [u32; 3],
    channels: u32,
    dtype: Dtype,
    index_to_world: DAffine3,
    source: String,
}

impl VoxelArray for NumpyVoxels {
    fn dims(&self) -> [u32; 3] {
        self.dims
    }
    fn channels(&self) -> u32 {
        self.channels
    }
    #[inline]
    fn value(&self, i: u32, j: u32, k: u32, c: u32) -> f32 {
        let s = self.strides;
        let at = k as isize * s[0] + j as isize * s[1] + i as isize * s[2] + c as isize * s[3];
        // SAFETY: the indices are inside the array's shape (callers iterate
        // `dims` and `channels`), the strides and address are numpy's own
        // for that shape, alignment and native byte order were checked
        // when the grid was made, and `owner` keeps the buffer alive.
        let v = unsafe {
            let p = (self.address as isize + at) as *const u8;
            match self.dtype {
                Dtype::F16 => half::f16::from_bits(*(p as *const u16)).to_f32(),
                Dtype::F32 => *(p as *const f32),
                Dtype::F64 => *(p as *const f64) as f32,
            }
        };
        if v.is_finite() {
            v
        } else {
            0.0
        }
    }
    fn index_to_world(&self) -> DAffine3 {
        self.index_to_world
    }
    fn describe(&self) -> String {
        self.source.clone()
    }
}

/// A voxel grid placed in the world (see the module's documentation).
#[pyclass(module = "fogbank._native", frozen)]
pub struct Grid {
    /// The name scenes use (`{ array = NAME }`).
    pub name: String,
    pub array: Arc<dyn VoxelArray>,
    /// The numpy array read in place, if any.
    numpy: Option<Py<PyAny>>,
    /// For grids read from scientific files: the value range the stored
    /// [0, 1] stands for.
    units: Option<(f32, f32)>,
}

impl Grid {
    pub fn from_array(
        array: Arc<dyn VoxelArray>,
        numpy: Option<Py<PyAny>>,
        units: Option<(f32, f32)>,
    ) -> Grid {
        let name = register_array(&array);
        Grid {
            name,
            array,
            numpy,
            units,
        }
    }
}

/// `dtype`'s kind, refusing what is not a float type numpy has.
fn dtype_of(array: &Bound<'_, PyAny>) -> PyResult<(Dtype, bool)> {
    let dt = array.getattr("dtype")?;
    let (kind, size): (String, usize) = (
        dt.getattr("kind")?.extract()?,
        dt.getattr("itemsize")?.extract()?,
    );
    let native = dt.getattr("isnative")?.extract::<bool>()?;
    let d = match (kind.as_str(), size) {
        ("f", 2) => Dtype::F16,
        ("f", 4) => Dtype::F32,
        ("f", 8) => Dtype::F64,
        _ => {
            return Err(PyTypeError::new_err(format!(
                "array: dtype {} is not float16, float32 or float64 (convert it: array.astype(numpy.float32))",
                dt.str()?
            )))
        }
    };
    Ok((d, native))
}

/// A 4×4 matrix or a 3×4 affine matrix as an affine map.
pub fn affine(m: &Bound<'_, PyAny>, what: &str) -> PyResult<DAffine3> {
    let rows: Vec<Vec<f64>> = m
        .call_method0("tolist")
        .or_else(|_| Ok::<_, PyErr>(m.clone()))?
        .extract()
        .map_err(|_| {
            PyValueError::new_err(format!(
                "{what}: expected a 4×4 matrix (nested lists or a numpy array)"
            ))
        })?;
    let ok_shape = (rows.len() == 4 || rows.len() == 3) && rows.iter().all(|r| r.len() == 4);
    if !ok_shape {
        return Err(PyValueError::new_err(format!(
            "{what}: expected a 4×4 matrix, got {} rows of {:?} entries",
            rows.len(),
            rows.iter().map(|r| r.len()).collect::<Vec<_>>()
        )));
    }
    if rows.iter().flatten().any(|v| !v.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "{what}: entries must be finite"
        )));
    }
    if rows.len() == 4 && rows[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(PyValueError::new_err(format!(
            "{what}: the last row must be [0, 0, 0, 1] (an affine map), not {:?}",
            rows[3]
        )));
    }
    let col = |c: usize| DVec3::new(rows[0][c], rows[1][c], rows[2][c]);
    let xf = DAffine3 {
        matrix3: DMat3::from_cols(col(0), col(1), col(2)),
        translation: col(3),
    };
    if xf.matrix3.determinant().abs() < 1e-30 {
        return Err(PyValueError::new_err(format!(
            "{what}: the matrix is singular"
        )));
    }
    Ok(xf)
}

/// `bbox = ((x0, y0, z0), (x1, y1, z1))`.
fn bbox_of(b: &Bound<'_, PyAny>) -> PyResult<([f64; 3], [f64; 3])> {
    let (lo, hi): ([f64; 3], [f64; 3]) = b
        .extract()
        .map_err(|_| PyValueError::new_err("bbox: expected ((x0, y0, z0), (x1, y1, z1))"))?;
    if !(lo.iter().chain(&hi).all(|v| v.is_finite()) && (0..3).all(|a| hi[a] > lo[a])) {
        return Err(PyValueError::new_err(format!(
            "bbox: ({lo:?}, {hi:?}) must be finite with every max above its min"
        )));
    }
    Ok((lo, hi))
}

/// The first non-finite voxel of `v`, as (z, y, x[, c]).
fn first_non_finite(v: &NumpyVoxels) -> Option<(u32, u32, u32, u32, f64)> {
    use rayon::prelude::*;
    let [nx, ny, nz] = v.dims;
    (0..nz).into_par_iter().find_map_first(|k| {
        for j in 0..ny {
            for i in 0..nx {
                for c in 0..v.channels {
                    let s = v.strides;
                    let at = k as isize * s[0]
                        + j as isize * s[1]
                        + i as isize * s[2]
                        + c as isize * s[3];
                    // SAFETY: as in `NumpyVoxels::value`.
                    let x = unsafe {
                        let p = (v.address as isize + at) as *const u8;
                        match v.dtype {
                            Dtype::F16 => half::f16::from_bits(*(p as *const u16)).to_f64(),
                            Dtype::F32 => *(p as *const f32) as f64,
                            Dtype::F64 => *(p as *const f64),
                        }
                    };
                    if !x.is_finite() {
                        return Some((k, j, i, c, x));
                    }
                }
            }
        }
        None
    })
}

#[pymethods]
impl Grid {
    /// `Grid(array, to_world=None, bbox=None, index_to_world=None)`:
    /// `array` a float16/32/64 numpy array of shape (z, y, x) or (z, y, x,
    /// 3); `bbox` the box the index space maps onto, ((x0, y0, z0), (x1,
    /// y1, z1)); `to_world` a 4×4 affine matrix applied after it; or
    /// `index_to_world`, the 4×4 matrix from index space [0, dims] to the
    /// world (another grid's `index_to_world`, a scanner's affine).
    #[new]
    #[pyo3(signature = (array, to_world=None, bbox=None, index_to_world=None))]
    fn new(
        py: Python<'_>,
        array: Bound<'_, PyAny>,
        to_world: Option<Bound<'_, PyAny>>,
        bbox: Option<Bound<'_, PyAny>>,
        index_to_world: Option<Bound<'_, PyAny>>,
    ) -> PyResult<Grid> {
        let np = py.import("numpy")?;
        if !array.is_instance(&np.getattr("ndarray")?)? {
            return Err(PyTypeError::new_err(format!(
                "array: expected a numpy array, got {}",
                array.get_type().name()?
            )));
        }
        let (dtype, native) = dtype_of(&array)?;
        let aligned: bool = array.getattr("flags")?.getattr("aligned")?.extract()?;
        let array = if native && aligned {
            array
        } else {
            // One copy into native byte order and alignment.
            let name = match dtype {
                Dtype::F16 => "float16",
                Dtype::F32 => "float32",
                Dtype::F64 => "float64",
            };
            np.call_method1("ascontiguousarray", (&array, name))?
        };
        let shape: Vec<usize> = array.getattr("shape")?.extract()?;
        let strides: Vec<isize> = array.getattr("strides")?.extract()?;
        let channels = match shape.as_slice() {
            [_, _, _] => 1,
            [_, _, _, 3] => 3,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "array: shape {shape:?}; expected (z, y, x) or (z, y, x, 3)"
                )))
            }
        };
        let dims = [shape[2] as u64, shape[1] as u64, shape[0] as u64];
        let dims = check_dims(dims).map_err(|e| invalid(format!("array: {e}")))?;
        let address: usize = array
            .getattr("__array_interface__")?
            .get_item("data")?
            .get_item(0)?
            .extract()?;
        let placement = match (&index_to_world, &bbox, &to_world) {
            (Some(m), None, None) => affine(m, "index_to_world")?,
            (Some(_), _, _) => {
                return Err(PyValueError::new_err(
                    "index_to_world: give it alone, or bbox and to_world",
                ))
            }
            (None, b, m) => {
                let boxed = match b {
                    Some(b) => {
                        let (lo, hi) = bbox_of(b)?;
                        box_transform(dims, lo, hi)
                    }
                    None => unit_box_transform(dims),
                };
                match m {
                    Some(m) => affine(m, "to_world")? * boxed,
                    None => boxed,
                }
            }
        };
        let source = format!(
            "numpy {} array {}×{}×{}{}",
            array.getattr("dtype")?.str()?,
            dims[0],
            dims[1],
            dims[2],
            if channels == 3 { "×3" } else { "" }
        );
        let voxels = NumpyVoxels {
            owner: array.clone().unbind(),
            address,
            strides: [
                strides[0],
                strides[1],
                strides[2],
                strides.get(3).copied().unwrap_or(0),
            ],
            dims,
            channels,
            dtype,
            index_to_world: placement,
            source,
        };
        let bad = guarded(|| Ok(py.detach(|| first_non_finite(&voxels))))?;
        if let Some((k, j, i, c, x)) = bad {
            let at = if channels == 3 {
                format!("[{k}, {j}, {i}, {c}]")
            } else {
                format!("[{k}, {j}, {i}]")
            };
            return Err(PyValueError::new_err(format!(
                "array: value {x} at {at} is not finite"
            )));
        }
        let numpy = Some(voxels.owner.clone_ref(py));
        Ok(Grid::from_array(Arc::new(voxels), numpy, None))
    }

    /// The array's shape: (z, y, x) or (z, y, x, 3).
    #[getter]
    fn shape(&self) -> Vec<u32> {
        let [x, y, z] = self.array.dims();
        let mut s = vec![z, y, x];
        if self.array.channels() == 3 {
            s.push(3);
        }
        s
    }

    /// Values per voxel: 1 or 3.
    #[getter]
    fn channels(&self) -> u32 {
        self.array.channels()
    }

    /// The name a scene gives it (`{ array = NAME }`), valid in this process.
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// For grids read from NIfTI/NRRD files: the file's value range
    /// (lo, hi) that the grid's [0, 1] stands for; else None.
    #[getter]
    fn units(&self) -> Option<(f32, f32)> {
        self.units
    }

    /// The 4×4 matrix taking index space [0, dims] (x, y, z) to the world.
    #[getter]
    fn index_to_world(&self) -> [[f64; 4]; 4] {
        let xf = self.array.index_to_world();
        let (m, t) = (xf.matrix3, xf.translation);
        [
            [m.x_axis.x, m.y_axis.x, m.z_axis.x, t.x],
            [m.x_axis.y, m.y_axis.y, m.z_axis.y, t.y],
            [m.x_axis.z, m.y_axis.z, m.z_axis.z, t.z],
            [0.0, 0.0, 0.0, 1.0],
        ]
    }

    /// The voxels as a numpy array of shape `shape`: the array the grid was
    /// made from (no copy), or for a grid read from a file a float32 copy,
    /// refused over `max_voxels` voxels (default 2³⁰, 4 GiB).
    #[pyo3(signature = (max_voxels = 1 << 30))]
    fn to_numpy<'py>(&self, py: Python<'py>, max_voxels: u64) -> PyResult<Bound<'py, PyAny>> {
        if let Some(a) = &self.numpy {
            return Ok(a.bind(py).clone());
        }
        let [x, y, z] = self.array.dims().map(u64::from);
        let n = x * y * z * self.array.channels() as u64;
        if n > max_voxels {
            return Err(PyValueError::new_err(format!(
                "to_numpy: {x}×{y}×{z}×{} values are more than max_voxels = {max_voxels}",
                self.array.channels()
            )));
        }
        let a = self.array.clone();
        let data: Vec<f32> = py.detach(|| {
            let mut v = Vec::with_capacity(n as usize);
            for k in 0..z as u32 {
                for j in 0..y as u32 {
                    for i in 0..x as u32 {
                        for c in 0..a.channels() {
                            v.push(a.value(i, j, k, c));
                        }
                    }
                }
            }
            v
        });
        let shape = self.shape();
        Ok(PyArray1::from_vec(py, data)
            .reshape(shape.iter().map(|&s| s as usize).collect::<Vec<_>>())?
            .into_any())
    }

    fn __repr__(&self) -> String {
        format!(
            "fogbank.Grid({}, shape={:?}, name={:?})",
            self.array.describe(),
            self.shape(),
            self.name
        )
    }
}

/// Reads a volume file as fogbank reads it for a scene: `.vdb` and `.nvdb`
/// (grid `grid`), `.vol`, `.nii`/`.nii.gz`/`.hdr`, `.nrrd`/`.nhdr`, `.raw`
/// (dimensions from a `name_XxYxZ_type.raw` file name); values as fogbank
/// renders them (negative densities clamped to 0, a level set as fog,
/// scientific data normalised onto [0, 1] with its range in `units`).
#[pyfunction]
#[pyo3(signature = (path, grid = None, channel = None, max_voxels = 1 << 30))]
pub fn read_volume(
    py: Python<'_>,
    path: std::path::PathBuf,
    grid: Option<String>,
    channel: Option<u32>,
    max_voxels: u64,
) -> PyResult<Grid> {
    let read = guarded(|| {
        py.detach(|| fogbank::volumes::read_volume(&path, grid, channel, max_voxels))
            .map_err(crate::errors::to_py)
    })?;
    Ok(Grid::from_array(Arc::new(read.array), None, read.units))
}
