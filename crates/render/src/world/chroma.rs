//! Chromatic extinction: σ_t differing per RGB channel,
//! σ_t,c(x) = s_c · d(x) — one density, a scale per channel
//! (`sigma_t_scale = [s_r, s_g, s_b]`).
//!
//! Free-flight sampling tracks the channel of largest extinction (the
//! medium's own `sigma_t_scale` is max_c s_c), and its collisions serve as
//! the null collisions of every channel: at one, channel c scatters with
//! probability a_c k_c, absorbs with (1 − a_c) k_c and passes with 1 − k_c,
//! where k_c = s_c / max s and a_c is the albedo. The path picks scatter or
//! pass with probabilities proportional to the largest channel weight of
//! each (spectral tracking, Kutz et al. 2017, §5) and divides each channel
//! by its own probability, so every channel stays unbiased whatever the
//! path picks. Shadow rays estimate each channel's transmittance with that
//! channel's own medium (its scale and super-voxel statistics), so every
//! transmittance estimator works per channel; those whose sample positions
//! do not depend on the scale (the jackknife, ray marching, regular
//! tracking) serve all three channels from one walk
//! (`fogbank_estimators::scaled`).
//!
//! With `density_rgb = true` the density is a 3-channel `.vol` (Mitsuba's
//! RGB `gridvolume`) or in-memory array (pbrt's `rgbgrid`),
//! σ_t,c(x) = s_c · g_c(x): the tracked grid is the per-voxel maximum of
//! s_c g_c / max s, whose trilinear interpolant bounds every channel's,
//! and k_c(x) = σ_t,c(x) / σ̄(x) is read at each collision
//! (trilinear filtering only, so that the ratio is the one of the fields
//! the collision was sampled in).

use super::field::{FieldData, FieldDesc};
use crate::error::SceneError;
use fogbank_math::Vec3;
use fogbank_volume::loaders::vol;
use fogbank_volume::{BrickGrid, DensityData, Medium, Precision};
use std::path::Path;
use std::sync::Arc;

#[derive(Clone, Debug)]
pub struct Chroma {
    /// k_c = s_c / max_c s_c: the largest is 1.
    pub k: Vec3,
    /// Each channel's medium: the same density (shared voxels) with scale
    /// s_c and the super-voxel statistics of that scale, or (`varying`) the
    /// channel's own grid.
    pub channels: Arc<[Medium; 3]>,
    /// Per-channel grids: k varies in space and is read at each collision.
    varying: bool,
}

/// What a collision of the tracked channel does to the path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ChromaEvent {
    /// A real scattering event: multiply the throughput by this weight.
    Scatter(Vec3),
    /// A null collision: multiply by this weight and continue straight on.
    Pass(Vec3),
    /// No channel carries anything further.
    Stop,
}

impl Chroma {
    /// The chromatic part of a medium whose channel scales are `scales`
    /// (`medium` has scale max_c s_c), or `None` when they are all equal.
    pub fn new(medium: &Medium, scales: [f32; 3]) -> Option<Chroma> {
        let max = scales[0].max(scales[1]).max(scales[2]);
        if scales.iter().all(|&s| s == max) {
            return None;
        }
        let channel = |s: f32| {
            Medium::classified(
                medium.data.clone(),
                medium.opacity.clone(),
                s,
                medium.filter,
                medium.index_to_world,
                medium.supervoxels.size,
            )
        };
        Some(Chroma {
            k: Vec3::from(scales) / max,
            channels: Arc::new(scales.map(channel)),
            varying: false,
        })
    }

    /// The chromatic part of a medium with per-channel grids `grids`
    /// (from [`rgb_density`]) and scales `scales`; `tracked` is the medium
    /// built from the grids' maximum.
    pub fn from_grids(tracked: &Medium, grids: [DensityData; 3], scales: [f32; 3]) -> Chroma {
        let max = scales[0].max(scales[1]).max(scales[2]);
        let channel = |g, s| {
            let (filter, xf) = (tracked.filter, tracked.index_to_world);
            Medium::new(g, s, filter, xf, tracked.supervoxels.size)
        };
        let [r, g, b] = grids;
        let channels = [
            channel(r, scales[0]),
            channel(g, scales[1]),
            channel(b, scales[2]),
        ];
        Chroma {
            k: Vec3::from(scales) / max.max(f32::MIN_POSITIVE),
            channels: Arc::new(channels),
            varying: true,
        }
    }

