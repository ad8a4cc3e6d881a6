//! The options of a volume file fogbank writes (`export`, `convert`).

use clap::Args;
use fogbank::export::{Codec, NanoValue};

#[derive(Args)]
pub struct VolumeWriteArgs {
    /// `.vdb` only: store values as half floats.
    #[arg(long)]
    pub half: bool,
    /// none, zip or blosc.
    #[arg(long, default_value = "none")]
    pub codec: String,
    /// `.nvdb` only: quantise leaves to fp8 or fp16 (default: float).
    #[arg(long)]
    pub quantise: Option<String>,
}

impl VolumeWriteArgs {
    /// The codec and the NanoVDB value type asked for.
    pub fn parse(&self) -> Result<(Codec, NanoValue), String> {
        let codec = Codec::parse(&self.codec)
            .ok_or_else(|| format!("--codec {}: expected none, zip or blosc", self.codec))?;
        let value = match self.quantise.as_deref() {
            None => NanoValue::Float,
            Some(q) => NanoValue::parse(q)
                .filter(|v| *v != NanoValue::Float)
                .ok_or_else(|| format!("--quantise {q}: expected fp8 or fp16"))?,
        };
        Ok((codec, value))
    }
}
