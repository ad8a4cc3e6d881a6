//! ReSTIR sequences over the frames of an animated scene, each frame
//! reusing from the one before it, with a `volpath` reference per frame, for the studies of moving scenes (`restir-dynamic`,
//! `restir-bias`) and the animated case of `restir-equal-time`.

use crate::harness::protocol::{build, Reference};
use fogbank_render::integrators::restir::frame::{FrameOutput, Sequence};
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::Scene;

/// Frames `0..n` of the animated scene `text` (with `set` overrides), each
/// built once so that many sequences can replay them.
pub fn build_frames(text: &str, set: &[String], n: u32) -> Result<Vec<Scene>, String> {
    let first = build(text, set)?;
    let mut frames = Vec::with_capacity(n as usize);
    for f in 1..n {
        frames.push(first.at_frame(f).map_err(|e| e.0)?);
    }
    frames.insert(0, first);
    Ok(frames)
}

/// One ReSTIR sequence (`sequence` of seed `seed`) over the built `frames`
/// of an animated scene, each frame reusing from the one before it;
/// `each(frame, output)` sees every frame.
pub fn restir_sequence(
    frames: &[Scene],
    seed: u32,
    sequence: u32,
    mut each: impl FnMut(usize, FrameOutput),
) {
    let restir = |s: &Scene| match &s.integrator {
        IntegratorKind::Restir(r) => r.clone(),
        _ => panic!("restir_sequence needs the restir integrator"),
    };
    let built: Vec<_> = frames.iter().map(restir).collect();
    let mut seq = Sequence::new(&built[0], seed, sequence);
    for (i, s) in frames.iter().enumerate() {
        let p = i.saturating_sub(1);
        let cur = built[i].data(&s.world);
        let old = built[p].data(&frames[p].world);
        each(i, seq.frame(&cur, &old));
    }
}

/// Per-frame `volpath` references of the animated scene `text`.
pub fn frame_references(
    text: &str,
    set: &[String],
    frames: std::ops::Range<u32>,
    spp: u32,
    seed: u32,
) -> Result<Vec<Reference>, String> {
    let mut set = set.to_vec();
    set.push("integrator.type=volpath".into());
    let first = build(text, &set)?;
    frames
        .map(|f| {
            let s = first.at_frame(f).map_err(|e| e.0)?;
            Ok(Reference::render(&s, spp, seed.wrapping_add(f)))
        })
        .collect()
}

/// RGB triples of a frame's radiance.
pub fn rgb(out: &FrameOutput) -> Vec<[f32; 3]> {
    out.radiance.iter().map(|l| l.to_array()).collect()
}
