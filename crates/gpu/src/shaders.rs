//! WGSL sources, one concept per file, concatenated per kernel (WGSL has no
//! includes). Order matters only for readability: WGSL resolves names
//! module-wide.

pub const RNG: &str = include_str!("wgsl/rng.wgsl");
pub const MEDIUM: &str = include_str!("wgsl/medium.wgsl");
pub const DDA: &str = include_str!("wgsl/dda.wgsl");
pub const REGULAR_TRACKING: &str = include_str!("wgsl/regular_tracking.wgsl");
pub const NULL_COLLISIONS: &str = include_str!("wgsl/null_collisions.wgsl");
pub const TRACK_LENGTH: &str = include_str!("wgsl/track_length.wgsl");
pub const RATIO_TRACKING: &str = include_str!("wgsl/ratio_tracking.wgsl");
pub const RNG_STREAMS_KERNEL: &str = include_str!("wgsl/rng_streams_kernel.wgsl");
pub const TRANSMITTANCE_KERNEL: &str = include_str!("wgsl/transmittance_kernel.wgsl");

/// Every estimator's source, after the shared media code.
pub fn estimators() -> String {
    [
        RNG,
        MEDIUM,
        DDA,
        REGULAR_TRACKING,
        NULL_COLLISIONS,
        TRACK_LENGTH,
        RATIO_TRACKING,
    ]
    .join("\n")
}

pub fn transmittance_kernel() -> String {
    format!("{}\n{}", estimators(), TRANSMITTANCE_KERNEL)
}
