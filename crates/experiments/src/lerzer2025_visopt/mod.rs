//! N. Lerzer, C. Dachsbacher, *View-Dependent Visibility Optimization for
//! Monte Carlo Volume Visualization*, Computer Graphics Forum 2025 (the
//! project's Lerzer and Dachsbacher 2025): the `visopt` integrator, which optimises extinction
//! for the visibility of important regions along camera rays, against the
//! ray-marched optimisation of Ament et al. (AZD17).
//!
//! - `fig2`: Fig. 2 / Eq. 5, AZD17's sums as printed against the
//!   Δx-normalised ones as the step shrinks (`visopt-fig2`);
//! - `fig7`: Fig. 7, convergence of the importance segments, adaptive
//!   against uniform passes (`visopt-fig7`);
//! - `overhead`: Fig. 5 (right) and Table 3 on the CPU, what the
//!   optimisation costs per pass (`visopt-overhead`);
//! - `equal_time`: Figs. 5 and 8 on the CPU, visopt against AZD17 at equal
//!   time and visopt's error against spp (`visopt-equal-time`);
//! - `head`: Figs. 9, 10 and 12 on the MNI152 head: scattering settings,
//!   a two-valued importance swept, light-ray list sizes (`visopt-head`);
//! - `pre`: Figs. 3 and 11, post- against pre-interpolative importance
//!   (`visopt-pre`);
//! - `teaser`: Fig. 1, frame times and errors of DVR, single and multiple
//!   scattering (`visopt-teaser`);
//! - `denoise`: Fig. 6, equal time with a denoiser (`visopt-denoise`);
//! - `gpu_frame_time`: Table 3 and Fig. 1's frame times on a GPU
//!   (`visopt-gpu-frame-time`).

pub mod denoise;
pub mod equal_time;
pub mod fig2;
pub mod fig7;
pub mod gpu_frame_time;
pub mod head;
pub mod overhead;
pub mod pre;
pub mod teaser;
