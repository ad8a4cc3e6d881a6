//! The distance-sampling strategies of `point_mis` (Peters 2025 §5, §6.2).

/// How distances along the camera ray are sampled and combined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Delta tracking; T(t)μ(t) cancels with its density (Peters 2025 §2.1).
    FreeFlight,
    /// Kulla & Fajardo 2012 towards the chosen light; T(t0) by ratio tracking.
    Equiangular,
    /// Balance heuristic with Miller et al. 2019's weights: μ T_rt/(p0 + μ T_rt)
    /// with T_rt from delta tracking's own null collisions (Peters 2025 §6.2).
    MisMiller,
    /// Eq. 10 with the naive weight g(X) of one optical-depth estimate
    /// (m = 1, 2N lookups, the same cost as two of N). Biased.
    MisNaive,
    /// Eq. 9 with jackknife weights Re g(X̄ + iS) (Eq. 12, App. F) and an
    /// independent ratio-tracking estimate of T(t0). Unbiased (App. D).
    MisJackknife,
    /// Eq. 10: jackknife weights that also carry the transmittance. Biased.
    MisJackknifeBiased,
}

impl Strategy {
    pub const ALL: [Strategy; 6] = [
        Strategy::FreeFlight,
        Strategy::Equiangular,
        Strategy::MisMiller,
        Strategy::MisNaive,
        Strategy::MisJackknife,
        Strategy::MisJackknifeBiased,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Strategy::FreeFlight => "free_flight",
            Strategy::Equiangular => "equiangular",
            Strategy::MisMiller => "mis_miller",
            Strategy::MisNaive => "mis_naive",
            Strategy::MisJackknife => "mis_jackknife",
            Strategy::MisJackknifeBiased => "mis_jackknife_biased",
        }
    }

    pub fn parse(s: &str) -> Option<Strategy> {
        Strategy::ALL.into_iter().find(|k| k.name() == s)
    }

    /// Whether the expected radiance differs from the single-scattering
    /// integral (given an unbiased light-ray `estimator`).
    pub fn biased(self) -> bool {
        matches!(self, Strategy::MisNaive | Strategy::MisJackknifeBiased)
    }

    /// Distance samples per pixel sample.
    pub fn distance_samples(self) -> u32 {
        match self {
            Strategy::FreeFlight | Strategy::Equiangular => 1,
            _ => 2,
        }
    }
}