    /// k at world point `p` of a collision in `tracked` (the medium whose
    /// collisions the path samples), counting the lookups it takes.
    pub fn k_at(&self, tracked: &Medium, p: Vec3, lookups: &mut u32) -> Vec3 {
        if !self.varying {
            return self.k;
        }
        let q = tracked
            .world_to_index
            .transform_point3(p.as_dvec3())
            .as_vec3();
        *lookups += 4;
        let max = tracked.sigma_t_smooth(q);
        if max.is_nan() || max <= 0.0 {
            return Vec3::ZERO;
        }
        // ≤ 1 but for rounding: the tracked grid bounds each channel's.
        Vec3::from(
            self.channels
                .each_ref()
                .map(|m| (m.sigma_t_smooth(q) / max).min(1.0)),
        )
    }

    /// Scatter or pass at a collision of the tracked channel with path
    /// throughput `beta`, albedo `albedo`, channel ratios `k` (from
    /// [`Chroma::k_at`]) and uniform `u`.
    pub fn event(&self, beta: Vec3, albedo: Vec3, k: Vec3, u: f32) -> ChromaEvent {
        let scatter = albedo * k;
        let pass = Vec3::ONE - k;
        let (ws, wp) = ((beta * scatter).max_element(), (beta * pass).max_element());
        if (ws + wp).is_nan() || ws + wp <= 0.0 {
            return ChromaEvent::Stop;
        }
        let p_scatter = ws / (ws + wp);
        if u < p_scatter {
            ChromaEvent::Scatter(scatter / p_scatter)
        } else {
            ChromaEvent::Pass(pass / (1.0 - p_scatter))
        }
    }

    /// Whether k varies in space (per-channel grids, `density_rgb`).
    pub fn varying(&self) -> bool {
        self.varying
    }

    /// k when every channel is the tracked density times a constant (an
    /// estimator may then serve all three from one walk), else `None`.
    pub fn shared_scale(&self) -> Option<[f32; 3]> {
        (!self.varying).then(|| self.k.to_array())
    }

    /// Each channel's transmittance from `estimate(channel medium)` →
    /// (T, lookups); channels of one density with equal scales share one
    /// estimate.
    pub fn transmittance(&self, mut estimate: impl FnMut(&Medium) -> (f32, u32)) -> (Vec3, u32) {
        let k = self.k.to_array();
        let (mut t, mut lookups) = ([0.0f32; 3], 0);
        for c in 0..3 {
            match (0..c).find(|&b| !self.varying && k[b] == k[c]) {
                Some(b) => t[c] = t[b],
                None => {
                    let (tc, n) = estimate(&self.channels[c]);
                    t[c] = tc;
                    lookups += n;
                }
            }
        }
        (Vec3::from(t), lookups)
    }
}

/// The three channel grids of a 3-channel `.vol` or in-memory array,
/// their dims, index → world map and a name for messages.
type Channels = (
    [BrickGrid<f32>; 3],
    [u32; 3],
    fogbank_math::DAffine3,
    String,
);

fn rgb_channels(d: &FieldDesc, key: &str, base: &Path) -> Result<Channels, SceneError> {
    let err = |e: fogbank_volume::VolumeError| SceneError(format!("{key}: {e}"));
    match (d.files.path_of("vol"), &d.array, d.channel) {
        (Some(f), None, None) => {
            let path = base.join(f);
            let v = vol::read_vol(&path).map_err(err)?;
            if v.channels != 3 {
                return Err(SceneError(format!(
                    "{key}: density_rgb needs a 3-channel .vol, {} has {}",
                    path.display(),
                    v.channels
                )));
            }
            let g = [v.channel_grid(0).map_err(err)?, v.channel_grid(1).map_err(err)?, v.channel_grid(2).map_err(err)?];
            Ok((g, v.dims, v.index_to_world(), path.display().to_string()))
        }
        (None, Some(name), None) => {
            let a = super::arrays::get(name, key)?;
            if a.channels() != 3 {
                return Err(SceneError(format!(
                    "{key}: density_rgb needs a 3-channel array, {} has {}",
                    a.describe(),
                    a.channels()
                )));
            }
            let g = [a.channel_grid(0).map_err(err)?, a.channel_grid(1).map_err(err)?, a.channel_grid(2).map_err(err)?];
            Ok((g, a.dims(), a.index_to_world(), a.describe()))
        }
        _ => Err(SceneError(format!(
            "{key}: density_rgb reads the three channels of a `.vol` or an in-memory `array` (no `channel`)"
        ))),
    }
}

