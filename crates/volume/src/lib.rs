//! Volume data layer of fogbank: storage, filtering, super-voxel statistics,
//! traversal, analytic and procedural media, and file loaders.
//!
//! Modules in layers, each importing only those before it: `error` (errors naming the
//! file at fault) → `grid` (the sparse brick grid: the one storage layout, uploaded to
//! the GPU unchanged) → `grid_builder` (a brick grid built from sparse input such as
//! OpenVDB leaves and tiles), `supervoxel` (the super-voxel statistics every estimator
//! traverses: minimum, maximum, mean, importance), `bc4` (BC4-style block compression,
//! Lin et al. 2021 §5.1), `distance` (Euclidean distance transforms of voxel masks, Lerzer and Dachsbacher 2025
//! §6.6's signed distance) and `procedural` (a fractal cloud) → `access` (the
//! `VolumeAccess` interface every estimator is written against) and media built on the
//! cloud's noise: `bunny` (Lin et al. 2021 Fig. 1's bunny-shaped cloud), `explosion` (an
//! emissive fireball with a temperature) and `plume` (an animated smoke plume) →
//! `analytic` (test media with closed-form optical depth), `dda` (Amanatides–Woo grid
//! traversal) and `lanes` (eight filtered lookups at a time in SIMD lanes) → `medium`
//! (a medium's extinction: data, scale, filter, placement, statistics) and `occupied`
//! (empty-space skipping along a ray) → `loaders` (volume files: OpenVDB, NanoVDB, `.vol`, NRRD,
//! NIfTI, raw) and `mip` (conservative mips for regular tracking, Lin et al. 2021 §4.1) →
//! `voxel_array` (voxels held in memory by the caller, such as a numpy array) and
//! `writers` (OpenVDB and NanoVDB files written from a brick grid).

pub mod access;
pub mod analytic;
pub mod bc4;
pub mod bunny;
pub mod dda;
pub mod distance;
pub mod error;
pub mod explosion;
pub mod formats;
pub mod grid;
pub mod grid_builder;
pub mod lanes;
mod leaf_bricks;
pub mod loaders;
pub mod medium;
pub mod mip;
pub mod occupied;
pub mod plume;
pub mod procedural;
pub mod supervoxel;
pub mod voxel_array;
pub mod writers;

pub use access::{Filter, GridView, VolumeAccess};
pub use analytic::{AnalyticField, AnalyticKind, AnalyticView};
pub use dda::{Dda, DdaStep};
pub use error::{Result, VolumeError};
pub use grid::{BrickGrid, Precision, Voxel};
pub use grid_builder::BrickGridBuilder;
pub use medium::{DensityData, Medium, MediumView};
pub use occupied::Occupied;
pub use supervoxel::{SuperVoxel, SuperVoxelGrid, ZERO_NEAREST, ZERO_TRILINEAR};
pub use voxel_array::{DenseArray, VoxelArray};
