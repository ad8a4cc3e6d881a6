//! ReSTIR's side of Lin et al. 2021's equal-time protocol: a static scene's
//! sequence stepped frame by frame ([`RestirRun`]), so that per-pixel
//! rivals (the paper's baseline, the null-scattering tracer) can take turns
//! with it and share the machine's drift ([`equal_time_race`]).

use crate::harness::protocol::{Accumulator, BudgetRun, Frames, Reference};
use crate::harness::timing::clocked;
use fogbank_render::integrators::restir::frame::{PassTimes, Sequence};
use fogbank_render::integrators::restir::FrameData;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::Scene;

/// ReSTIR frames of one sequence of the static `scene` (its integrator
/// must be `restir`), one per [`RestirRun::step`], so that another run can
/// take turns with it and share the machine's drift.
pub struct RestirRun<'a> {
    data: FrameData<'a>,
    seq: Sequence<'a>,
    acc: Accumulator<'a>,
    /// Frames measured and their summed pass times.
    n: u32,
    passes: PassTimes,
    last: Vec<[f32; 3]>,
}

impl<'a> RestirRun<'a> {
    /// The sequence of `seed` after `warm_up` untimed frames.
    pub fn new(scene: &'a Scene, reference: &'a Reference, warm_up: u32, seed: u32) -> Self {
        let IntegratorKind::Restir(r) = &scene.integrator else {
            panic!("RestirRun needs the restir integrator");
        };
        let data = r.data(&scene.world);
        let mut seq = Sequence::new(r, seed, 0);
        for _ in 0..warm_up {
            seq.frame(&data, &data);
        }
        RestirRun {
            data,
            seq,
            acc: Accumulator::new(reference),
            n: 0,
            passes: PassTimes::default(),
            last: Vec::new(),
        }
    }

    /// Mean milliseconds per frame so far.
    pub fn ms(&self) -> f64 {
        self.acc.ms()
    }

    /// Forgets the frames measured so far (the sequence goes on): frames
    /// timed as a pilot become part of the warm-up.
    pub fn restart(&mut self) {
        self.acc = self.acc.cleared();
        self.n = 0;
        self.passes = PassTimes::default();
    }

    /// Renders and times one more frame.
    pub fn step(&mut self) {
        let (out, seconds) = clocked(|| self.seq.frame(&self.data, &self.data));
        self.last = out.radiance.iter().map(|l| l.to_array()).collect();
        self.acc.add(&self.last, seconds);
        self.n += 1;
        let (p, t) = (&mut self.passes, out.times);
        p.candidates += t.candidates;
        p.temporal += t.temporal;
        p.spatial += t.spatial;
        p.shading += t.shading;
    }

    /// The frames, with the mean time of each pass.
    pub fn finish(self) -> Frames {
        let n = self.n.max(1) as f64;
        let p = self.passes;
        let passes = PassTimes {
            candidates: p.candidates / n,
            temporal: p.temporal / n,
            spatial: p.spatial / n,
            shading: p.shading / n,
        };
        self.acc.finish(passes, self.last)
    }
}

/// A per-pixel integrator's frames raced against ReSTIR's: its spp (picked
/// from 1-spp frames timed during ReSTIR's warm-up) and its frames at that
/// spp.
pub struct Rival {
    pub one_spp: Frames,
    pub spp: u32,
    pub frames: Frames,
}

impl Rival {
    /// (colour, monochrome) MSE ratio rival/ReSTIR at ReSTIR's frame time:
    /// the rival's MSE scaled by the two measured frame times (MSE ∝ 1/time
    /// for its independent samples). > 1: ReSTIR has the lower MSE.
    pub fn ratios(&self, restir: &Frames) -> (f64, f64) {
        let scale = self.frames.ms / restir.ms;
        (
            self.frames.mse * scale / restir.mse,
            self.frames.mono_mse * scale / restir.mono_mse,
        )
    }
}

