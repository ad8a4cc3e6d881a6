//! The measurement protocol of rendered frames, from Lin et al. 2021 §6
//! (Lin et al. 2021) and shared by every experiment that renders frames against a
//! reference (`restir-*`, `pins-*`, `light-bvh`): an offline `volpath`
//! reference with pixel-centre rays, independent frames of a per-pixel
//! integrator, frames raced within a time budget; MSE of every frame and
//! of the running mean, with the reference's own variance subtracted.

use super::clock::clocked;
use fogbank_render::integrators::restir::frame::PassTimes;
use fogbank_render::{parse_scene, render, Progress, RenderOptions, RenderResult, Scene};
use std::path::{Path, PathBuf};

/// The repository's `scenes/` folder (probes, scene files).
pub fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// The scene `text` with `set` overrides, with what its integrator gathers
/// before sampling (pin grids) built now, so frame times never include it.
pub fn build(text: &str, set: &[String]) -> Result<Scene, String> {
    let desc = parse_scene(text, "restir-equal-time", set).map_err(|e| e.0)?;
    let scene = Scene::build(desc, &scenes_dir()).map_err(|e| e.0)?;
    scene.integrator.prepare(&scene.world);
    Ok(scene)
}

/// Override strings for [`build`] (`--set` pairs such as
/// `integrator.type=volpath`).
pub fn set(kv: &[&str]) -> Vec<String> {
    kv.iter().map(|s| s.to_string()).collect()
}

/// The pixel samples `--trials` asks for (`default` without it), at most
/// 2²⁰.
pub fn spp(trials: Option<u64>, default: u64) -> u32 {
    trials.unwrap_or(default).min(1 << 20) as u32
}

/// `scene` rendered at `spp` samples per pixel with `seed`, no time budget.
pub fn render_at(scene: &Scene, spp: u32, seed: u32) -> RenderResult {
    let opts = RenderOptions::new(spp, seed);
    render(scene, &opts, &Progress::default())
}

/// Luminance (Rec. 709) of an RGB pixel.
pub fn lum(p: &[f32; 3]) -> f64 {
    0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64
}

/// Mean squared error over pixels and channels.
pub fn mse(a: &[[f32; 3]], reference: &[[f32; 3]]) -> f64 {
    let n = (a.len() * 3) as f64;
    a.iter()
        .zip(reference)
        .map(|(p, r)| {
            (0..3)
                .map(|c| (p[c] as f64 - r[c] as f64).powi(2))
                .sum::<f64>()
        })
        .sum::<f64>()
        / n
}

/// Mean squared luminance of the error: the monochrome MSE of Lin et al. 2021
/// Fig. 19, blind to the colour noise a scalar (luminance) target leaves.
pub fn mono_mse(a: &[[f32; 3]], reference: &[[f32; 3]]) -> f64 {
    a.iter()
        .zip(reference)
        .map(|(p, r)| (lum(p) - lum(r)).powi(2))
        .sum::<f64>()
        / a.len() as f64
}

/// A reference image, the variance of each pixel's mean and the noise
/// floors (their averages, in colour and in luminance).
pub struct Reference {
    pub rgb: Vec<[f32; 3]>,
    pub var: Vec<[f32; 3]>,
    pub floor: f64,
    pub mono_floor: f64,
}

impl Reference {
    pub fn render(scene: &Scene, spp: u32, seed: u32) -> Reference {
        let film = render_at(scene, spp, seed).film;
        let rgb = film.mean();
        let var = film.variance_of_mean();
        let floor = var
            .iter()
            .map(|v| v.iter().map(|&x| x as f64).sum::<f64>())
            .sum::<f64>()
            / (rgb.len() * 3) as f64;
        // The film keeps no covariance between channels; one path serves
        // all three, so take them as fully correlated (the largest luminance
        // variance their variances allow).
        let mono_floor = var
            .iter()
            .map(|v| lum(&v.map(|x| x.max(0.0).sqrt())).powi(2))
            .sum::<f64>()
            / rgb.len() as f64;
        Reference {
            rgb,
            var,
            floor,
            mono_floor,
        }
    }

    /// MSE of `img` with the reference's own variance subtracted.
    pub fn mse(&self, img: &[[f32; 3]]) -> f64 {
        (mse(img, &self.rgb) - self.floor).max(0.0)
    }

