//! The 5D pin grid (Hansen 2025 §3.6, §3.7, §3.10): P³ cells over the unit
//! cube × a hemisphere grid uniform in the polar angles (φ ∈ [0, 2π) in
//! `phi` bins, θ ∈ [0, π/2] in `theta` bins, the thesis's 16 × 4), one pin
//! per 5D cell, indexed position first. Initial population by gather (one
//! pin per cell through a uniform point of the cell with a direction
//! uniform in the cell's (φ, θ) ranges, as the author's `update_all`);
//! an optional stream re-traces random pins and writes each into the cells
//! along it; lookups jitter position and direction by a fraction of a cell.

use super::pin::{canonical, Pin, UnitCube};
use fogbank_math::{Pcg32, Vec3};
use fogbank_volume::VolumeAccess;
use rayon::prelude::*;
use std::f32::consts::{FRAC_PI_2, TAU};

/// Largest grid the builder accepts (2^28 pins = 2 GiB).
pub const MAX_PINS: u64 = 1 << 28;

/// What a pin grid is made of (`pin_grid = { … }` in a scene).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PinGridSpec {
    /// P: position cells per axis.
    pub positions: u32,
    /// Azimuth bins over [0, 2π).
    pub phi: u32,
    /// Polar bins over [0, π/2].
    pub theta: u32,
    /// Ray-marching step of pin tracing, in unit-cube edges (thesis: 0.01).
    pub step: f32,
    /// Lookup jitter of position and direction in cells (0..=1; the
    /// thesis's evaluation uses its strongest setting).
    pub jitter_position: f32,
    pub jitter_direction: f32,
    /// k of the majorant mask (§3.8).
    pub mask_iterations: u32,
}

impl Default for PinGridSpec {
    fn default() -> Self {
        PinGridSpec {
            positions: 16,
            phi: 16,
            theta: 4,
            step: 0.01,
            jitter_position: 1.0,
            jitter_direction: 1.0,
            mask_iterations: super::mask::DEFAULT_ITERATIONS,
        }
    }
}

impl PinGridSpec {
    pub fn directions(&self) -> u32 {
        self.phi * self.theta
    }

    /// Number of pins, refused past [`MAX_PINS`] or with a zero resolution.
    pub fn pin_count(&self) -> Result<u64, String> {
        if self.positions == 0 || self.phi == 0 || self.theta == 0 {
            return Err(format!(
                "pin_grid: positions, phi and theta must be ≥ 1 (got {}, {}, {})",
                self.positions, self.phi, self.theta
            ));
        }
        let n = (self.positions as u64).pow(3) * self.directions() as u64;
        if n > MAX_PINS {
            return Err(format!(
                "pin_grid: {}³ positions × {} directions = {n} pins ({} MiB), more than the limit of {MAX_PINS}",
                self.positions,
                self.directions(),
                (n * 8) >> 20
            ));
        }
        if !(self.step > 0.0 && self.step.is_finite()) {
            return Err(format!(
                "pin_grid.step must be positive (got {})",
                self.step
            ));
        }
        Ok(n)
    }

    /// The direction bin of `d` (either sign): flipped to +z, binned in φ
    /// and θ; index θ-bin · phi + φ-bin.
    pub fn direction_bin(&self, d: Vec3) -> u32 {
        let d = canonical(d).normalize_or_zero();
        let theta = d.z.clamp(-1.0, 1.0).acos();
        let mut phi = d.y.atan2(d.x);
        if phi < 0.0 {
            phi += TAU;
        }
        let ip = ((phi / TAU * self.phi as f32) as u32).min(self.phi - 1);
        let it = ((theta / FRAC_PI_2 * self.theta as f32) as u32).min(self.theta - 1);
        it * self.phi + ip
    }

    /// The cell of unit-cube point `p` and direction `d`.
    pub fn cell(&self, p: Vec3, d: Vec3) -> usize {
        let n = self.positions;
        let c = (p.clamp(Vec3::ZERO, Vec3::ONE) * n as f32)
            .as_uvec3()
            .min(glam::UVec3::splat(n - 1));
        let pos = ((c.z * n + c.y) * n + c.x) as usize;
        pos * self.directions() as usize + self.direction_bin(d) as usize
    }

