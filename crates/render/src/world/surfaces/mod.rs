//! Surfaces: `[[shapes]]` entries — meshes from OBJ and PLY
//! files or Mitsuba's unit shapes, placed by `to_world`, with a BSDF and
//! optionally an area emitter — gathered into one triangle mesh and BVH.
//! Media stay the regions their boxes give; shapes sit in them (a shape
//! that bounds a medium comes next).

pub mod bsdf_desc;
mod conductor_table;
pub mod conductors;
pub mod frame;
pub mod ior;
pub mod material;
pub mod scene_surfaces;
pub mod shape;
pub mod spectrum;

pub use frame::ShadingFrame;
pub use material::{BsdfDesc, Material, SurfaceBsdf};
pub use scene_surfaces::{SurfaceHit, Surfaces};
pub use shape::{EmitterDesc, ShapeDesc, ShapeType};
