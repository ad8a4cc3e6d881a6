//! `restir` on the GPU (Lin et al. 2021 §5, Fig. 5): the passes of the CPU's
//! `restir::frame` as compute kernels over one shared reservoir buffer —
//! candidates → (reprojection, temporal reuse) → spatial reuse → final
//! shading → reduction into the accumulation buffers. WGSL in `wgsl/`, one
//! file per pass, mirroring the CPU files.
//!
//! Independent sequences run side by side along the dispatch's z axis
//! (`batch` of them), so small images still fill the device; each pass
//! keys its random numbers by seed, pixel, sequence, frame and pass as the
//! CPU does. Reprojection runs with the previous frame's bind groups
//! (camera, medium placement, lights), the other passes with the current
//! frame's, so moving cameras, media placements and lights reuse as on the
//! CPU. Timestamp queries give the time of each pass.
//!
//! Velocity fields move reprojected points back as on the CPU (a grid, or
//! an affine field: a constant or the plume's). Shapes are path vertices
//! as on the CPU (`wgsl/surface.wgsl`: BSDFs of surfaces.wgsl, the
//! stored path's surface bits and point on an emitting shape).

//!
//! Files: [`port`] (its `GpuIntegrator`), [`source`] (its WGSL), [`uniform`]
//! (the passes' uniform, region plan, velocity),
//! [`frame_data`] (one frame's bind groups), [`kernels`] (pipelines,
//! buffers, one frame's passes), [`sequences`] (the drivers).

mod frame_data;
#[cfg(test)]
mod kernel_test;
mod kernels;
mod port;
mod sequences;
mod source;
mod uniform;

pub use frame_data::FrameGpu;
pub use kernels::{PassMs, RestirGpu};
pub use sequences::{last_frames, render, SequenceGpu};
pub use port::RestirPort;
pub use uniform::STORED_BYTES;
