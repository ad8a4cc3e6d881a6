//! Hansen 2025 Figs. 4.1 and 4.6 : the pin stream
//! against static pins, on the surfaces scene of [`super::surfaces`]
//! (the Teapot stand-in on a diffuse ground, an area light from the left).
//! Each method accumulates 1-spp frames for the same render time, taking
//! turns; a streaming method traces R new pins into the grid before each
//! frame (`shared::pin_stream`, its time counted), writes 0.1 apart, from
//! a random stream keyed by the frame. Fig. 4.1: pins on every ray, the
//! stream rate raised (0 = static, 10³, 10⁴, 10⁵ pins a frame) — the thesis
//! finds the box artefacts on surfaces and in shadows shrink but remain.
//! Fig. 4.6: static against streamed pins with every ray on pins and with
//! PinMS (jitter on in both) — the thesis finds the stream helps only
//! surface shadows. Reported: MSE over the image and over the ground's
//! shadow region against unbiased `volpath`.

use super::surfaces::{region_mse, scene, shadow_region, HEIGHT, WIDTH};
use crate::harness::protocol::{build, render_at, Accumulator, Reference};
use crate::harness::Writer;
use fogbank_render::integrators::restir::frame::PassTimes;
use fogbank_render::integrators::shared::pin_stream::{stream, STREAM_SPACING};
use fogbank_render::integrators::shared::tracking::PinSet;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::Scene;
use std::sync::Arc;
use std::time::Instant;

/// Render time per method, seconds.
const BUDGET: f64 = 8.0;

/// (label, pin mode, pins streamed per frame).
const METHODS: [(&str, &str, u32); 6] = [
    ("all rays, static", "all", 0),
    ("all rays, stream 10^3", "all", 1_000),
    ("all rays, stream 10^4", "all", 10_000),
    ("all rays, stream 10^5", "all", 100_000),
    ("PinMS, static", "ms", 0),
    ("PinMS, stream 10^3", "ms", 1_000),
];

/// One method's frames with its own grid.
struct Run<'a> {
    scene: Scene,
    set: Option<Arc<PinSet>>,
    rate: u32,
    acc: Accumulator<'a>,
    /// Keys the method's stream (`pin_stream::stream_seed`).
    stream_key: u64,
    last: Vec<[f32; 3]>,
    /// Frames so far, and the first frame's seed (independent per method).
    frame: u32,
    seed: u32,
}

impl Run<'_> {
    /// One more frame (stream, then render) unless the budget is spent.
    fn step(&mut self) -> bool {
        if self.acc.seconds() >= BUDGET {
            return false;
        }
        let clock = Instant::now();
        if self.rate > 0 {
            if let Some(set) = &self.set {
                let next = Arc::new(stream(
                    set,
                    &self.scene.world,
                    self.rate,
                    STREAM_SPACING,
                    self.stream_key,
                    self.frame,
                ));
                if let IntegratorKind::VolPath(v) = &mut self.scene.integrator {
                    v.set_pin_set(Some(next.clone()));
                }
                self.set = Some(next);
            }
        }
        self.last = render_at(&self.scene, 1, self.seed + self.frame)
            .film
            .mean();
        self.acc.add(&self.last, clock.elapsed().as_secs_f64());
        self.frame += 1;
        true
    }
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let reference_spp = trials.unwrap_or(1024).min(1 << 16) as u32;
    let text = scene()?;
    let base = build(&text, &[])?;
    let region = shadow_region(&base);
    let reference = Reference::render(&base, reference_spp, 0x0413);
    let mut runs = Vec::new();
    for (i, (_, mode, rate)) in METHODS.iter().enumerate() {
        let set = vec![
            format!("integrator.pins={mode}"),
            "integrator.march_step=0.03".into(),
        ];
        let scene = build(&text, &set)?;
        let grid = match &scene.integrator {
            IntegratorKind::VolPath(v) => v.pin_set(&scene.world).cloned().map(Arc::new),
            _ => None,
        };
        runs.push(Run {
            scene,
            set: grid,
            rate: *rate,
            acc: Accumulator::new(&reference),
            stream_key: 0x0401 + i as u64,
            last: Vec::new(),
            frame: 0,
            seed: 0x0401_0000 + 0x0010_0000 * i as u32,
        });
    }
    while runs.iter_mut().fold(false, |any, r| r.step() | any) {}
    let (mut rows, mut lines) = (Vec::new(), Vec::new());
    for (run, (label, _, rate)) in runs.into_iter().zip(METHODS) {
        let mean = run.acc.mean();
        let frames = run.acc.finish(PassTimes::default(), run.last);
        let (mse, shadow) = (reference.mse(&mean), region_mse(&mean, &reference, &region));
        let spp = frames.curve.len();
        w.png(
            &format!("{}.png", label.replace([' ', ',', '^'], "_")),
            WIDTH,
            HEIGHT,
            &mean,
            0.0,
        )?;
        rows.push(vec![
            label.to_string(),
            rate.to_string(),
            spp.to_string(),
            format!("{mse:.4e}"),
            format!("{shadow:.4e}"),
        ]);
        lines.push(format!("| {label} | {spp} | {mse:.2e} | {shadow:.2e} |"));
    }
    w.csv(
        "pins_stream.csv",
        &[
            "method",
            "pins_per_frame",
            "spp_in_budget",
            "mse",
            "shadow_mse",
        ],
        &rows,
    )?;
    Ok(format!(
        "Hansen 2025 Figs. 4.1 and 4.6 on fogbank's CPU ({} threads), {WIDTH}×{HEIGHT}, 8 bounces, ray-marching step 0.03: \
         the scene of `pins-surfaces` (the Teapot stand-in on a diffuse ground, an area light from the left). Each \
         method accumulates 1-spp frames for {BUDGET} s (streaming counted), against unbiased `volpath` at \
         {reference_spp} spp (its variance subtracted); shadow-region MSE over the ground pixels the medium's box \
         hides from the light. Images: the accumulated means, `<method>.png`.\n\n\
         | method | spp in budget | MSE | shadow-region MSE |\n|---|---|---|---|\n{}\n",
        rayon::current_num_threads(),
        lines.join("\n")
    ))
}
