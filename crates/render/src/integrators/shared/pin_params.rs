//! Which rays of `volpath` use pins (Hansen 2025 §3.9, Fig. 4.3) and what the
//! others use, with the pin grid's parameters.
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `pins` | `off` | `off`; `all` (every ray); `secondary` (all but the view ray; NEE at the first vertex uses pins); `ms` (PinMS: pins for distances from vertex 1 on and NEE from vertex 2 on) |
//! | `tracking` | `ray_marching` with pins, else `unbiased` | rays without pins: `ray_marching` (the thesis's baseline, §2.4) or `unbiased` (`distance_sampler` and `estimator`) |
//! | `march_step` | 0.03 | ray-marching step, in edges of the medium's box (thesis: 0.015–0.16 by scene) |
//! | `pin_grid` | see below | table of the 5D grid |
//!
//! `pin_grid` keys: `positions` (P per axis; default from `memory_ratio`),
//! `memory_ratio` (grid bytes ÷ half-float density bytes, default 0.1 as
//! the thesis's evaluation), `phi` (16), `theta` (4), `step` (pin tracing,
//! 0.01 box edges), `jitter` (position and direction, in cells, default 1:
//! the thesis's strongest setting), `mask_iterations` (5), `unquantised`
//! (false: Fig. 4.5's pins traced along each query ray), `seed` (0),
//! `stream` (pins streamed into each grid before every pass, default 0:
//! static pins, as the thesis's evaluation; its code streams 1000 a frame),
//! `stream_spacing` (0.1 box edges between a streamed pin's writes).

use super::tracking::{unit_cube, Flight, PinSet, Shadow};
use super::DistanceSampler;
use crate::error::SceneError;
use crate::params::ParamReader;
use crate::world::World;
use fogbank_estimators::pins::{PinGrid, PinGridSpec, MIN_STREAM_SPACING};
use fogbank_estimators::Estimator;
use fogbank_volume::MediumView;
use std::sync::Arc;

/// Which rays read pins.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PinMode {
    Off,
    All,
    Secondary,
    /// PinMS: multiple scattering only.
    Ms,
}

impl PinMode {
    pub const NAMES: [(&'static str, PinMode); 4] = [
        ("off", PinMode::Off),
        ("all", PinMode::All),
        ("secondary", PinMode::Secondary),
        ("ms", PinMode::Ms),
    ];
    pub fn name(self) -> &'static str {
        PinMode::NAMES
            .iter()
            .find(|(_, m)| *m == self)
            .map_or("off", |(n, _)| n)
    }
}

/// What rays without pins use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tracking {
    RayMarching,
    Unbiased,
}

/// The `pin_grid` table.
#[derive(Clone, Debug, PartialEq)]
pub struct PinGridParams {
    pub positions: Option<u32>,
    pub memory_ratio: f32,
    pub phi: u32,
    pub theta: u32,
    pub step: f32,
    pub jitter: f32,
    pub mask_iterations: u32,
    pub unquantised: bool,
    pub seed: u64,
    /// Pins streamed into each grid before every pass (0: static).
    pub stream: u32,
    pub stream_spacing: f32,
}

impl Default for PinGridParams {
    fn default() -> Self {
        let s = PinGridSpec::default();
        PinGridParams {
            positions: None,
            memory_ratio: 0.1,
            phi: s.phi,
            theta: s.theta,
            step: s.step,
            jitter: 1.0,
            mask_iterations: s.mask_iterations,
            unquantised: false,
            seed: 0,
            stream: 0,
            stream_spacing: super::pin_stream::STREAM_SPACING,
        }
    }
}

/// Most pins `pin_grid.stream` may trace a pass.
pub const MAX_STREAM_PINS: u32 = 1 << 24;

const GRID_KEYS: [&str; 11] = [
    "positions",
    "memory_ratio",
    "phi",
    "theta",
    "step",
    "jitter",
    "mask_iterations",
    "unquantised",
    "seed",
    "stream",
    "stream_spacing",
];

