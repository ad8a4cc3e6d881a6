//! Peters 2025 Fig. 14 and §6.3 (limitations): the explosion failure case in
//! two dimensions. A ray runs along x through a sparse field whose dense
//! puffs lie mostly *beside* the ray: the super-voxels it crosses are
//! non-empty (their Eq. 5 importance comes from voxels off the ray), so Alg.
//! 1 spends most samples where μ(t) = μ_min and they contribute nothing
//! (the paper: 86% at super-voxel size 16). The few informative samples make
//! the optical-depth estimates far from normal and the jackknife biased.
//! Smaller super-voxels fit the field more tightly ("at 12³ the problems are
//! mostly gone").
//!
//! This uses the project's whole stack: a `BrickGrid` seen through a
//! nearest-filter `GridView` (Fig. 14 uses neither stochastic filtering nor
//! compression), `SuperVoxelGrid::build`, and Alg. 2/Alg. 1 with N = 10.

use crate::harness::trials::{run_chunked, Moments};
use crate::harness::Writer;
use fogbank_estimators::jackknife::jackknife_transmittance;
use fogbank_estimators::optical_depth::{estimates, prepare, Importance, Jitter};
use fogbank_eval::plot::{palette, ColourMap, Figure, HeatMap, LinePlot, Mark, Rgb, Series};
use fogbank_math::{Pcg32, Ray, RaySegment, Vec3};
use fogbank_volume::{BrickGrid, Filter, GridView, SuperVoxelGrid, VolumeAccess};
use std::sync::atomic::{AtomicU64, Ordering};

pub const DEFAULT_TRIALS: u64 = 1_000_000;
pub const SUPERVOXEL_SIZES: [u32; 3] = [16, 12, 8];
/// Samples per estimate, the paper's default.
pub const SAMPLES: u32 = 10;
pub const DIMS: [u32; 3] = [256, 48, 1];
/// The ray's voxel row (centre y = ROW + ½).
pub const ROW: u32 = 44;
const SEED: u32 = 0x000f_1614;

/// A smooth compactly supported puff, (1 − (d/r)²)² inside radius r.
fn puff(x: f64, y: f64, cx: f64, cy: f64, r: f64) -> f64 {
    let q = ((x - cx).powi(2) + (y - cy).powi(2)) / (r * r);
    if q < 1.0 {
        (1.0 - q).powi(2)
    } else {
        0.0
    }
}

/// The sparse field: dense puffs below the ray whose tops reach into the
/// ray's super-voxel rows at varying heights, plus a few faint wisps on
/// the ray itself (so its optical depth is small but non-zero).
pub fn field() -> BrickGrid<f32> {
    let mut rng = Pcg32::new(0x0e4b_1051, 14);
    let mut puffs = Vec::new();
    for _ in 0..14 {
        let cx = 8.0 + 240.0 * rng.next_f64();
        let r = 6.0 + 8.0 * rng.next_f64();
        // Top of the puff between rows 31 and 37: inside the ray's 16-voxel
        // super-voxel row (32–47), partly inside its 12-voxel row (36–47),
        // never inside its 8-voxel row (40–47): the paper's "at 12³ the
        // problems are mostly gone".
        let top = 31.0 + 6.0 * rng.next_f64();
        puffs.push((cx, top - r, r, 8.0));
    }
    for _ in 0..6 {
        let cx = 8.0 + 240.0 * rng.next_f64();
        puffs.push((
            cx,
            ROW as f64 + 0.5 + 2.0 * rng.next_f64() - 1.0,
            3.0 + 2.0 * rng.next_f64(),
            0.05,
        ));
    }
    BrickGrid::from_fn(DIMS, |i, j, _| {
        let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
        puffs
            .iter()
            .map(|&(cx, cy, r, a)| a * puff(x, y, cx, cy, r))
            .sum::<f64>() as f32
    })
    .expect("fig14 field dimensions are valid")
}

/// A volume view that counts lookups returning the super-voxel minimum,
/// i.e. samples whose term (μ − μ_min)/P in Alg. 1 is zero.
struct Counting<'a> {
    view: GridView<'a, f32>,
    zero: AtomicU64,
    total: AtomicU64,
}

impl VolumeAccess for Counting<'_> {
    fn sigma_t(&self, p: Vec3, u: Vec3) -> f32 {
        let v = self.view.sigma_t(p, u);
        let sv = self.view.supervoxels;
        let cell: [i32; 3] = std::array::from_fn(|a| {
            ((p[a] / sv.size as f32).floor() as i32).clamp(0, sv.dims[a] as i32 - 1)
        });
        if v <= sv.get(cell).min {
            self.zero.fetch_add(1, Ordering::Relaxed);
        }
        self.total.fetch_add(1, Ordering::Relaxed);
        v
    }
    fn needs_jitter(&self) -> bool {
        false
    }
    fn supervoxels(&self) -> &SuperVoxelGrid {
        self.view.supervoxels
    }
    fn dims(&self) -> [u32; 3] {
        self.view.grid.dims()
    }
}

