//! Distance samplers: where along a ray the next real collision happens.
//!
//! Free-flight samplers (delta, decomposition and regular tracking) draw t
//! with density T(t)·σ_t(t) on `[t0, t1]` and report `None` (escape) with
//! probability T(t1); their density cancels in the path throughput. The
//! equiangular sampler draws t with a known closed-form density that does not
//! depend on the medium.

pub mod analytic_trilinear;
pub mod decomposition_tracking;
pub mod delta_tracking;
pub mod delta_tracking_ratio;
pub mod equiangular;
pub mod ray_marching;
pub mod regular_tracking;

/// A free-flight distance sample and what it cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FreeFlight {
    /// Parameter of the real collision, `None` when the ray escapes `[t0, t1]`.
    pub t: Option<f32>,
    pub lookups: u32,
}

/// A free flight with what its density is made of, for samplers whose pdf
/// has a closed form (regular tracking through a piecewise-constant grid,
/// exact trilinear free flight): p(t) = σ_t(t)·exp(−τ(t)), and the escape
/// probability exp(−τ) over the whole range when `t` is `None`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackedFlight {
    pub t: Option<f32>,
    /// σ_t at `t` (0 on escape), per unit of the ray parameter.
    pub sigma_t: f64,
    /// Optical depth from the start to `t`, or over the whole range on escape.
    pub tau: f64,
    pub lookups: u32,
}

impl TrackedFlight {
    pub fn free_flight(&self) -> FreeFlight {
        FreeFlight {
            t: self.t,
            lookups: self.lookups,
        }
    }
}
