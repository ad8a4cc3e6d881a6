//! `ray_marching`: exp(−X) of N equidistant samples sharing one jitter
//! (`crate::ray_marching`), biased.

use super::options::{OptionValue, Options};
use super::plugin::{read_samples, EstimatorPlugin};
use crate::{ray_marching, Estimate};
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::MediumView;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayMarching {
    pub samples: u32,
    /// Shrink the segment to the non-empty super-voxels first.
    pub clip: bool,
}

impl EstimatorPlugin for RayMarching {
    const NAME: &'static str = "ray_marching";
    const BIASED: bool = true;
    const DESCRIPTION: &'static str = "exp(−X), N equidistant samples sharing one jitter";
    const KEYS: &'static [&'static str] = &["samples", "clip"];
    const OPTIONS_HELP: &'static str = "samples=10, clip=false";

    fn read(o: &Options) -> Result<Self, String> {
        Ok(RayMarching {
            samples: read_samples(o)?,
            clip: o.flag("clip")?.unwrap_or(false),
        })
    }

    fn options(&self) -> Options {
        Options::default()
            .with("samples", OptionValue::Int(self.samples.into()))
            .with("clip", OptionValue::Bool(self.clip))
    }

    fn transmittance(&self, view: MediumView<'_>, seg: &RaySegment, rng: &mut Pcg32) -> Estimate {
        let (samples, clip) = (self.samples, self.clip);
        with_view!(view, v => ray_marching::transmittance(&v, seg, samples, clip, rng))
    }
}