impl PinGridParams {
    fn read(path: &str, table: toml::Table) -> Result<Self, SceneError> {
        let mut r = ParamReader::new(path, "pin_grid", table);
        let d = PinGridParams::default();
        let p = PinGridParams {
            positions: r.take("positions")?,
            memory_ratio: r.take("memory_ratio")?.unwrap_or(d.memory_ratio),
            phi: r.take("phi")?.unwrap_or(d.phi),
            theta: r.take("theta")?.unwrap_or(d.theta),
            step: r.take("step")?.unwrap_or(d.step),
            jitter: r.take("jitter")?.unwrap_or(d.jitter),
            mask_iterations: r.take("mask_iterations")?.unwrap_or(d.mask_iterations),
            unquantised: r.take("unquantised")?.unwrap_or(d.unquantised),
            seed: r.take("seed")?.unwrap_or(d.seed),
            stream: r.take("stream")?.unwrap_or(d.stream),
            stream_spacing: r.take("stream_spacing")?.unwrap_or(d.stream_spacing),
        };
        r.finish(&GRID_KEYS)?;
        let bad = |k: &str, why: &str| Err(SceneError(format!("{path}.{k}: {why}")));
        if p.positions == Some(0) {
            return bad("positions", "must be at least 1");
        }
        if p.phi == 0 || p.theta == 0 {
            return bad(
                if p.phi == 0 { "phi" } else { "theta" },
                "must be at least 1",
            );
        }
        if !(p.memory_ratio > 0.0 && p.memory_ratio.is_finite()) {
            return bad("memory_ratio", "must be a positive number");
        }
        if !(p.step > 0.0 && p.step <= 1.0) {
            return bad("step", "must be in (0, 1] (box edges)");
        }
        if !(0.0..=1.0).contains(&p.jitter) {
            return bad("jitter", "must be in [0, 1] (cells)");
        }
        if p.stream > MAX_STREAM_PINS {
            return bad(
                "stream",
                &format!("must be at most {MAX_STREAM_PINS} pins a pass"),
            );
        }
        if !(p.stream_spacing >= MIN_STREAM_SPACING && p.stream_spacing <= 1.0) {
            return bad(
                "stream_spacing",
                &format!("must be in [{MIN_STREAM_SPACING}, 1] (box edges)"),
            );
        }
        if p.mask_iterations > 24 {
            return bad("mask_iterations", "must be at most 24");
        }
        if let Some(n) = p.positions {
            p.spec(n)
                .pin_count()
                .map_err(|e| SceneError(format!("{path}.positions: {e}")))?;
        }
        Ok(p)
    }

    fn write(&self) -> toml::Table {
        let mut t = toml::Table::new();
        if let Some(p) = self.positions {
            t.insert("positions".into(), i64::from(p).into());
        }
        t.insert("memory_ratio".into(), f64::from(self.memory_ratio).into());
        t.insert("phi".into(), i64::from(self.phi).into());
        t.insert("theta".into(), i64::from(self.theta).into());
        t.insert("step".into(), f64::from(self.step).into());
        t.insert("jitter".into(), f64::from(self.jitter).into());
        t.insert(
            "mask_iterations".into(),
            i64::from(self.mask_iterations).into(),
        );
        t.insert("unquantised".into(), self.unquantised.into());
        t.insert("seed".into(), (self.seed as i64).into());
        if self.stream > 0 {
            t.insert("stream".into(), i64::from(self.stream).into());
            t.insert(
                "stream_spacing".into(),
                f64::from(self.stream_spacing).into(),
            );
        }
        t
    }

    /// P for a medium of `voxels` voxels: the given one, or the largest
    /// whose grid stays within `memory_ratio` of the half-float density
    /// (2 bytes a voxel, as the thesis counts; at least 1).
    pub fn positions_for(&self, voxels: u64) -> u32 {
        self.positions.unwrap_or_else(|| {
            let budget = self.memory_ratio as f64 * 2.0 * voxels as f64;
            let per_cell = 8.0 * (self.phi * self.theta) as f64;
            ((budget / per_cell).cbrt().floor() as u32).max(1)
        })
    }

    pub fn spec(&self, positions: u32) -> PinGridSpec {
        PinGridSpec {
            positions,
            phi: self.phi,
            theta: self.theta,
            step: self.step,
            jitter_position: self.jitter,
            jitter_direction: self.jitter,
            mask_iterations: self.mask_iterations,
        }
    }
}

/// One medium's pin grid in a scene: its own (gathered from `seed`), or
/// the grid of an earlier medium (a rigidly moved instance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GridPlan {
    Own { spec: PinGridSpec, seed: u64 },
    Shared(usize),
}

