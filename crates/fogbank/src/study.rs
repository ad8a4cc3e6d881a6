//! `fogbank stats` as a library call: per-pixel mean, single-frame std and
//! bias of a scene's estimator over K independent 1-spp frames (streamed:
//! memory does not grow with K), against an exact estimator or a reference
//! image; a shard's part as a partial result; the files and the summary.
//! And `fogbank converge`: equal-time curves of several estimators.

use crate::error::Error;
use crate::renderer::{Device, Renderer};
use crate::stats::peak_memory_bytes;
use fogbank_estimators::estimator::{AnalyticTrilinear, RegularTracking};
use fogbank_estimators::Estimator;
/// The time a convergence curve first reaches an error.
pub use fogbank_eval::converge::time_to_reach;
use fogbank_eval::converge::{convergence, write_csv, Curve};
use fogbank_eval::frame_stats::frame_stats_piece;
/// Per-pixel statistics over independent frames.
pub use fogbank_eval::FrameStats;
use fogbank_eval::{exact_reference, frame_stats, Backend};
use fogbank_image::image_io::{read_image, write_exr_channels};
use fogbank_partial::partial::{Partial, PartialHeader};
use fogbank_render::shard::Shard;
use fogbank_render::Scene;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// What the frames' mean is held against for bias.
#[derive(Clone, Debug)]
pub enum StatsReference {
    /// An exact estimator of the same scene (analytic_trilinear,
    /// regular_tracking).
    Exact(Estimator),
    /// An image of the same size rendered through pixel centres.
    Image(PathBuf),
}

impl StatsReference {
    /// The exact estimator `name`; an error for an unknown or inexact one.
    pub fn exact(name: &str) -> Result<StatsReference, Error> {
        let e = Estimator::parse(name).ok_or_else(|| {
            Error::invalid(format!("--reference-estimator: unknown estimator `{name}`"))
        })?;
        if e.biased()
            || !matches!(
                e,
                Estimator::AnalyticTrilinear(AnalyticTrilinear)
                    | Estimator::RegularTracking(RegularTracking)
            )
        {
            return Err(Error::invalid(format!("--reference-estimator must be exact (analytic_trilinear or regular_tracking), not `{name}`")));
        }
        Ok(StatsReference::Exact(e))
    }

    fn label(&self) -> String {
        match self {
            StatsReference::Exact(e) => e.name().to_string(),
            StatsReference::Image(p) => p.display().to_string(),
        }
    }
}

#[derive(Clone, Debug)]
pub struct StatsJob {
    /// Independent 1-spp frames.
    pub runs: u32,
    pub seed: u32,
    pub reference: Option<StatsReference>,
}

impl StatsJob {
    /// Refuses a job of no frames.
    pub fn check(&self) -> Result<(), Error> {
        if self.runs == 0 {
            return Err(Error::invalid("--runs must be at least 1"));
        }
        Ok(())
    }

    /// The frames' statistics on `renderer`, with the reference's mean when
    /// there is one.
    pub fn run(&self, renderer: &Renderer, scene: &Scene) -> Result<FrameStats, Error> {
        self.check()?;
        let backend = Backend::from(renderer.gpu_device());
        let mut st = renderer
            .install(|| frame_stats(backend, scene, self.runs, self.seed))
            .map_err(|e| Error::runtime(format!("--device {}: {e}", backend.name())))?;
        match &self.reference {
            Some(StatsReference::Exact(e)) => {
                st.reference = Some(renderer.install(|| exact_reference(scene, *e)));
            }
            Some(StatsReference::Image(path)) => {
                let img = read_image(path).map_err(|e| Error::runtime(e.to_string()))?;
                if (img.width, img.height) != (st.width as usize, st.height as usize) {
                    return Err(Error::invalid(format!(
                        "{}: reference is {}×{}, the scene renders {}×{}",
                        path.display(),
                        img.width,
                        img.height,
                        st.width,
                        st.height
                    )));
                }
                st.reference = Some(img.rgb.iter().map(|p| p.map(f64::from)).collect());
            }
            None => {}
        }
        Ok(st)
    }