    /// [`mono_mse`] of `img` with the reference's own (bounded) variance
    /// subtracted.
    pub fn mono_mse(&self, img: &[[f32; 3]]) -> f64 {
        (mono_mse(img, &self.rgb) - self.mono_floor).max(0.0)
    }
}

/// What a run of frames measured.
pub struct Frames {
    /// Mean wall-clock milliseconds per frame.
    pub ms: f64,
    /// Mean per-frame MSE, in colour and in luminance (monochrome).
    pub mse: f64,
    pub mono_mse: f64,
    /// (seconds so far, MSE of the running mean) after each frame.
    pub curve: Vec<(f64, f64)>,
    /// Mean seconds per pass (ReSTIR only).
    pub passes: PassTimes,
    /// The last frame.
    pub last: Vec<[f32; 3]>,
}

impl Frames {
    /// The curve's points a log–log plot can show (both coordinates > 0).
    pub fn log_curve(&self) -> Vec<(f64, f64)> {
        self.curve
            .iter()
            .copied()
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
            .collect()
    }
}

/// Frames accumulated against a reference: their running mean, time and
/// per-frame and running-mean MSE.
pub struct Accumulator<'a> {
    reference: &'a Reference,
    acc: Vec<[f64; 3]>,
    n: u32,
    seconds: f64,
    mse_sum: f64,
    mono_mse_sum: f64,
    curve: Vec<(f64, f64)>,
}

impl<'a> Accumulator<'a> {
    pub fn new(reference: &'a Reference) -> Self {
        Accumulator {
            reference,
            acc: vec![[0.0; 3]; reference.rgb.len()],
            n: 0,
            seconds: 0.0,
            mse_sum: 0.0,
            mono_mse_sum: 0.0,
            curve: Vec::new(),
        }
    }

    pub fn add(&mut self, rgb: &[[f32; 3]], seconds: f64) {
        self.n += 1;
        self.seconds += seconds;
        self.mse_sum += self.reference.mse(rgb);
        self.mono_mse_sum += self.reference.mono_mse(rgb);
        for (a, p) in self.acc.iter_mut().zip(rgb) {
            for c in 0..3 {
                a[c] += p[c] as f64;
            }
        }
        let mean = self.mean();
        self.curve.push((self.seconds, self.reference.mse(&mean)));
    }

    /// Seconds of the frames so far.
    pub fn seconds(&self) -> f64 {
        self.seconds
    }

    /// Mean milliseconds per frame so far.
    pub fn ms(&self) -> f64 {
        1e3 * self.seconds / self.n.max(1) as f64
    }

    /// A fresh accumulator against the same reference.
    pub fn cleared(&self) -> Accumulator<'a> {
        Accumulator::new(self.reference)
    }

    /// The running mean of the frames so far.
    pub fn mean(&self) -> Vec<[f32; 3]> {
        let n = self.n.max(1) as f64;
        self.acc.iter().map(|a| a.map(|x| (x / n) as f32)).collect()
    }

    pub fn finish(self, passes: PassTimes, last: Vec<[f32; 3]>) -> Frames {
        let n = self.n.max(1) as f64;
        Frames {
            ms: 1e3 * self.seconds / n,
            mse: self.mse_sum / n,
            mono_mse: self.mono_mse_sum / n,
            curve: self.curve,
            passes,
            last,
        }
    }
}

/// `frames` independent frames of `spp` samples of a per-pixel integrator.
pub fn independent_frames(
    scene: &Scene,
    reference: &Reference,
    spp: u32,
    frames: u32,
    seed: u32,
) -> Frames {
    let mut acc = Accumulator::new(reference);
    let mut last = Vec::new();
    for f in 0..frames {
        let (film, seconds) = clocked(|| render_at(scene, spp, seed.wrapping_add(f)).film);
        last = film.mean();
        acc.add(&last, seconds);
    }
    acc.finish(PassTimes::default(), last)
}

