//! S. Hansen, *Pin Transmittance Sampling*, master thesis, Karlsruhe
//! Institute of Technology (KIT), 2025 (the project's Hansen 2025): pins, a
//! grid of precomputed free-flight samples that replaces tracking for
//! multiple scattering (PinMS), against the ray-marching baseline and
//! fogbank's unbiased `volpath`.
//!
//! - `fig3_4`: Fig. 3.4, why the collision matrix is decomposed
//!   (`pins-fig3-4`);
//! - `memory`: Fig. 4.9, memory of the density texture and the pin grid
//!   (`pins-memory`);
//! - `instances`: Fig. 4.10, many overlapping instances of one cloud
//!   (`pins-instances`);
//! - `runtime`: Fig. 4.11, time per sample of ray marching over PinMS on
//!   the CPU and the GPU (`pins-runtime`, `pins-gpu-runtime`);
//! - `ablation`: Figs. 4.2–4.5, 4.7, 4.8, one pin setting per row
//!   (`pins-ablation`);
//! - `stream`: Figs. 4.1 and 4.6, the pin stream against static pins
//!   (`pins-stream`);
//! - `boundary`: Fig. 4.12, the boundary bias of hard-edged volumes
//!   (`pins-boundary`);
//! - `surfaces`: Figs. 4.12–4.13 with surfaces, errors over time and the
//!   bias ordering per step (`pins-surfaces`);
//! - `convergence`: Figs. 4.12–4.24, error over time of ray marching,
//!   PinMS and `volpath` (`pins-convergence`);
//! - `bias`: fogbank's own bias bar for pins as the grid grows
//!   (`pins-bias`).

pub mod ablation;
pub mod bias;
pub mod boundary;
pub mod convergence;
pub mod fig3_4;
pub mod instances;
pub mod memory;
pub mod runtime;
pub mod stream;
pub mod surfaces;
