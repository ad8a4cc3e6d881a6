//! The GPU backend: wgpu compute kernels written in WGSL that mirror the CPU
//! reference (`fogbank-estimators`, `fogbank-render`) for the hot paths.
//!
//! Layout: the scene's media are uploaded once into flat buffers
//! ([`scene_buffers`]); WGSL sources live one concept per file under
//! `src/wgsl/` and are concatenated per kernel ([`shaders`]), with the
//! estimator chosen by a pipeline-overridable constant so the hot loop has
//! no dispatch. PCG32/PCG3D are bit-identical to the CPU's, so a pixel's
//! random stream is the same on both.

pub mod accumulation;
pub mod context;
pub mod contract;
#[cfg(test)]
mod contract_test;
pub mod diagnostics;
mod kernel;
mod kernel_setup;
pub mod lights;
mod pin_kernel;
pub mod pin_stream;
pub mod pins;
pub mod pipelines;
#[cfg(test)]
mod pipelines_test;
pub mod render;
#[cfg(test)]
mod render_test;
pub mod restir;
pub mod scene_buffers;
pub mod shaders;
pub mod surfaces;
pub mod visopt;

pub use context::{Gpu, GpuError};

/// For tests: the process's GPU, or `None` with a visible message. With
/// `FOGBANK_REQUIRE_GPU=1` (set by `.ci/run`) a missing adapter is a failure.
/// Every call hands out a handle to the same device, so that the tests of
/// one binary build each pipeline once.
pub fn test_gpu() -> Option<Gpu> {
    static SHARED: std::sync::OnceLock<Result<Gpu, GpuError>> = std::sync::OnceLock::new();
    match SHARED.get_or_init(Gpu::new) {
        Ok(g) => Some(g.clone()),
        Err(e) => {
            if std::env::var("FOGBANK_REQUIRE_GPU").as_deref() == Ok("1") {
                panic!("FOGBANK_REQUIRE_GPU=1 but no GPU: {e}");
            }
            eprintln!("SKIPPED (no GPU adapter): {e}");
            None
        }
    }
}
