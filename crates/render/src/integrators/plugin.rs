//! What an integrator's description provides, in its own file: its name,
//! its parameter table (the one source of its docs: `fogbank integrators`,
//! its module doc and the README are checked against it), reading and
//! writing its `[integrator]` table, its transmittance estimator and what
//! it can render. `integrators/mod.rs` registers each implementation in one
//! line of its `integrators!` list, which generates `IntegratorDesc` and
//! every dispatch over it, so no list of integrators is written twice.

use crate::error::SceneError;
use crate::params::{Param, ParamReader};
use fogbank_estimators::Estimator;

/// What an integrator renders beyond media, checked when a scene builds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Capabilities {
    /// Chromatic extinction: σ_t scaled per RGB channel (`sigma_t_scale =
    /// [r, g, b]`), which needs spectral tracking in the walk.
    pub chromatic: bool,
    /// Camera rays end on the far clip plane (Mitsuba's `far_clip`).
    pub far_clip: bool,
}

/// An integrator's parameters: the typed `[integrator]` table of one
/// `integrator.type`.
pub trait IntegratorParams: Sized {
    /// Its `integrator.type`.
    const NAME: &'static str;
    /// Its parameter table, one row per key it reads.
    const PARAMS: &'static [Param];
    const CAPABILITIES: Capabilities;

    /// Reads its keys from the table (defaults from `Default`); every key
    /// it does not take is left for the caller to refuse.
    fn read(r: &mut ParamReader) -> Result<Self, SceneError>;

    /// Writes the keys that `read` reads back to the same value.
    fn write(&self, t: &mut toml::Table);

    /// The transmittance estimator as given (before any preset): the
    /// camera ray's (`transmittance`), NEE's, or final shading's.
    fn estimator(&self) -> Estimator;
}
