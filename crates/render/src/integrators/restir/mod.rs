//! `restir`: volumetric ReSTIR (Lin et al. 2021, Lin, Wyman & Yuksel 2021),
//! spatiotemporal reservoir resampling of volumetric paths. Each frame runs
//! the passes of §5 over every pixel ([`frame`]): M candidate random walks
//! per pixel through conservative mips ([`candidates`]), temporal reuse of
//! the previous frame's reservoir ([`temporal`]), one round of spatial
//! reuse ([`spatial`]), both combined with Talbot MIS ([`combine`]), and
//! final shading of the selected path with unbiased transmittance.
//!
//! Rendering a static scene with `fogbank render`, each of the `spp` passes
//! renders an independent sequence of `frames` frames and keeps its last
//! frame, so the image is the mean of independent last frames and its
//! variance layer is their variance (what the z-test against `volpath`
//! needs). Primary rays go through pixel centres (`render.pixel_jitter` is
//! ignored): reuse compares targets of fixed pixel rays.
//!
//! Shapes are path vertices ([`surface`], Lin et al. 2021 §4.2), on the CPU and
//! the GPU (`restir/surface.wgsl`): walks scatter off them by their BSDFs
//! (which must have no delta lobe), light sampling leaves from them, a
//! shifted surface vertex is the closest surface along the shifted ray,
//! emitting shapes are light-sampling candidates picked by power whose
//! point on the light stays fixed under reuse (area measure), and Q
//! defaults to 10 (§5.3). Null boundaries and thin dielectrics are refused
//! (`shared/occluders.rs`).
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `max_depth` | 3 | K, the longest path in vertices, medium or surface (1..=8) |
//! | `candidates` | 4 | M, random walks per pixel and frame |
//! | `reuse` | spatiotemporal | `none` (plain RIS), `spatial`, `temporal`, `spatiotemporal` |
//! | `mis` | talbot | combination MIS: `talbot` (Eq. 11), `stochastic` (Eq. 10), `uniform` (1/M, Eq. 9, biased), `pairwise` (beyond the paper: 2N target evaluations for N neighbours instead of N(N + 1)) |
//! | `temporal_cap` | 4 (10 with shapes) | Q: the previous reservoir's M is capped at Q·M |
//! | `neighbours` | 3 | spatial neighbours besides the pixel itself (0..=32) |
//! | `radius` | 10 | spatial reuse radius in pixels |
//! | `frames` | 8 | frames per sequence of a static render (the last one is kept) |
//! | `primary_mip` | 1 | mip of candidate regular tracking on the primary segment (0: exact trilinear free flight at full resolution) |
//! | `indirect_mip` | 2 | mip of candidate regular tracking after the first vertex |
//! | `nee_mip` | 2 | mip of the ray-marched T̃ on candidate NEE segments |
//! | `nee_transmittance` | true | false: candidates ignore NEE transmittance (Fig. 11) |
//! | `reuse_mip` | 1 | mip of the ray-marched T̃ in the reuse target p̂ (0: full resolution) |
//! | `reuse_step` | 1 | marching step of T̃ in p̂, in voxel diagonals of `reuse_mip` |
//! | `estimator` | analytic_trilinear | transmittance of final shading: exact, or any unbiased estimator |
//! | `reuse_bc4` | false | march the reuse T̃ through a BC4-compressed copy of its mip (4 bits a voxel, §5.1; p̂ only, so no bias) |
//! | `primary_table` | true | tabulate the reuse T̃ of every pixel's primary ray once per frame (`restir::primary`): the same p̂ bit for bit with one lookup per first segment instead of a march (CPU; the GPU marches) |
//! | `shift` | direction | path shift of reuse: `direction` (ω_i and z_i copied, §4.2's default) or `vertex` (x_2 … x_k kept, 1/z² terms; not with shapes) |
//! | `reprojection` | true | temporal reuse follows x_1 to the previous frame (false: the same pixel, Fig. 8) |
//! | `velocity_resampling` | true | a sample without x_1 reprojects through a medium point resampled ∝ σ_t·T along its ray (§5.2, Fig. 13) |
//! | `rr_depth` | 3 | Russian roulette by albedo after vertex x_rr_depth (only when K > rr_depth, §6.1) |

pub mod candidates;
pub mod combine;
pub mod frame;
pub mod integrator;
pub mod neighbours;
pub mod params;
pub mod path;
pub mod primary;
pub mod reservoir;
pub mod spatial;
pub mod surface;
pub mod target;
pub mod temporal;
pub mod velocity_resampling;
pub mod volume;

pub use integrator::{FrameData, Restir};
pub use params::{RestirParams, Reuse, ReuseMis, PARAMS};
