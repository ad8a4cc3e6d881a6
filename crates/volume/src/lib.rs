//! Volume data layer of fogbank: storage, filtering, super-voxel statistics,
//! traversal, analytic and procedural media, and file loaders.

pub mod access;
pub mod analytic;
pub mod bc4;
pub mod bunny;
pub mod dda;
pub mod distance;
pub mod error;
pub mod explosion;
pub mod grid;
pub mod grid_builder;
pub mod lanes;
pub mod loaders;
pub mod medium;
pub mod mip;
pub mod occupied;
pub mod plume;
pub mod procedural;
pub mod supervoxel;
pub mod voxel_array;

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
