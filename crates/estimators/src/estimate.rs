//! What one transmittance estimate returns.

/// One transmittance estimate and what it cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    pub transmittance: f32,
    /// Full-resolution lookups (filtered σ_t evaluations) taken.
    pub lookups: u32,
}

impl Estimate {
    pub const ONE: Estimate = Estimate {
        transmittance: 1.0,
        lookups: 0,
    };
}