/// `pins`, `tracking`, `march_step` and `pin_grid` of an integrator.
#[derive(Clone, Debug, PartialEq)]
pub struct PinParams {
    pub mode: PinMode,
    pub tracking: Option<Tracking>,
    pub march_step: f32,
    pub grid: PinGridParams,
}

impl Default for PinParams {
    fn default() -> Self {
        PinParams {
            mode: PinMode::Off,
            tracking: None,
            march_step: 0.03,
            grid: PinGridParams::default(),
        }
    }
}

pub const PIN_KEYS: [&str; 4] = ["pins", "tracking", "march_step", "pin_grid"];

impl PinParams {
    pub fn read(r: &mut ParamReader) -> Result<Self, SceneError> {
        let mode = match r.take::<String>("pins")? {
            None => PinMode::Off,
            Some(s) => PinMode::NAMES
                .iter()
                .find(|(n, _)| *n == s)
                .map(|(_, m)| *m)
                .ok_or_else(|| {
                    SceneError(format!(
                        "{}: `{s}` is not off, all, secondary or ms",
                        r.key_path("pins")
                    ))
                })?,
        };
        let tracking = match r.take::<String>("tracking")?.as_deref() {
            None => None,
            Some("ray_marching") => Some(Tracking::RayMarching),
            Some("unbiased") => Some(Tracking::Unbiased),
            Some(o) => {
                return Err(SceneError(format!(
                    "{}: `{o}` is not ray_marching or unbiased",
                    r.key_path("tracking")
                )))
            }
        };
        let march_step = r
            .take::<f32>("march_step")?
            .unwrap_or(PinParams::default().march_step);
        if !(march_step > 0.0 && march_step <= 1.0) {
            return Err(SceneError(format!(
                "{}: {march_step} is outside (0, 1] (box edges)",
                r.key_path("march_step")
            )));
        }
        let grid = match r.take::<toml::Table>("pin_grid")? {
            None => PinGridParams::default(),
            Some(t) => PinGridParams::read(&r.key_path("pin_grid"), t)?,
        };
        Ok(PinParams {
            mode,
            tracking,
            march_step,
            grid,
        })
    }

    pub fn write(&self, t: &mut toml::Table) {
        if *self != PinParams::default() {
            t.insert("pins".into(), self.mode.name().into());
            if let Some(k) = self.tracking {
                let name = if k == Tracking::RayMarching {
                    "ray_marching"
                } else {
                    "unbiased"
                };
                t.insert("tracking".into(), name.into());
            }
            t.insert("march_step".into(), f64::from(self.march_step).into());
            t.insert("pin_grid".into(), self.grid.write().into());
        }
    }

    /// The render-time stream of the grids `set` (gathered), when pins are
    /// on and `pin_grid.stream` asks for one (unquantised pins read no grid).
    pub fn stream(&self, set: Option<&Arc<PinSet>>) -> Option<super::pin_stream::PinStream> {
        let g = &self.grid;
        let set = set.filter(|_| g.stream > 0 && !g.unquantised && self.mode != PinMode::Off)?;
        Some(super::pin_stream::PinStream::new(
            set.clone(),
            g.stream,
            g.stream_spacing,
            g.seed,
        ))
    }

    /// The tracking of rays without pins: as given, else ray marching when
    /// pins are on (the thesis) and the unbiased samplers when off.
    pub fn tracking(&self) -> Tracking {
        self.tracking.unwrap_or(if self.mode == PinMode::Off {
            Tracking::Unbiased
        } else {
            Tracking::RayMarching
        })
    }

    /// Every medium's grid as a plan, when pins are on: its spec and seed,
    /// or the earlier medium whose grid it shares. Instances of one
    /// `[[media]]` entry share a grid when they differ by a rigid motion
    /// (Hansen 2025 §3.10: one grid for all instances); a scaled copy has
    /// other optical depths and gets its own. Every spec is checked here
    /// (size limits), so building cannot fail later.
    pub fn plan(&self, world: &World) -> Result<Option<Vec<GridPlan>>, SceneError> {
        if self.mode == PinMode::Off {
            return Ok(None);
        }
        let mut plan: Vec<GridPlan> = Vec::with_capacity(world.media.len());
        for (i, sm) in world.media.iter().enumerate() {
            let m = &sm.medium;
            let shared = world.media[..i]
                .iter()
                .position(|o| o.entry == sm.entry && rigidly_moved(&o.medium, m));
            if let Some(j) = shared {
                // Point at the owner, not at another sharer.
                plan.push(match plan[j] {
                    GridPlan::Shared(k) => GridPlan::Shared(k),
                    GridPlan::Own { .. } => GridPlan::Shared(j),
                });
                continue;
            }
            let d = m.dims();
            let voxels = d.iter().map(|&x| x as u64).product();
            let spec = self.grid.spec(self.grid.positions_for(voxels));
            spec.pin_count()
                .map_err(|e| SceneError(format!("media.{}: {e}", sm.entry)))?;
            plan.push(GridPlan::Own {
                spec,
                seed: self.grid.seed ^ ((i as u64) << 32),
            });
        }
        Ok(Some(plan))
    }