    /// A point and direction uniform in cell `index`'s ranges (gather).
    pub fn sample_in_cell(&self, index: usize, rng: &mut Pcg32) -> (Vec3, Vec3) {
        let dirs = self.directions() as usize;
        let (pos, dir) = (index / dirs, (index % dirs) as u32);
        let n = self.positions as usize;
        let c = Vec3::new(
            (pos % n) as f32,
            ((pos / n) % n) as f32,
            (pos / (n * n)) as f32,
        );
        let p = (c + Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32())) / n as f32;
        let (ip, it) = (dir % self.phi, dir / self.phi);
        let phi = (ip as f32 + rng.next_f32()) / self.phi as f32 * TAU;
        let theta = (it as f32 + rng.next_f32()) / self.theta as f32 * FRAC_PI_2;
        let d = Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        );
        (p, d)
    }

    /// §3.9 jitter (the author's `apply_jitter`): position moved by
    /// j_p(½ − U³)/P (clamped to the cube), direction by j_d(½ − U³)/θ-bins
    /// (renormalised).
    pub fn jitter(&self, p: Vec3, d: Vec3, rng: &mut Pcg32) -> (Vec3, Vec3) {
        if self.jitter_position <= 0.0 && self.jitter_direction <= 0.0 {
            return (p, d);
        }
        let mut u3 =
            || Vec3::splat(0.5) - Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let p =
            (p + self.jitter_position * u3() / self.positions as f32).clamp(Vec3::ZERO, Vec3::ONE);
        let dj = d.normalize_or_zero() + self.jitter_direction * u3() / self.theta as f32;
        let d = if dj.length_squared() > 0.0 {
            dj.normalize()
        } else {
            d
        };
        (p, d)
    }
}

/// Pins a stream traces at a time (memory of the traced pins).
const STREAM_CHUNK: u32 = 1 << 16;

/// Smallest spacing of a stream pin's writes (unit-cube edges); scenes are
/// refused below it, so a pin writes at most √3/10⁻⁴ cells.
pub const MIN_STREAM_SPACING: f32 = 1e-4;

/// A stream pin's line and the offset of its first write, in the order
/// the random numbers are drawn (`pin_stream_kernel.wgsl` draws the same).
struct StreamLine {
    point: Vec3,
    direction: Vec3,
    offset: f32,
}

impl StreamLine {
    fn draw(spacing: f32, rng: &mut Pcg32) -> StreamLine {
        let point = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let direction =
            Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - Vec3::splat(0.5);
        let offset = rng.next_f32() * spacing;
        StreamLine {
            point,
            direction,
            offset,
        }
    }
}

/// The pins of one medium.
#[derive(Clone, Debug)]
pub struct PinGrid {
    pub spec: PinGridSpec,
    pub pins: Vec<Pin>,
}

impl PinGrid {
    /// Gather population (§3.7): every cell traces its own pin, cells in
    /// parallel, each from its own random stream (so the grid depends only
    /// on `seed`, not on threads).
    pub fn gather<V: VolumeAccess>(
        v: &V,
        cube: &UnitCube,
        spec: PinGridSpec,
        seed: u64,
    ) -> Result<PinGrid, String> {
        let n = spec.pin_count()? as usize;
        let pins = (0..n)
            .into_par_iter()
            .map(|i| {
                let mut rng = Pcg32::new(seed, i as u64);
                let (p, d) = spec.sample_in_cell(i, &mut rng);
                Pin::trace(v, cube, p, d, spec.step, &mut rng)
            })
            .collect();
        Ok(PinGrid { spec, pins })
    }

    /// The stream (§3.4.4, §3.7): `count` new pins, pin i from its own
    /// random stream Pcg32(`seed`, i) — a uniform point, a direction
    /// normalise(U³ − ½) (the author's), an offset U·`spacing`, then its
    /// trace — each written into the cells of points `spacing` apart along
    /// its chord from that offset. Pins are traced in parallel and written
    /// in index order (a later pin wins a cell), so the grid depends only
    /// on `seed`; the GPU writes them in any order, the write races the
    /// thesis tolerates.
    pub fn stream<V: VolumeAccess>(
        &mut self,
        v: &V,
        cube: &UnitCube,
        count: u32,
        spacing: f32,
        seed: u64,
    ) {
        let spec = self.spec;
        // Bounded memory for any count: traced a chunk at a time.
        for chunk in (0..count).step_by(STREAM_CHUNK as usize) {
            let traced: Vec<_> = (chunk..count.min(chunk + STREAM_CHUNK))
                .into_par_iter()
                .map(|i| {
                    let mut rng = Pcg32::new(seed, i as u64);
                    let line = StreamLine::draw(spacing, &mut rng);
                    let chord = cube.chord(line.point, line.direction)?;
                    let pin = Pin::trace(v, cube, line.point, line.direction, spec.step, &mut rng);
                    Some((pin, chord, line))
                })
                .collect();
            for (pin, (start, end), line) in traced.into_iter().flatten() {
                let len = (end - start).length();
                let mut s = line.offset;
                while s <= len {
                    let q = start + (end - start) * (s / len);
                    self.pins[spec.cell(q, line.direction)] = pin;
                    s += spacing.max(MIN_STREAM_SPACING);
                }
            }
        }
    }

    /// The pin for a query at unit-cube point `p` with direction `d`,
    /// after jitter; also returns the jittered point and direction, which
    /// the thesis's code uses for the query's chord as well.
    pub fn lookup(&self, p: Vec3, d: Vec3, rng: &mut Pcg32) -> (Pin, Vec3, Vec3) {
        let (p, d) = self.spec.jitter(p, d, rng);
        (self.pins[self.spec.cell(p, d)], p, d)
    }

    pub fn memory_bytes(&self) -> usize {
        self.pins.len() * std::mem::size_of::<Pin>()
    }
}