/// Independent `spp`-sample frames of a per-pixel integrator, one per
/// [`BudgetRun::step`], until their render time reaches a budget, keeping
/// the running mean's image at each snapshot time (the first frame ending
/// at or past it). Several runs stepped in turn share the machine's drift,
/// so their times compare.
pub struct BudgetRun<'a> {
    scene: &'a Scene,
    acc: Accumulator<'a>,
    spp: u32,
    budget: f64,
    snapshots: Vec<f64>,
    shots: Vec<Vec<[f32; 3]>>,
    seed: u32,
    last: Vec<[f32; 3]>,
}

impl<'a> BudgetRun<'a> {
    pub fn new(
        scene: &'a Scene,
        reference: &'a Reference,
        spp: u32,
        budget: f64,
        snapshots: &[f64],
        seed: u32,
    ) -> Self {
        BudgetRun {
            scene,
            acc: Accumulator::new(reference),
            spp,
            budget,
            snapshots: snapshots.to_vec(),
            shots: Vec::new(),
            seed,
            last: Vec::new(),
        }
    }

    /// Renders one more frame unless the budget is spent; false when it is.
    pub fn step(&mut self) -> bool {
        if self.acc.seconds >= self.budget {
            return false;
        }
        let seed = self.seed.wrapping_add(self.acc.n);
        let (film, seconds) = clocked(|| render_at(self.scene, self.spp, seed).film);
        self.last = film.mean();
        self.acc.add(&self.last, seconds);
        while self.shots.len() < self.snapshots.len()
            && self.acc.seconds >= self.snapshots[self.shots.len()]
        {
            self.shots.push(self.acc.mean());
        }
        true
    }

    /// The frames and the snapshots (the final mean for those not reached).
    pub fn finish(mut self) -> (Frames, Vec<Vec<[f32; 3]>>) {
        while self.shots.len() < self.snapshots.len() {
            self.shots.push(self.acc.mean());
        }
        (self.acc.finish(PassTimes::default(), self.last), self.shots)
    }
}

/// [`BudgetRun`] of one scene alone.
pub fn frames_within(
    scene: &Scene,
    reference: &Reference,
    spp: u32,
    budget: f64,
    snapshots: &[f64],
    seed: u32,
) -> (Frames, Vec<Vec<[f32; 3]>>) {
    let mut run = BudgetRun::new(scene, reference, spp, budget, snapshots, seed);
    while run.step() {}
    run.finish()
}

/// A finished [`BudgetRun`]: its frames and its snapshots.
pub type Finished = (Frames, Vec<Vec<[f32; 3]>>);

/// [`BudgetRun`]s of `text` under each override set in `sets`, 1 spp per
/// frame, taking turns frame by frame (so the machine's drift hits them
/// alike) until each has spent `budget` seconds; run `i` is seeded
/// `seed + i`.
pub fn race(
    text: &str,
    sets: &[Vec<String>],
    reference: &Reference,
    budget: f64,
    snapshots: &[f64],
    seed: u32,
) -> Result<Vec<Finished>, String> {
    let scenes: Vec<Scene> = sets
        .iter()
        .map(|set| build(text, set))
        .collect::<Result<_, _>>()?;
    let mut runs: Vec<BudgetRun> = scenes
        .iter()
        .enumerate()
        .map(|(i, s)| BudgetRun::new(s, reference, 1, budget, snapshots, seed + i as u32))
        .collect();
    while runs.iter_mut().fold(false, |any, r| r.step() | any) {}
    Ok(runs.into_iter().map(BudgetRun::finish).collect())
}

#[cfg(test)]
mod tests {
    use super::{mono_mse, mse};

    /// A pure chroma error (zero luminance) is invisible to the monochrome
    /// MSE and not to the colour MSE; a grey error is the same in both.
    #[test]
    fn mono_mse_sees_luminance_only() {
        let reference = [[0.5f32, 0.5, 0.5]; 4];
        // Rec. 709 weights: +0.0722 on R and −0.2126 on B change nothing.
        let chroma = [[0.5f32 + 0.0722, 0.5, 0.5 - 0.2126]; 4];
        assert!(mono_mse(&chroma, &reference) < 1e-14);
        assert!(mse(&chroma, &reference) > 1e-2);
        let grey = [[0.75f32; 3]; 4];
        assert!((mono_mse(&grey, &reference) - 0.0625).abs() < 1e-9);
        assert!((mse(&grey, &reference) - 0.0625).abs() < 1e-9);
    }
}
