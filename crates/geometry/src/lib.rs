//! Surfaces: triangle meshes and analytic spheres and disks, watertight
//! ray–triangle intersection and the BVH (one flat node array for the CPU
//! and the GPU). A layer beside `fogbank-volume`, on top of `fogbank-math`.

pub mod accel;
pub mod analytic;
pub mod bvh;
pub mod loaders;
pub mod mesh;
pub mod shapes;
pub mod triangle;

pub use accel::{MeshAccel, MeshHit};
pub use analytic::{AnalyticHit, AnalyticShape, Quadric};
pub use bvh::{Bvh, BvhNode};
pub use loaders::load_mesh;
pub use mesh::TriangleMesh;
pub use triangle::{intersect, RayFrame, TriangleHit};