    /// Refuses what a shard cannot do: compare with a reference (only the
    /// merged mean can) or run on a GPU.
    pub fn check_shard(&self, shard: Shard, device: Device) -> Result<(), Error> {
        self.check()?;
        if self.reference.is_some() {
            return Err(Error::invalid(format!("--shard {}: not with a reference; merge the parts, then compare the merged mean with `fogbank compare`", shard.label())));
        }
        if device == Device::Gpu {
            return Err(Error::invalid(format!("--shard {}: not with --device gpu (GPU frames keep running means in f32, whose parts do not add up bit for bit)", shard.label())));
        }
        Ok(())
    }

    /// Shard `shard`'s frames as a partial result in `out`; returns its
    /// path and the seconds it took.
    pub fn run_shard(
        &self,
        renderer: &Renderer,
        scene: &Scene,
        shard: Shard,
        out: &Path,
    ) -> Result<(PathBuf, f64), Error> {
        self.check_shard(shard, renderer.device())?;
        let piece = shard.piece(self.runs);
        let (film, covered, seconds) =
            renderer.install(|| frame_stats_piece(scene, &piece, self.seed));
        let run = crate::shard_run::run(shard, self.runs, seconds, renderer.threads());
        let header = PartialHeader::for_shard("stats", scene, self.seed, self.runs, &film, run);
        let path = out.join(format!("shard_{}_of_{}.fbpart", shard.index, shard.count));
        Partial {
            header,
            film,
            covered: Some(covered),
        }
        .write(&path)
        .map_err(Error::runtime)?;
        Ok((path, seconds))
    }

    /// `summary.json` of statistics `st` of `scene`.
    pub fn summary(&self, scene: &Scene, renderer: &Renderer, st: &FrameStats) -> Value {
        let s = st.summary();
        let known = |v: f64| {
            if st.reference.is_some() {
                json!(v)
            } else {
                Value::Null
            }
        };
        json!({
            "integrator": scene.integrator.name(),
            "estimator": scene.integrator.estimator_name(),
            "reference": self.reference.as_ref().map(StatsReference::label),
            "width": st.width,
            "height": st.height,
            "runs": s.runs,
            "seed": self.seed,
            "threads": renderer.threads(),
            "covered_pixels": s.pixels,
            "mean_abs_bias": known(s.mean_abs_bias),
            "mean_bias": known(s.mean_bias),
            "mean_bias_se": s.mean_bias_se,
            "mean_std": s.mean_std,
            "rmse": known(s.rmse),
            "ms_per_frame": s.ms_per_frame,
            "lookups_per_pixel": s.lookups_per_pixel,
            "nonfinite_samples": st.nonfinite,
            "stats_seconds": st.seconds,
            "device": Backend::from(renderer.gpu_device()).name(),
            "peak_memory_bytes": peak_memory_bytes(),
        })
    }
}

/// Writes `stats.exr` (mean, std, bias when known, count), the false-colour
/// maps and `summary.json` into `out`.
pub fn write_stats(
    st: &FrameStats,
    estimator: &str,
    out: &Path,
    json: &Value,
) -> Result<(), Error> {
    let io = |e: Box<dyn std::error::Error>| Error::runtime(e.to_string());
    let to32 = |v: &[[f64; 3]], f: &dyn Fn(f64) -> f64| -> Vec<[f32; 3]> {
        v.iter().map(|p| p.map(|c| f(c) as f32)).collect()
    };
    let mut layers: Vec<(&str, Vec<[f32; 3]>)> = vec![
        ("mean", to32(&st.mean, &|c| c)),
        ("std", to32(&st.variance, &|c| c.sqrt())),
    ];
    if let Some(b) = st.bias() {
        layers.push(("bias", to32(&b, &|c| c)));
    }
    let counts: Vec<f32> = st.count.iter().map(|&c| c as f32).collect();
    write_exr_channels(
        &out.join("stats.exr"),
        st.width,
        st.height,
        &layers,
        Some(("count", &counts)),
    )
    .map_err(|e| io(e.into()))?;
    fogbank_eval::maps::write_maps(st, estimator, &out.join("maps")).map_err(|e| io(e.into()))?;
    let text = serde_json::to_string_pretty(json).map_err(|e| io(e.into()))? + "\n";
    std::fs::write(out.join("summary.json"), text)
        .map_err(|e| Error::runtime(format!("{}: {e}", out.join("summary.json").display())))
}