/// ReSTIR's frames on the static `restir` scene and `frames` frames of each
/// rival at the spp matching ReSTIR's frame time, every ReSTIR frame timed
/// in turn with one frame of each rival, so that the machine's drift (this
/// shared machine's speed wanders by tens of percent within a minute) and
/// each one's cold caches after the others' frames hit all alike. The
/// `warm_up` frames pair ReSTIR with 1-spp rival frames, whose times pick
/// the spp; the ratio then comes from the matched frames' own times, since
/// a 1-spp frame's fixed costs overstate a rival's time per sample. Rival
/// `i` is seeded `seed + 2000 i` (1 spp) and `seed + 1000 + 2000 i`.
pub fn equal_time_race(
    restir: &Scene,
    rivals: &[&Scene],
    reference: &Reference,
    warm_up: u32,
    frames: u32,
    restir_seed: u32,
    seed: u32,
) -> (Frames, Vec<Rival>) {
    let seed_of = |i: usize, k: u32| seed.wrapping_add(2000 * i as u32 + k);
    let mut run = RestirRun::new(restir, reference, 0, restir_seed);
    let mut ones: Vec<BudgetRun> = rivals
        .iter()
        .enumerate()
        .map(|(i, s)| BudgetRun::new(s, reference, 1, f64::INFINITY, &[], seed_of(i, 0)))
        .collect();
    for _ in 0..warm_up {
        run.step();
        ones.iter_mut().for_each(|o| _ = o.step());
    }
    let ones: Vec<Frames> = ones.into_iter().map(|o| o.finish().0).collect();
    let spps: Vec<u32> = ones
        .iter()
        .map(|o| ((run.ms() / o.ms).round() as u32).max(1))
        .collect();
    run.restart();
    let mut matched: Vec<BudgetRun> = rivals
        .iter()
        .enumerate()
        .map(|(i, s)| BudgetRun::new(s, reference, spps[i], f64::INFINITY, &[], seed_of(i, 1000)))
        .collect();
    for _ in 0..frames {
        run.step();
        matched.iter_mut().for_each(|m| _ = m.step());
    }
    let rivals = ones
        .into_iter()
        .zip(spps)
        .zip(matched)
        .map(|((one_spp, spp), m)| Rival {
            one_spp,
            spp,
            frames: m.finish().0,
        })
        .collect();
    (run.finish(), rivals)
}

/// `frames` ReSTIR frames of one sequence of the static `scene` (its
/// integrator must be `restir`) after `warm_up` frames.
pub fn restir_frames(
    scene: &Scene,
    reference: &Reference,
    warm_up: u32,
    frames: u32,
    seed: u32,
) -> Frames {
    let mut run = RestirRun::new(scene, reference, warm_up, seed);
    for _ in 0..frames {
        run.step();
    }
    run.finish()
}

#[cfg(test)]
mod tests {
    use super::{equal_time_race, restir_frames};
    use crate::harness::protocol::{build, set, Reference};

    const SCENE: &str = "[camera]\nfrom = [0.0, 0.1, 2.0]\nto = [0.0, 0.0, 0.0]\nfov = 40.0\n\
        width = 12\nheight = 8\n\
        [[media]]\ndensity = { procedural = \"cloud\", resolution = 16, seed = 7 }\n\
        sigma_t_scale = 20.0\nalbedo = [0.9, 0.9, 0.9]\n\
        [[lights]]\ntype = \"constant\"\nradiance = [0.8, 0.9, 1.0]\n\
        [render]\npixel_jitter = false\n";

    /// Racing changes nothing ReSTIR renders: its pilot frames are the
    /// warm-up, so the measured frames are `restir_frames`' bit for bit.
    /// (The rivals' spp comes from timings, so only their sanity is
    /// checked.)
    #[test]
    fn race_renders_what_restir_frames_renders() {
        // The rivals' MSE is net of the reference's variance and clamped at
        // 0; their spp follows the timings, which a busy machine can push
        // past a small reference's, so the reference has many more.
        let reference = Reference::render(
            &build(SCENE, &set(&["integrator.type=volpath"])).unwrap(),
            1024,
            1,
        );
        let restir = build(SCENE, &set(&["integrator.type=restir"])).unwrap();
        let rival = build(SCENE, &set(&["integrator.type=volpath"])).unwrap();
        let (raced, rivals) = equal_time_race(&restir, &[&rival, &rival], &reference, 2, 3, 9, 100);
        let alone = restir_frames(&restir, &reference, 2, 3, 9);
        assert_eq!(raced.last, alone.last);
        assert_eq!(raced.mse.to_bits(), alone.mse.to_bits());
        assert_eq!(raced.mono_mse.to_bits(), alone.mono_mse.to_bits());
        assert_eq!(rivals.len(), 2);
        for r in &rivals {
            assert!(r.spp >= 1 && r.frames.mse > 0.0 && r.frames.ms > 0.0);
            let (colour, mono) = r.ratios(&raced);
            assert!(colour.is_finite() && colour > 0.0 && mono.is_finite() && mono > 0.0);
        }
    }
}
