//! `visopt`: Lerzer and Dachsbacher 2025 (Lerzer & Dachsbacher 2025), view-dependent
//! visibility optimisation for Monte Carlo volume visualisation.
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `p` | 1 | Eq. 8: weight of the data term (> 0); lengths in the medium's [−1, 1]³ units |
//! | `q` | 70 | Eq. 7: weight of important matter behind a point: thins occluders |
//! | `r` | 30 | Eq. 7: weight of important matter in front of a point: thins background clutter |
//! | `lambda` | 1 | Eq. 8: exponent of (1 − g)^{2λ} |
//! | `samples` | 64 | N, importance samples per camera ray and pass |
//! | `passes` | 4 | 1 uniform + (passes − 1) adaptive camera-list passes, then the lists are frozen |
//! | `merge_distance` | 0 (auto: 2·L/N) | d of Alg. 1, in [−1, 1]³ units; 0 picks 2·L/N per ray |
//! | `gap_share` | 0.5 | share of adaptive strata at change points and ray ends |
//! | `light_samples` | 200 | importance samples of each NEE ray's list (0: light rays unoptimised) |
//! | `scattering` | single | `single`, `first` (optimised first NEE + plain multiple scattering), `all` (every NEE optimised) |
//! | `max_depth` | 64 | longest path in scattering vertices, with `first` or `all` |
//! | `shading` | false | add the gradient lobe ‖∇μ_t‖ (H·N)^n (N·ω_L)₊ to HG at NEE (§3; the paper enables it in Figs. 6 and 9) |
//! | `n` | 40 | Blinn–Phong exponent of the lobe |
//! | `optimise` | true | false: plain DVR (μ' = μ) with the same sampler |
//!
//! The medium's `[[media.importance]]` rules define the importance (see
//! [`crate::world::importance`]).

pub mod integrator;
pub mod lists;
pub mod optimised;
pub mod params;
pub mod reference;
pub mod sampling;
pub mod segments;

pub use integrator::VisOpt;
pub use params::{VisOptParams, PARAMS};