/// `fogbank converge` as a library call: equal-time MSE-versus-time curves
/// of several estimators on one scene against an exact reference, measured
/// in one run (primary rays through pixel centres, so that the reference is
/// the limit of every estimator's mean).
#[derive(Clone, Debug)]
pub struct ConvergeJob {
    /// Estimators, each `NAME` (options via the scene's keys).
    pub estimators: Vec<String>,
    /// Render time per estimator.
    pub seconds: f64,
    /// Exact estimator of the reference: analytic_trilinear or
    /// regular_tracking.
    pub reference: String,
    pub seed: u32,
}

impl ConvergeJob {
    /// Refuses a non-positive time, an inexact reference or no estimators.
    pub fn check(&self) -> Result<Estimator, Error> {
        if !(self.seconds > 0.0 && self.seconds.is_finite()) {
            return Err(Error::invalid("--seconds must be positive"));
        }
        if self.estimators.is_empty() {
            return Err(Error::invalid("--estimators: name at least one"));
        }
        Estimator::parse(&self.reference)
            .filter(|e| matches!(e, Estimator::AnalyticTrilinear(AnalyticTrilinear) | Estimator::RegularTracking(RegularTracking)))
            .ok_or_else(|| {
                Error::invalid(format!(
                    "--reference-estimator must be analytic_trilinear or regular_tracking, not `{}`",
                    self.reference
                ))
            })
    }

    /// The scene overrides every run of the study adds.
    pub fn overrides(overrides: &[String]) -> Vec<String> {
        let mut o = overrides.to_vec();
        o.push("render.pixel_jitter=false".into());
        o
    }

    /// One curve per estimator; `load(overrides)` builds the scene with
    /// extra overrides (`integrator.estimator=NAME` for each run),
    /// `started(name)` is called before each.
    pub fn run(
        &self,
        renderer: &Renderer,
        load: &dyn Fn(&[String]) -> Result<Scene, Error>,
        started: &mut dyn FnMut(&str),
    ) -> Result<Vec<Curve>, Error> {
        let reference_estimator = self.check()?;
        let backend = Backend::from(renderer.gpu_device());
        let base = load(&[])?;
        let reference = renderer.install(|| exact_reference(&base, reference_estimator));
        let mut curves = Vec::new();
        for name in &self.estimators {
            let scene = load(&[format!("integrator.estimator={name}")])?;
            started(name);
            let points = renderer
                .install(|| convergence(backend, &scene, self.seconds, &reference, self.seed))
                .map_err(|e| Error::runtime(format!("--device {}: {e}", backend.name())))?;
            curves.push(Curve {
                label: name.clone(),
                points,
            });
        }
        Ok(curves)
    }
}

/// Writes `converge.csv` and the plots of `curves` into `out`.
pub fn write_curves(curves: &[Curve], out: &Path) -> Result<(), Error> {
    let io = |e: String| Error::runtime(e);
    write_csv(&out.join("converge.csv"), curves)
        .map_err(|e| io(format!("{}: {e}", out.join("converge.csv").display())))?;
    fogbank_eval::converge::plot(curves, "equal-time convergence", &out.join("converge"))
        .map(|_| ())
        .map_err(io)
}
