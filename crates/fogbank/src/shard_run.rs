//! The record a shard's partial result keeps of where and how it ran.

use fogbank_partial::partial::ShardRun;
use fogbank_render::shard::Shard;

/// This machine's name.
pub fn host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|s| s.trim().to_string())
        .or_else(|_| std::env::var("HOSTNAME"))
        .unwrap_or_else(|_| "unknown".into())
}

/// The record of one shard's run of `spp` samples per pixel in total.
pub fn run(shard: Shard, spp: u32, seconds: f64, threads: usize) -> ShardRun {
    ShardRun {
        shard,
        piece: shard.piece(spp),
        seconds,
        threads,
        host: host(),
    }
}
