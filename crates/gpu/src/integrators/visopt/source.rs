//! `visopt`'s WGSL: the scattering prelude, the occluders, importance
//! rules, lists and the optimised view; its parameters and rules serve
//! `ament` too.

use crate::shaders;

/// The uniform and rule records (`ament` reads them too).
pub(crate) const PARAMS: &str = include_str!("params.wgsl");
/// The importance rules (`ament` reads them too).
pub(crate) const IMPORTANCE: &str = include_str!("importance.wgsl");
const SEGMENTS: &str = include_str!("segments.wgsl");
const KERNEL: &str = include_str!("visopt.wgsl");

/// Its source: the scattering prelude, the occluders, importance rules,
/// lists and the optimised view.
pub(crate) fn source() -> String {
    shaders::occluding_kernel(&[PARAMS, IMPORTANCE, SEGMENTS, KERNEL].join("\n"))
}

