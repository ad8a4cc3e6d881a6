//! File loaders. Each one validates sizes before allocating and returns a
//! [`crate::VolumeError`] naming the file and the problem.

pub mod grid_choice;
pub mod nanovdb;
pub mod nifti;
pub mod nrrd;
pub mod raw;
pub mod sample;
pub mod scalar;
pub mod vdb;
pub mod vdb_grid;
pub mod vol;
