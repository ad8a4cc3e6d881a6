//! The GPU backend: wgpu compute kernels written in WGSL that mirror the CPU
//! reference (`fogbank-estimators`, `fogbank-render`) for the hot paths.
//!
//! Layout: the scene's media are uploaded once into flat buffers
//! ([`scene_buffers`]); WGSL sources live one concept per file under
//! `src/wgsl/` and are concatenated per kernel ([`shaders`]), with the
//! estimator chosen by a pipeline-overridable constant so the hot loop has
//! no dispatch. PCG32/PCG3D are bit-identical to the CPU's, so a pixel's
//! random stream is the same on both.
//!
//! Modules in layers, each importing only those before it (`context` and `pipelines`
//! refer to each other):
//! - `contract` (every id and flag bit a WGSL kernel switches on, taken from the Rust
//!   registries) → `shaders`; `context` (the wgpu device: adapter, limits, timestamp
//!   support) and `pipelines` (compute pipelines and bind group layouts, built once per
//!   device);
//! - `scene_buffers`, `accumulation` (bind group 1: the frame uniform and the
//!   accumulation buffers, read back as a film) and `surfaces` (the scene's BVH, shapes,
//!   triangles and materials on the device);
//! - `lights` (bind group 2: lights, environment map, the media's albedo, phase and
//!   emission, the surfaces) and Hansen 2025's pins: `pin_kernel` (the bind-group layout
//!   and pipeline its grid-writing kernels share) → `pin_stream` (the pins streamed into
//!   each grid before every pass) → `pins` (every medium's pin grid gathered on the
//!   device, bind group 3 of the scatter kernel);
//! - `diagnostics` (kernels that test the WGSL ports against the CPU bit for bit);
//! - `integrators` (the GPU's integrators, one folder each with its WGSL and a
//!   `GpuIntegrator` implementation, registered in one line of `gpu_integrators!`;
//!   `restir` runs Lin et al. 2021 §5's passes) ↔ `kernel_setup` (bind groups, buffers,
//!   pipeline and timestamp queries before a kernel's first dispatch) and `render` (the
//!   progressive render loop of the per-sample kernels).
//!
//! Tests: `contract_test`, `pipelines_test`, `render_test`.

pub mod accumulation;
pub mod context;
pub mod contract;
#[cfg(test)]
mod contract_test;
pub mod diagnostics;
mod integrators;
mod kernel_setup;
pub mod lights;
pub mod medium_records;
mod pin_kernel;
pub mod pin_stream;
pub mod pins;
pub mod pipelines;
#[cfg(test)]
mod pipelines_test;
pub mod render;
#[cfg(test)]
mod render_test;
pub mod scene_buffers;
pub mod shaders;
pub mod surfaces;

pub use context::{Gpu, GpuError};
/// `restir`'s passes and `visopt`'s scratch budget, for the experiments.
pub use integrators::{restir, visopt};

/// How many devices [`test_gpu`] opens at most.
pub const TEST_DEVICES: usize = 2;

/// For tests: a GPU of the process's pool, or `None` with a visible
/// message. With `FOGBANK_REQUIRE_GPU=1` (set by `.ci/run`) a missing
/// adapter is a failure.
///
/// The pool holds one device per core (at most [`TEST_DEVICES`]) and each
/// call hands out a handle to the device fewest running tests hold, so that
/// the tests of one binary build each pipeline once per device. More than
/// one because lavapipe compiles a kernel at its first dispatch on the
/// device's one queue thread, which stalls every test on that device for the
/// minutes a scattering kernel takes to compile: with one device the suite
/// on an empty Mesa cache kept one of two cores idle most of its 23 minutes
/// (1372 s wall, 1589 s CPU), with two it takes 14 (docs/results/build.md).
pub fn test_gpu() -> Option<Gpu> {
    static POOL: std::sync::OnceLock<Result<Vec<Gpu>, GpuError>> = std::sync::OnceLock::new();
    let pool = POOL.get_or_init(|| {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        (0..cores.clamp(1, TEST_DEVICES))
            .map(|_| Gpu::new())
            .collect()
    });
    match pool {
        Ok(devices) => {
            // One choice at a time, so that two tests starting together
            // count each other's handles.
            static CHOOSING: std::sync::Mutex<()> = std::sync::Mutex::new(());
            let _one = CHOOSING.lock().unwrap_or_else(|e| e.into_inner());
            devices.iter().min_by_key(|g| g.handles()).cloned()
        }
        Err(e) => {
            if std::env::var("FOGBANK_REQUIRE_GPU").as_deref() == Ok("1") {
                panic!("FOGBANK_REQUIRE_GPU=1 but no GPU: {e}");
            }
            eprintln!("SKIPPED (no GPU adapter): {e}");
            None
        }
    }
}