#[derive(Clone, Copy, Debug)]
pub struct Row {
    pub size: u32,
    /// Fraction of samples contributing nothing.
    pub zero_fraction: f64,
    /// Super-voxels with non-zero importance crossed by the ray.
    pub nonempty: usize,
    pub jackknife: Moments,
    /// e^{−X} from one estimate of 2N samples (same cost).
    pub naive: Moments,
    pub exact: f64,
}

pub fn compute(trials: u64, sizes: &[u32]) -> Vec<Row> {
    let grid = field();
    let ray = Ray::new(
        Vec3::new(0.0, ROW as f32 + 0.5, 0.5),
        Vec3::new(1.0, 0.0, 0.0),
    );
    let tau: f64 = (0..DIMS[0] as i32)
        .map(|i| grid.fetch(i, ROW as i32, 0) as f64)
        .sum();
    let exact = (-tau).exp();
    sizes
        .iter()
        .map(|&size| size_row(&grid, &ray, size, trials, exact))
        .collect()
}

/// `trials` estimates along `ray` with super-voxels of `size` voxels:
/// the jackknife from two estimates of N samples and the naive e^{−X}
/// from one of 2N, with the fraction of samples that contribute nothing.
fn size_row(grid: &BrickGrid<f32>, ray: &Ray, size: u32, trials: u64, exact: f64) -> Row {
    let svg = SuperVoxelGrid::build(DIMS, size, Filter::Nearest.apron(), |i, j, k| {
        grid.fetch(i, j, k)
    });
    let view = || GridView {
        grid,
        filter: Filter::Nearest,
        scale: 1.0,
        supervoxels: &svg,
        opacity: None,
    };
    let v0 = view();
    let prep = prepare(
        &v0,
        &RaySegment::new(*ray, 0.0, DIMS[0] as f32),
        Importance::VarianceAware,
    );
    let nonempty = (0..svg.dims[0] as i32)
        .filter(|&c| svg.get([c, (ROW / size) as i32, 0]).importance > 0.0)
        .count();
    let (jk, nv, zero, total) = run_chunked(
        trials,
        SEED,
        size,
        || (Moments::default(), Moments::default(), 0u64, 0u64),
        |rng, acc, count| {
            let c = Counting {
                view: view(),
                zero: AtomicU64::new(0),
                total: AtomicU64::new(0),
            };
            let (mut x, mut x1, mut lookups) = ([0.0f64; 2], [0.0f64], 0u32);
            for _ in 0..count {
                estimates(
                    &c,
                    &prep,
                    prep.total / SAMPLES as f64,
                    Jitter::Stratified,
                    rng,
                    &mut lookups,
                    &mut x,
                );
                acc.0.push(jackknife_transmittance(x[0], x[1]));
                estimates(
                    &v0,
                    &prep,
                    prep.total / (2 * SAMPLES) as f64,
                    Jitter::Stratified,
                    rng,
                    &mut lookups,
                    &mut x1,
                );
                acc.1.push((-x1[0]).exp());
            }
            acc.2 += c.zero.load(Ordering::Relaxed);
            acc.3 += c.total.load(Ordering::Relaxed);
        },
        |a, b| {
            a.0.merge(b.0);
            a.1.merge(b.1);
            a.2 += b.2;
            a.3 += b.3;
        },
    );
    Row {
        size,
        zero_fraction: zero as f64 / total.max(1) as f64,
        nonempty,
        jackknife: jk,
        naive: nv,
        exact,
    }
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let trials = trials.unwrap_or(DEFAULT_TRIALS);
    let rows = compute(trials, &SUPERVOXEL_SIZES);
    write_csv(w, &rows)?;
    w.figure("fig14", &figure(&rows, trials))?;
    Ok(summary(&rows))
}

/// `fig14.csv`: per super-voxel size, the zero-contribution fraction and
/// both estimates' bias and std.
fn write_csv(w: &mut Writer, rows: &[Row]) -> Result<(), String> {
    let csv: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.size.to_string(),
                format!("{:.4}", r.zero_fraction),
                r.nonempty.to_string(),
                format!("{:.6}", r.exact),
                format!("{:.6}", r.jackknife.mean()),
                format!("{:.6}", r.jackknife.mean() - r.exact),
                format!("{:.6}", r.jackknife.std_error()),
                format!("{:.6}", r.jackknife.std()),
                format!("{:.6}", r.naive.mean() - r.exact),
                format!("{:.6}", r.naive.std()),
            ]
        })
        .collect();
    w.csv(
        "fig14.csv",
        &[
            "supervoxel_size",
            "zero_fraction",
            "nonempty_supervoxels_on_ray",
            "T_exact",
            "jackknife_mean",
            "jackknife_bias",
            "jackknife_bias_std_error",
            "jackknife_std",
            "naive_bias",
            "naive_std",
        ],
        &csv,
    )
}

