//! `visopt`: seed 003 (Lerzer & Dachsbacher 2025), view-dependent
//! visibility optimisation for Monte Carlo volume visualisation.
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `p`, `q`, `r`, `lambda` | 1, 70, 30, 1 | Eq. 7–8 (lengths in the medium's [−1, 1]³ units) |
//! | `samples` | 64 | N, importance samples per camera ray and pass |
//! | `passes` | 4 | 1 uniform + 3 adaptive passes, then the lists are frozen |
//! | `merge_distance` | 0 (auto 2·L/N) | d of Alg. 1 |
//! | `gap_share` | 0.5 | share of adaptive strata at change points and ray ends |
//! | `light_samples` | 200 | samples of each NEE ray's list (0: light rays unoptimised) |
//! | `scattering` | `single` | `single`, `first` (optimised first NEE + plain MS), `all` (every NEE optimised) |
//! | `max_depth` | 64 | path length with `first`/`all` |
//! | `shading` | false | HG plus the gradient lobe at NEE (§3; the paper enables it in Figs. 6 and 9) |
//! | `n` | 40 | the lobe's exponent |
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