    /// Every medium's grid, gathered (§3.7) on the CPU as [`Self::plan`]
    /// lays them out, when pins are on.
    pub fn build(&self, world: &World) -> Result<Option<Arc<PinSet>>, SceneError> {
        let Some(plan) = self.plan(world)? else {
            return Ok(None);
        };
        let mut media: Vec<Option<Arc<PinGrid>>> = Vec::with_capacity(plan.len());
        for (sm, p) in world.media.iter().zip(&plan) {
            let (spec, seed) = match *p {
                GridPlan::Shared(j) => {
                    media.push(media[j].clone());
                    continue;
                }
                GridPlan::Own { spec, seed } => (spec, seed),
            };
            let m = &sm.medium;
            let err = |e: String| SceneError(format!("media.{}: {e}", sm.entry));
            let cube = unit_cube(m);
            let grid = match m.view() {
                MediumView::F16(v) => PinGrid::gather(&v, &cube, spec, seed),
                MediumView::F32(v) => PinGrid::gather(&v, &cube, spec, seed),
                MediumView::Analytic(v) => PinGrid::gather(&v, &cube, spec, seed),
            }
            .map_err(err)?;
            media.push(Some(Arc::new(grid)));
        }
        Ok(Some(Arc::new(PinSet {
            media,
            mask_iterations: self.grid.mask_iterations,
            unquantised: self.grid.unquantised,
        })))
    }

    /// Free-flight sampling of the ray leaving vertex `depth` (0: the view
    /// ray).
    pub fn flight<'a>(
        &self,
        depth: u32,
        base: DistanceSampler,
        pins: Option<&'a PinSet>,
    ) -> Flight<'a> {
        let use_pins = match self.mode {
            PinMode::Off => false,
            PinMode::All => true,
            PinMode::Secondary | PinMode::Ms => depth >= 1,
        };
        self.pick(
            use_pins,
            pins,
            Flight::Pins,
            Flight::RayMarching {
                step: self.march_step,
            },
            base.into(),
        )
    }

    /// NEE transmittance at scattering vertex `vertex` (0: the first).
    pub fn shadow<'a>(&self, vertex: u32, base: Estimator, pins: Option<&'a PinSet>) -> Shadow<'a> {
        let use_pins = match self.mode {
            PinMode::Off => false,
            PinMode::All | PinMode::Secondary => true,
            PinMode::Ms => vertex >= 1,
        };
        self.pick(
            use_pins,
            pins,
            Shadow::Pins,
            Shadow::RayMarching {
                step: self.march_step,
            },
            base.into(),
        )
    }

    fn pick<'a, T>(
        &self,
        use_pins: bool,
        pins: Option<&'a PinSet>,
        with: impl Fn(&'a PinSet) -> T,
        marching: T,
        unbiased: T,
    ) -> T {
        match (use_pins, pins) {
            (true, Some(p)) => with(p),
            _ if self.tracking() == Tracking::RayMarching => marching,
            _ => unbiased,
        }
    }
}

/// Whether `b` is `a` moved rigidly (the same local lengths in the world):
/// b's linear map is a rotation of a's, Bᵀ·B = Aᵀ·A.
fn rigidly_moved(a: &fogbank_volume::Medium, b: &fogbank_volume::Medium) -> bool {
    let (ma, mb) = (a.index_to_world.matrix3, b.index_to_world.matrix3);
    let (ga, gb) = (ma.transpose() * ma, mb.transpose() * mb);
    let scale = ga
        .to_cols_array()
        .iter()
        .fold(0.0f64, |s, v| s.max(v.abs()));
    a.dims() == b.dims()
        && ga
            .to_cols_array()
            .iter()
            .zip(gb.to_cols_array())
            .all(|(x, y)| (x - y).abs() <= 1e-9 * scale)
}
