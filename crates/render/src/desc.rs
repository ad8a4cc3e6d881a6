//! Every part of the scene description in one place, for callers that
//! build or inspect scenes. Each type lives with what it describes (the
//! camera's in `world::camera`, an integrator's in its file); nothing inside
//! the crate imports this module.

pub use crate::error::SceneError;
pub use crate::integrators::shared::ScatterParams;
pub use crate::integrators::IntegratorDesc;
pub use crate::lights::LightDesc;
pub use crate::overrides::{apply_override, parse_value};
pub use crate::scene::{RenderDesc, SceneDesc, DEFAULT_SCENE};
pub use crate::world::camera::CameraDesc;
pub use crate::world::emission::EmissionDesc;
pub use crate::world::field::FieldDesc;
pub use crate::world::medium::{MediumDesc, ScaleDesc, TransformDesc};
pub use crate::world::phase::PhaseDesc;
pub use crate::world::surfaces::{BsdfDesc, EmitterDesc, ShapeDesc, ShapeType};
