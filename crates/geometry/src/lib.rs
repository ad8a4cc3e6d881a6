//! Surfaces: triangle meshes and analytic spheres and disks, watertight
//! ray–triangle intersection and the BVH (one flat node array for the CPU
//! and the GPU). A layer beside `fogbank-volume`, on top of `fogbank-math`.
//!
//! Modules in layers, each importing only those before it: `mesh` (triangle meshes:
//! positions, index triples, optional normals and UVs), `triangle` (watertight
//! ray–triangle intersection), `analytic` (Mitsuba 3's `sphere` and `disk`, intersected
//! exactly) and `bvh` (a binned-SAH BVH over boxed primitives, one flat array of 32-byte
//! nodes the CPU and WGSL read alike) → `loaders` (mesh files: OBJ and PLY) and `shapes`
//! (Mitsuba 3's mesh-backed `rectangle` and `cube`, and test meshes) → `accel` (one BVH
//! over a mesh and analytic shapes: closest-hit and any-hit queries) → `instances` (groups of
//! shapes placed by affine maps under a top-level BVH).

pub mod accel;
pub mod analytic;
pub mod bvh;
pub mod instances;
pub mod loaders;
pub mod mesh;
pub mod shapes;
pub mod triangle;
pub mod wide;

pub use accel::{MeshAccel, MeshHit};
pub use analytic::{AnalyticHit, AnalyticShape, Quadric};
pub use bvh::{Bvh, BvhNode, Walk};
pub use instances::{Instance, InstanceHit, Instances};
pub use loaders::load_mesh;
pub use mesh::TriangleMesh;
pub use triangle::{intersect, RayFrame, TriangleHit};
pub use wide::WideBvh;