/// The field with the ray and the 16-voxel super-voxels drawn over it,
/// the zero-contribution fraction and the bias against super-voxel size.
fn figure(rows: &[Row], trials: u64) -> Figure {
    let sizes: Vec<f64> = rows.iter().map(|r| r.size as f64).collect();
    Figure::new(3)
        .panel_size(620, 420)
        .title(format!(
            "Peters 2025 Fig. 14 analogue: sparse field, N = {SAMPLES}, {trials} trials per size"
        ))
        .with(field_panel())
        .with(
            LinePlot::new(
                "samples contributing nothing",
                "super-voxel size",
                "fraction",
            )
            .y_range(0.0, 1.0)
            .with(Series::new(
                "zero-contribution fraction",
                sizes
                    .iter()
                    .zip(rows)
                    .map(|(&s, r)| (s, r.zero_fraction))
                    .collect(),
                palette(0),
                Mark::LinePoints,
            )),
        )
        .with(
            LinePlot::new("transmittance bias", "super-voxel size", "mean - T")
                .with(Series::new(
                    "jackknife (m = 2, N = 10)",
                    sizes
                        .iter()
                        .zip(rows)
                        .map(|(&s, r)| (s, r.jackknife.mean() - r.exact))
                        .collect(),
                    palette(0),
                    Mark::LinePoints,
                ))
                .with(Series::new(
                    "naive e^-X (2N samples)",
                    sizes
                        .iter()
                        .zip(rows)
                        .map(|(&s, r)| (s, r.naive.mean() - r.exact))
                        .collect(),
                    palette(1),
                    Mark::LinePoints,
                ))
                .with(Series::dashed("", vec![(8.0, 0.0), (16.0, 0.0)], Rgb::GREY)),
        )
}

/// The extinction field as a heat map with the ray and the 16-voxel
/// super-voxels along it drawn over it.
fn field_panel() -> HeatMap {
    let grid = field();
    let values: Vec<f64> = (0..DIMS[1])
        .flat_map(|j| (0..DIMS[0]).map(move |i| (i, j)))
        .map(|(i, j)| grid.fetch(i as i32, j as i32, 0) as f64)
        .collect();
    let vmax = values.iter().cloned().fold(0.0, f64::max);
    let mut overlays = vec![Series::line(
        "ray",
        vec![(0.0, ROW as f64 + 0.5), (DIMS[0] as f64, ROW as f64 + 0.5)],
        Rgb(255, 80, 80),
    )];
    for k in 1..=(DIMS[0] / 16) {
        overlays.push(Series::dashed(
            "",
            vec![(k as f64 * 16.0, 32.0), (k as f64 * 16.0, 48.0)],
            Rgb(255, 255, 255),
        ));
    }
    overlays.push(Series::dashed(
        "16-voxel super-voxels",
        vec![(0.0, 32.0), (DIMS[0] as f64, 32.0)],
        Rgb(255, 255, 255),
    ));
    HeatMap {
        title: "extinction (x: ray direction)".into(),
        x_label: "x (voxels)".into(),
        y_label: "y (voxels)".into(),
        x_range: (0.0, DIMS[0] as f64),
        y_range: (0.0, DIMS[1] as f64),
        nx: DIMS[0] as usize,
        ny: DIMS[1] as usize,
        values,
        map: ColourMap::Sequential,
        limits: (0.0, vmax),
        bar_label: "mu".into(),
        overlays,
    }
}

/// The finding: the zero-contribution fraction and the bias at the
/// largest and the smallest super-voxels, and a table of all.
fn summary(rows: &[Row]) -> String {
    let lines: Vec<String> = rows
        .iter()
        .map(|r| {
            format!(
                "| {} | {} | {:.1}% | {:+.5} (±{:.5}) | {:.4} | {:+.5} |",
                r.size,
                r.nonempty,
                100.0 * r.zero_fraction,
                r.jackknife.mean() - r.exact,
                2.0 * r.jackknife.std_error(),
                r.jackknife.std(),
                r.naive.mean() - r.exact
            )
        })
        .collect();
    let (a, b) = (rows[0], rows[rows.len() - 1]);
    format!(
        "A ray along x at row {ROW} of a {}×{} field whose dense puffs lie mostly beside the ray (exact T = {:.5} along \
the ray). With super-voxels of {} voxels {:.0}% of the N = {SAMPLES} samples per estimate return μ = μ_min and \
contribute nothing (paper: 86% at 16); the jackknife bias is {:+.5}. Shrinking the super-voxels to {} voxels cuts \
the zero-contribution fraction to {:.0}% and the bias to {:+.5}, as the paper's mitigation (smaller super-voxels) \
predicts.\n\n| super-voxel size | non-empty super-voxels on the ray | zero-contribution samples | jackknife bias (±2 se) | jackknife std | naive e^-X bias |\n|---|---|---|---|---|---|\n{}",
        DIMS[0],
        DIMS[1],
        a.exact,
        a.size,
        100.0 * a.zero_fraction,
        a.jackknife.mean() - a.exact,
        b.size,
        100.0 * b.zero_fraction,
        b.jackknife.mean() - b.exact,
        lines.join("\n")
    )
}
