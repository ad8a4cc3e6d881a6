//! Volumetric ReSTIR (seed 002): spatiotemporal reservoir resampling of
//! volumetric paths. Work in progress (issue 18): so far the reservoir and
//! its combination rules; the candidate, temporal, spatial and shading
//! passes and the `restir` integrator come next, one file per pass.

pub mod neighbours;
pub mod reservoir;
