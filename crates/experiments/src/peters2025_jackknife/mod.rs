//! C. Peters, *Jackknife Transmittance and MIS Weight Estimation*, ACM
//! Transactions on Graphics 44(6), 2025 (the project's Peters 2025): the
//! jackknife estimate cos(S)e^{−X̄} of transmittance (Eq. 4), its use for
//! MIS weights (Eq. 12), and the ray marching (Alg. 1/2) that feeds it.
//!
//! - `fig1`: Fig. 1, a cloud under a light probe at 32 spp per NEE
//!   transmittance estimator (bias, variance, fireflies, time);
//! - `fig2`: Fig. 2, jackknife against naive bias and std for six
//!   distributions of the optical-depth estimates;
//! - `fig3`: Fig. 3 and App. A, relative RMSE of both for normal estimates;
//! - `fig4`: Figs. 4 and 6 (§4.1), histograms of stratified against uniform
//!   jittered ray marching on a smooth and a sparse profile (`fig4`, `fig6`);
//! - `fig5`: Fig. 5 (§4.1), RMSE against the sample count per sampler;
//! - `fig7`: Fig. 7 (Eq. 11, App. E/F), bias of MIS-weight estimates;
//! - `fig12`: Figs. 12 and 13, the `point_mis` integrator's six
//!   distance-sampling strategies at equal pixel samples;
//! - `fig13`: Fig. 13, the bias of Eq. 10's biased MIS with naive against
//!   jackknife weights in a high-spp inset;
//! - `fig14`: Fig. 14 and §6.3, the explosion failure case in 2D;
//! - `table1`: Table 1, many short against few long estimates at 24
//!   samples;
//! - `distributions`: the six distributions of Fig. 2 with their
//!   moment-generating functions, random variates, normality tests;
//! - `profile`: the one-dimensional extinction profiles of Figs. 4–6 and
//!   Table 1 as a volume the project's estimators march.

pub mod distributions;
pub mod fig1;
pub mod fig12;
pub mod fig13;
pub mod fig14;
pub mod fig2;
pub mod fig3;
pub mod fig4;
pub mod fig5;
pub mod fig7;
pub mod profile;
pub mod table1;