/// The density of `density_rgb = true`: the tracked grid (the per-voxel
/// maximum of s_c g_c / max s, in f32 so that it bounds every channel) as
/// the medium's field, and the three channel grids g_c.
pub fn rgb_density(
    d: &FieldDesc,
    key: &str,
    base: &Path,
    scales: [f32; 3],
) -> Result<(FieldData, [DensityData; 3]), SceneError> {
    let (g, dims, index_to_world, source) = rgb_channels(d, key, base)?;
    let max = scales[0].max(scales[1]).max(scales[2]);
    let k = scales.map(|s| if max > 0.0 { s / max } else { 1.0 });
    let tracked = BrickGrid::from_fn(dims, |i, j, l| {
        let (i, j, l) = (i as i32, j as i32, l as i32);
        (0..3)
            .map(|c| k[c] * g[c].fetch(i, j, l).max(0.0))
            .fold(0.0, f32::max)
    })
    .map_err(|e| SceneError(format!("{key}: {e}")))?;
    let data = FieldData {
        data: DensityData::from_f32(tracked, Precision::F32),
        to_world: index_to_world,
        source: format!("{source} (RGB)"),
        units: None,
    };
    Ok((data, g.map(|g| DensityData::from_f32(g, Precision::F32))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use fogbank_volume::{DensityData, Filter, Precision};

    fn chroma(scales: [f32; 3]) -> Option<Chroma> {
        let grid = fogbank_volume::BrickGrid::from_fn([4, 4, 4], |_, _, _| 1.0).unwrap();
        let data = DensityData::from_f32(grid, Precision::F32);
        let max = scales[0].max(scales[1]).max(scales[2]);
        let m = Medium::new(data, max, Filter::Trilinear, Default::default(), 4);
        Chroma::new(&m, scales)
    }

    #[test]
    fn equal_scales_are_achromatic() {
        assert!(chroma([2.0; 3]).is_none());
        let c = chroma([1.0, 2.0, 4.0]).unwrap();
        assert_eq!(c.k, Vec3::new(0.25, 0.5, 1.0));
        assert_eq!(c.channels[0].sigma_t_scale, 1.0);
        assert_eq!(c.channels[2].supervoxels.cells[0].max, 4.0);
    }

    /// The expected weight of each event equals its channel's probability:
    /// E[scatter weight] = a_c k_c, E[pass weight] = 1 − k_c.
    #[test]
    fn event_weights_are_unbiased_per_channel() {
        let c = chroma([0.5, 1.5, 4.0]).unwrap();
        let (beta, albedo) = (Vec3::new(0.3, 1.0, 2.0), Vec3::new(0.9, 0.5, 0.8));
        // Summed in f64: 10⁵ f32 additions would lose the digits checked.
        let (mut scatter, mut pass) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
        let n = 100_000;
        for i in 0..n {
            match c.event(beta, albedo, c.k, (i as f32 + 0.5) / n as f32) {
                ChromaEvent::Scatter(w) => scatter += w.as_dvec3(),
                ChromaEvent::Pass(w) => pass += w.as_dvec3(),
                ChromaEvent::Stop => panic!("stopped"),
            }
        }
        let (scatter, pass) = ((scatter / n as f64).as_vec3(), (pass / n as f64).as_vec3());
        assert!(
            (scatter - albedo * c.k).abs().max_element() < 1e-4,
            "{scatter}"
        );
        assert!(
            (pass - (Vec3::ONE - c.k)).abs().max_element() < 1e-4,
            "{pass}"
        );
        assert_eq!(c.event(Vec3::ZERO, albedo, c.k, 0.5), ChromaEvent::Stop);
    }

    #[test]
    fn equal_channels_share_an_estimate() {
        let c = chroma([2.0, 2.0, 4.0]).unwrap();
        let mut calls = 0;
        let (t, n) = c.transmittance(|m| {
            calls += 1;
            ((-m.sigma_t_scale).exp(), 3)
        });
        assert_eq!(calls, 2);
        assert_eq!(n, 6);
        assert_eq!(t.x, t.y);
        assert_eq!(t.z, (-4.0f32).exp());
    }
}
