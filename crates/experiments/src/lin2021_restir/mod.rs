//! D. Lin, C. Wyman, C. Yuksel, *Fast Volume Rendering with Spatiotemporal
//! Reservoir Resampling*, ACM Transactions on Graphics 40(6), 2021 (the
//! project's Lin et al. 2021): volumetric ReSTIR against the paper's baseline with
//! the paper's protocol (§6), on fogbank's stand-in scenes.
//!
//! - `equal_time`: Figs. 16, 17 and 22, ReSTIR against the baseline at
//!   equal time (`restir-equal-time`);
//! - `surfaces`: Figs. 1, 18 and the surface curve of Fig. 22, the same
//!   with surfaces and emitting shapes (`restir-surfaces`);
//! - `ablation`: Figs. 4, 7, 10, 11, 12, 14, 15, 19, 21, one parameter
//!   changed per row (`restir-ablation`);
//! - `dynamic`: Figs. 8, 13, 14 and 20, moving scenes and accumulation
//!   (`restir-dynamic`);
//! - `bias`: Fig. 9, the bias of temporal reuse under motion
//!   (`restir-bias`);
//! - `gpu_frame_time`: §6's frame-time table on a GPU at 1920×1080
//!   (`restir-gpu-frame-time`);
//! - `race`: ReSTIR's side of the equal-time protocol, a sequence stepped
//!   frame by frame so that per-pixel rivals take turns with it;
//! - `sequence`: ReSTIR sequences over an animated scene's frames, with
//!   per-frame references;
//! - `scenes`: the scenes of the dynamic studies as scene text.

pub mod ablation;
pub mod bias;
pub mod dynamic;
pub mod equal_time;
pub mod gpu_frame_time;
pub mod race;
pub mod scenes;
pub mod sequence;
pub mod surfaces;
