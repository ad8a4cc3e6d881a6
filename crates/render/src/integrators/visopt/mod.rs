//! Seed 003 (Lerzer & Dachsbacher 2025): view-dependent visibility
//! optimisation for Monte Carlo volume visualisation. The integrator is
//! being built in parts; so far the per-ray importance segments (§5.1,
//! Alg. 1, Eq. 7–8) and their sampling (§5.2).

pub mod sampling;
pub mod segments;
