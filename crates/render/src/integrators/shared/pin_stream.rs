//! The pin stream (Hansen 2025 §3.4.4, §3.7): before a pass (a frame of the
//! thesis), R new pins are traced through uniform points of each medium's
//! box with directions normalise(U³ − ½) and written into the cells of
//! points `spacing` apart along their chords ([`PinGrid::stream`]), so that
//! a grid follows a changing density and its quantisation artefacts move
//! from pass to pass. The thesis's evaluation uses static pins; its code
//! streams 1000 pins a frame, written 0.1 apart. `pin_grid.stream` turns it
//! on in renders ([`PinStream`]): pass s renders with the gathered grids
//! after the streams of passes 0..=s, each keyed by ([`stream_seed`]), so a
//! render stays a function of scene, seed and sample index — a shard
//! starting at pass s₀ replays the streams before it.

use super::tracking::{unit_cube, PinSet};
use crate::world::World;
use fogbank_estimators::pins::PinGrid;
use fogbank_volume::MediumView;
use std::sync::Arc;

/// The author's code defaults: pins per frame and write spacing (unit-cube
/// edges).
pub const STREAM_PINS: u32 = 1000;
pub const STREAM_SPACING: f32 = 0.1;

/// The random-stream seed of pass `pass`'s stream into the grid owned by
/// medium `owner`, from `pin_grid.seed`: pin i of it draws from
/// Pcg32(seed, i) on the CPU and the GPU alike.
pub fn stream_seed(grid_seed: u64, owner: usize, pass: u32) -> u64 {
    // SplitMix64's finaliser over the three keys, so neighbouring passes
    // and media get unrelated seeds.
    let mut z = grid_seed
        ^ (owner as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ u64::from(pass)
            .wrapping_add(1)
            .wrapping_mul(0xD1B5_4A32_D192_ED03);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// `set` after pass `pass`'s stream of `count` pins into each distinct
/// grid of `world`'s media (instances keep sharing theirs, the grid's
/// owner — the first medium holding it — keys its seed; the grids of `set`
/// are not changed, the result holds new ones).
pub fn stream(
    set: &PinSet,
    world: &World,
    count: u32,
    spacing: f32,
    grid_seed: u64,
    pass: u32,
) -> PinSet {
    let mut out = set.clone();
    let mut streamed: Vec<(*const PinGrid, Arc<PinGrid>)> = Vec::new();
    for (owner, (sm, slot)) in world.media.iter().zip(out.media.iter_mut()).enumerate() {
        let Some(g) = slot.as_ref() else {
            continue;
        };
        let old = Arc::as_ptr(g);
        if let Some((_, new)) = streamed.iter().find(|(p, _)| *p == old) {
            *slot = Some(new.clone());
            continue;
        }
        let mut grid = (**g).clone();
        let m = &sm.medium;
        let cube = unit_cube(m);
        let seed = stream_seed(grid_seed, owner, pass);
        match m.view() {
            MediumView::F16(v) => grid.stream(&v, &cube, count, spacing, seed),
            MediumView::F32(v) => grid.stream(&v, &cube, count, spacing, seed),
            MediumView::Analytic(v) => grid.stream(&v, &cube, count, spacing, seed),
        }
        let new = Arc::new(grid);
        streamed.push((old, new.clone()));
        *slot = Some(new);
    }
    out
}

/// A render's streamed grids: the gathered set and the set after the
/// streams of passes 0..=`pass` for the pass being rendered.
pub struct PinStream {
    gathered: Arc<PinSet>,
    current: Arc<PinSet>,
    /// Passes whose streams `current` holds (0..next).
    next: u32,
    count: u32,
    spacing: f32,
    grid_seed: u64,
}

impl PinStream {
    pub fn new(gathered: Arc<PinSet>, count: u32, spacing: f32, grid_seed: u64) -> PinStream {
        PinStream {
            current: gathered.clone(),
            gathered,
            next: 0,
            count,
            spacing,
            grid_seed,
        }
    }

    /// The grids pass `pass` renders with: the gathered ones after the
    /// streams of passes 0..=pass (replayed from the gathered grids when
    /// `pass` is earlier than the last one asked for).
    pub fn at(&mut self, world: &World, pass: u32) -> &Arc<PinSet> {
        if pass < self.next.saturating_sub(1) {
            (self.current, self.next) = (self.gathered.clone(), 0);
        }
        while self.next <= pass {
            let s = stream(
                &self.current,
                world,
                self.count,
                self.spacing,
                self.grid_seed,
                self.next,
            );
            (self.current, self.next) = (Arc::new(s), self.next + 1);
        }
        &self.current
    }
}
