//! The pin stream (seed 004 §3.4.4, §3.7): between frames, R new pins are
//! traced through uniform points of each medium's box with directions
//! normalise(U³ − ½) and written into the cells of points `spacing` apart
//! along their chords ([`PinGrid::stream`]), so that a grid follows a
//! changing density and its quantisation artefacts move from frame to
//! frame. The thesis's evaluation uses static pins; its code streams 1000
//! pins a frame, written 0.1 apart. Here a frame's grid is a function of the
//! previous grid and the random stream given, so a caller that keys that
//! stream by frame stays reproducible.

use super::tracking::{unit_cube, PinSet};
use crate::world::World;
use fogbank_estimators::pins::PinGrid;
use fogbank_math::Pcg32;
use fogbank_volume::MediumView;
use std::sync::Arc;

/// The author's code defaults: pins per frame and write spacing (unit-cube
/// edges).
pub const STREAM_PINS: u32 = 1000;
pub const STREAM_SPACING: f32 = 0.1;

/// `set` after `count` streamed pins into each distinct grid of `world`'s
/// media (instances keep sharing theirs; the grids of `set` are not
/// changed, the result holds new ones).
pub fn stream(set: &PinSet, world: &World, count: u32, spacing: f32, rng: &mut Pcg32) -> PinSet {
    let mut out = set.clone();
    let mut streamed: Vec<(*const PinGrid, Arc<PinGrid>)> = Vec::new();
    for (sm, slot) in world.media.iter().zip(out.media.iter_mut()) {
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
        match m.view() {
            MediumView::F16(v) => grid.stream(&v, &cube, count, spacing, rng),
            MediumView::F32(v) => grid.stream(&v, &cube, count, spacing, rng),
            MediumView::Analytic(v) => grid.stream(&v, &cube, count, spacing, rng),
        }
        let new = Arc::new(grid);
        streamed.push((old, new.clone()));
        *slot = Some(new);
    }
    out
}

#[cfg(test)]
mod pin_stream_test {
    use super::*;
    use crate::integrators::IntegratorKind;
    use crate::{parse_scene, Scene};

    /// Streaming rewrites some cells and keeps the rest, deterministically
    /// for a given random stream, and leaves the input set as it was.
    #[test]
    fn a_stream_rewrites_some_cells_reproducibly() {
        let text = "[camera]\nwidth = 4\nheight = 4\n\
            [[media]]\ndensity = { procedural = \"cloud\", resolution = 16 }\nsigma_t_scale = 10.0\n\
            [integrator]\ntype = \"volpath\"\npins = \"all\"\npin_grid = { positions = 4 }\n";
        let s = Scene::build(
            parse_scene(text, "t", &[]).unwrap(),
            std::path::Path::new("."),
        )
        .unwrap();
        let IntegratorKind::VolPath(v) = &s.integrator else {
            panic!("volpath");
        };
        let set = v.pin_set(&s.world).unwrap().clone();
        let before = set.media[0].as_ref().unwrap().pins.clone();
        let a = stream(&set, &s.world, 50, STREAM_SPACING, &mut Pcg32::new(3, 1));
        let b = stream(&set, &s.world, 50, STREAM_SPACING, &mut Pcg32::new(3, 1));
        let (pa, pb) = (
            &a.media[0].as_ref().unwrap().pins,
            &b.media[0].as_ref().unwrap().pins,
        );
        assert_eq!(pa, pb, "the same stream gives the same grid");
        assert_eq!(set.media[0].as_ref().unwrap().pins, before, "input kept");
        let changed = pa.iter().zip(&before).filter(|(x, y)| x != y).count();
        assert!(
            changed > 0 && changed < before.len(),
            "{changed} of {} cells",
            before.len()
        );
    }
}
