//! Surfaces: `[[shapes]]` entries — meshes from OBJ and PLY
//! files or Mitsuba's unit shapes, placed by `to_world`, with a BSDF and
//! optionally an area emitter — gathered into one triangle mesh and BVH,
//! and shape groups placed by instances under a top-level BVH.
//! Media stay the regions their boxes give; shapes sit in them (a shape
//! that bounds a medium comes next).

pub mod bsdf_desc;
mod conductor_table;
pub mod conductors;
pub mod frame;
mod gathered;
pub mod ior;
pub mod material;
pub mod scene_surfaces;
pub mod shape;
mod shape_groups;
pub mod spectrum;
mod surface_hit;

pub use frame::ShadingFrame;
pub use material::{BsdfDesc, Material, SurfaceBsdf};
pub use scene_surfaces::{SurfaceHit, Surfaces};
pub use shape::{EmitterDesc, ShapeDesc, ShapeType};
