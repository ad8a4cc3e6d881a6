//! Hansen 2025 Fig. 4.10 and fogbank's speed criterion for pins: many overlapping
//! instances of one cloud (10, 50, 250), albedo 1, isotropic, 8 bounces,
//! under the sky probe; the ray-marching baseline at step 0.08 against
//! PinMS (pins for multiple scattering, ray marching at the same step for
//! the view ray and first-vertex NEE; grid at the thesis's 0.1× of the
//! half-float density), both on the CPU in one run, interleaved. Reported:
//! time per sample (pin building excluded and reported apart; the thesis
//! builds pins once), lookups, and per-frame MSE against an unbiased
//! `volpath` reference ("at similar error"). The thesis (RTX 2070 Super):
//! RM 1.93 / 25.57 / 136.2 ms, PinMS 1.83 / 20.16 / 87.41 ms → 1.05 /
//! 1.27 / 1.56×.

use crate::harness::protocol::{build, independent_frames, set, Reference};
use crate::harness::timing::clocked;
use crate::harness::Writer;
use fogbank_math::Pcg32;

pub const COUNTS: [u32; 3] = [10, 50, 250];
/// The thesis's step for this figure.
pub const STEP: f32 = 0.08;
const SPP: u32 = 16;
const REPEATS: u32 = 3;
/// The thesis's evaluation numbers (RM ms, PinMS ms).
pub const THESIS: [(f64, f64); 3] = [(1.93, 1.83), (25.57, 20.16), (136.2, 87.41)];

/// `n` seeded rigid placements: translations uniform in
/// [−h.x, h.x] × [−h.y, h.y] × [−h.z, z_max], random axes and angles.
pub fn placements(n: u32, seed: u64, h: [f32; 3], z_max: f32) -> Vec<String> {
    let mut rng = Pcg32::new(seed, 1);
    let mut u = |lo: f32, hi: f32| lo + (hi - lo) * rng.next_f32();
    (0..n)
        .map(|_| {
            let t = [u(-h[0], h[0]), u(-h[1], h[1]), u(-h[2], z_max)];
            let axis = [u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0)];
            let deg = u(0.0, 360.0);
            format!(
                "{{ translate = [{:.3}, {:.3}, {:.3}], rotate = [{:.3}, {:.3}, {:.3}, {deg:.1}] }}",
                t[0], t[1], t[2], axis[0], axis[1], axis[2]
            )
        })
        .collect()
}

/// Scene text: `n` rigid copies of a 64³ procedural cloud (unit box,
/// centred) at seeded random places and orientations in a 4.4 × 2.8 × 2.8
/// slab before the camera, so they overlap; `size` the image width.
pub fn scene(n: u32, width: u32, height: u32) -> String {
    let places = placements(n, 0x0004_0410, [2.2, 1.4, 2.0], 0.8);
    format!(
        "[camera]\nfrom = [0.0, 0.0, 5.0]\nto = [0.0, 0.0, 0.0]\nfov = 50.0\nwidth = {width}\nheight = {height}\n\
         [[media]]\ndensity = {{ procedural = \"cloud\", resolution = 64, seed = 7 }}\n\
         sigma_t_scale = 8.0\nalbedo = [1.0, 1.0, 1.0]\nto_world = {{ translate = [-0.5, -0.5, -0.5] }}\n\
         instances = [{}]\n\
         [[lights]]\ntype = \"envmap\"\nfile = \"probes/sky.hdr\"\n\
         [integrator]\ntype = \"volpath\"\nmax_depth = 8\nmarch_step = {STEP}\n[render]\npixel_jitter = false\n",
        places.join(", ")
    )
}

pub struct Row {
    pub n: u32,
    pub rm_ms: f64,
    pub pin_ms: f64,
    pub build_s: f64,
    pub rm_mse: f64,
    pub pin_mse: f64,
}

pub fn measure(n: u32, width: u32, height: u32, reference_spp: u32) -> Result<Row, String> {
    let text = scene(n, width, height);
    let reference = Reference::render(&build(&text, &[])?, reference_spp, 0x0410);
    let rm = build(&text, &set(&["integrator.tracking=ray_marching"]))?;
    let (pin, build_s) = clocked(|| build(&text, &set(&["integrator.pins=ms"])));
    let pin = pin?;
    let (mut rm_ms, mut pin_ms, mut rm_mse, mut pin_mse) = (0.0, 0.0, 0.0, 0.0);
    // Interleaved, so drift of the machine's speed hits both alike.
    for r in 0..REPEATS {
        let a = independent_frames(&rm, &reference, SPP, 1, 100 + 10 * r);
        let b = independent_frames(&pin, &reference, SPP, 1, 200 + 10 * r);
        rm_ms += a.ms / (SPP * REPEATS) as f64;
        pin_ms += b.ms / (SPP * REPEATS) as f64;
        rm_mse += a.mse / REPEATS as f64;
        pin_mse += b.mse / REPEATS as f64;
    }
    Ok(Row {
        n,
        rm_ms,
        pin_ms,
        build_s,
        rm_mse,
        pin_mse,
    })
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let reference_spp = trials.unwrap_or(64).min(1 << 16) as u32;
    let threads = rayon::current_num_threads();
    let (width, height) = (64, 48);
    let mut rows = Vec::new();
    let mut lines = Vec::new();
    for (i, &n) in COUNTS.iter().enumerate() {
        let r = measure(n, width, height, reference_spp)?;
        let (t_rm, t_pin) = THESIS[i];
        rows.push(vec![
            n.to_string(),
            format!("{:.3}", r.rm_ms),
            format!("{:.3}", r.pin_ms),
            format!("{:.3}", r.rm_ms / r.pin_ms),
            format!("{:.3}", r.build_s),
            format!("{:.4e}", r.rm_mse),
            format!("{:.4e}", r.pin_mse),
            format!("{:.2}", t_rm / t_pin),
        ]);
        lines.push(format!(
            "| {n} | {:.1} | {:.1} | **{:.2}×** | {:.2} s | {:.3e} | {:.3e} | {t_rm} / {t_pin} ms → {:.2}× |",
            r.rm_ms,
            r.pin_ms,
            r.rm_ms / r.pin_ms,
            r.build_s,
            r.rm_mse,
            r.pin_mse,
            t_rm / t_pin
        ));
    }
    w.csv(
        "instances.csv",
        &[
            "instances",
            "rm_ms_per_spp",
            "pinms_ms_per_spp",
            "speedup",
            "pin_build_s",
            "rm_mse_4spp",
            "pinms_mse_4spp",
            "thesis_speedup",
        ],
        &rows,
    )?;
    Ok(format!(
        "Hansen 2025 Fig. 4.10 on fogbank's CPU ({threads} threads), {width}×{height}, pixel centres, 8 bounces, albedo 1, \
         sky probe; ray marching at step {STEP} vs PinMS (same step for the view ray and first NEE), {REPEATS} interleaved \
         rounds of one {SPP}-spp frame each; MSE per {SPP}-spp frame against unbiased `volpath` at {reference_spp} spp \
         (its variance subtracted). Time per sample excludes scene and pin-grid building (listed apart).\n\n\
         | instances | RM ms/spp | PinMS ms/spp | RM/PinMS | pin build | RM MSE | PinMS MSE | thesis (GPU) |\n\
         |---|---|---|---|---|---|---|---|\n{}\n",
        lines.join("\n")
    ))
}
