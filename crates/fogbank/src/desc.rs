//! The scene description a front end builds, edits or lists: every part of
//! it, the integrators' registry with their parameter tables, and a
//! scene's file names rewritten for another folder. Each type lives with
//! what it describes in `fogbank-render`; this is where front ends find
//! them.

pub use fogbank_render::desc::*;
pub use fogbank_render::integrators::shared::DistanceSampler;
pub use fogbank_render::integrators::LISTED as INTEGRATORS;
pub use fogbank_render::params::{markdown_table, Param};
pub use fogbank_render::rebase::rebase_paths;
