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

    /// The estimate of a k-generic estimator run for one channel (k = [1]).
    pub fn of_one_channel(([transmittance], lookups): ([f32; 1], u32)) -> Estimate {
        Estimate {
            transmittance,
            lookups,
        }
    }
}
