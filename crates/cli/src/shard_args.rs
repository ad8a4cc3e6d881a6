//! `--shard I/N` for the commands whose work splits exactly (`render`,
//! `stats`): which part to do.

use clap::Args;
use fogbank::{Shard, ShardMode};

#[derive(Args, Clone)]
pub struct ShardArgs {
    /// Do shard I of N (0-based) of the work and write a partial result
    /// (`.fbpart`) for `fogbank merge`, which adds the N parts up to the
    /// single run's image bit for bit. For Slurm array jobs and Kubernetes
    /// Indexed Jobs: see `deploy/`.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// How shards split the work: `samples` (each shard renders spp/N sample
    /// indices of every pixel) or `tiles` (every N-th 32×32 tile, all samples).
    #[arg(
        long,
        value_name = "MODE",
        default_value = "samples",
        requires = "shard"
    )]
    pub shard_mode: String,
}

impl ShardArgs {
    pub fn get(&self) -> Result<Option<Shard>, String> {
        match &self.shard {
            None => Ok(None),
            Some(s) => Ok(Some(Shard::parse(
                s,
                ShardMode::parse(&self.shard_mode).map_err(|e| format!("--shard-mode: {e}"))?,
            )?)),
        }
    }
}
