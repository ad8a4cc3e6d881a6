//! Lin et al. 2021's frame-time table on a GPU (§6, Fig. 22's timings):
//! `restir` at 1920×1080 (the paper's resolution) with the
//! paper's defaults (M = 4, Q = 4, 3 neighbours within 10 px, T̃ on mip 1),
//! K = 1, 3, 7 on the light-probe cloud and K = 3 on the emissive
//! explosion, device time per pass from timestamp queries averaged over the
//! measured frames after a warm-up; beside it the paper's baseline
//! (`volpath` with `preset = "restir_baseline"`) at 1 spp on the same
//! device, so the table also says how many baseline samples one ReSTIR
//! frame costs. `--trials` sets the measured frames (default 16). Needs a
//! GPU with timestamp queries (a CPU Vulkan device such as lavapipe runs
//! it, slowly, but its times say nothing about a GPU).

use crate::harness::protocol::build;
use crate::harness::timing::gpu_ms_per_spp;
use crate::harness::Writer;
use fogbank_gpu::restir::{PassMs, RestirGpu, STORED_BYTES};
use fogbank_gpu::Gpu;
use fogbank_render::integrators::IntegratorKind;

const WARM_UP: u32 = 4;
const WIDTH: u32 = 1920;
const HEIGHT: u32 = 1080;

fn probe_cloud(width: u32, height: u32) -> String {
    format!(
        "[camera]\nfrom = [0.0, 0.1, 2.0]\nto = [0.0, 0.0, 0.0]\nfov = 40.0\nwidth = {width}\nheight = {height}\n\
         [[media]]\ndensity = {{ procedural = \"cloud\", resolution = 128, seed = 7 }}\n\
         sigma_t_scale = 40.0\nalbedo = [0.95, 0.95, 0.95]\nphase = {{ type = \"hg\", g = 0.5 }}\n\
         [[lights]]\ntype = \"envmap\"\nfile = \"probes/sky.hdr\"\n\
         [render]\npixel_jitter = false\n"
    )
}

fn explosion(width: u32, height: u32) -> String {
    format!(
        "[camera]\nfrom = [0.0, 0.1, 1.9]\nto = [0.0, -0.02, 0.0]\nfov = 40.0\nwidth = {width}\nheight = {height}\n\
         [[media]]\ndensity = {{ procedural = \"explosion\", resolution = 128, seed = 3 }}\n\
         sigma_t_scale = 10.0\nalbedo = [0.55, 0.55, 0.55]\nphase = {{ type = \"hg\", g = 0.3 }}\n\
         emission = {{ temperature = {{ procedural = \"explosion\", quantity = \"temperature\", resolution = 128, seed = 3 }}, scale = 40.0 }}\n\
         [[lights]]\ntype = \"constant\"\nradiance = [0.02, 0.025, 0.03]\n\
         [render]\npixel_jitter = false\n"
    )
}

/// Mean device milliseconds per frame of each pass over `frames` frames.
fn restir_times(gpu: &Gpu, text: &str, k: u32, frames: u32) -> Result<PassMs, String> {
    let set = vec![
        "integrator.type=restir".to_string(),
        format!("integrator.max_depth={k}"),
    ];
    let scene = build(text, &set)?;
    let reuse = match &scene.integrator {
        IntegratorKind::Restir(r) => r.params.reuse,
        _ => unreachable!("the scene's integrator is restir"),
    };
    let err = |e: fogbank_gpu::GpuError| e.0;
    let mut kernels = RestirGpu::new(gpu, &scene, 1).map_err(err)?;
    let data = kernels.upload(gpu, &scene).map_err(err)?;
    kernels.start_sequences(0, 1);
    for f in 0..WARM_UP + frames {
        if f == WARM_UP {
            kernels.times = PassMs::default();
        }
        kernels
            .frame(gpu, &data, &data, f, f + 1 == WARM_UP + frames, reuse)
            .map_err(err)?;
    }
    let t = kernels.times;
    let n = t.frames.max(1) as f64;
    Ok(PassMs {
        candidates: t.candidates / n,
        temporal: t.temporal / n,
        spatial: t.spatial / n,
        shading: t.shading / n,
        frames: t.frames,
    })
}

/// Device milliseconds of one baseline sample per pixel (median of five
/// `spp`-sample renders).
fn baseline_ms(gpu: &Gpu, text: &str, k: u32, spp: u32) -> Result<f64, String> {
    let set = vec![
        "integrator.type=volpath".to_string(),
        "integrator.preset=restir_baseline".to_string(),
        format!("integrator.max_depth={k}"),
        "media.0.supervoxel=8".to_string(),
    ];
    gpu_ms_per_spp(gpu, text, &set, spp)
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let gpu = Gpu::new().map_err(|e| e.0)?;
    run_on(&gpu, w, trials, WIDTH, HEIGHT)
}

/// [`run`] on `gpu` at `width`×`height` (smaller sizes for smoke tests).
pub fn run_on(
    gpu: &Gpu,
    w: &mut Writer,
    trials: Option<u64>,
    width: u32,
    height: u32,
) -> Result<String, String> {
    let frames = trials.unwrap_or(16).clamp(1, 10_000) as u32;
    if !gpu.timestamps {
        return Err(format!(
            "{}: no timestamp queries, so no per-pass times",
            gpu.describe()
        ));
    }
    let cases = [
        ("light-probe cloud", probe_cloud(width, height), 1),
        ("light-probe cloud", probe_cloud(width, height), 3),
        ("light-probe cloud", probe_cloud(width, height), 7),
        ("explosion", explosion(width, height), 3),
    ];
    let (mut rows, mut table) = (Vec::new(), Vec::new());
    for (name, text, k) in &cases {
        let t = restir_times(gpu, text, *k, frames)?;
        let total = t.candidates + t.temporal + t.spatial + t.shading;
        let base = baseline_ms(gpu, text, *k, 16)?;
        table.push(format!(
            "| {name} | {k} | {:.2} | {:.2} | {:.2} | {:.2} | **{:.2}** | {:.2} | {:.1} |",
            t.candidates,
            t.temporal,
            t.spatial,
            t.shading,
            total,
            base,
            total / base
        ));
        rows.push(vec![
            name.to_string(),
            k.to_string(),
            format!("{:.4}", t.candidates),
            format!("{:.4}", t.temporal),
            format!("{:.4}", t.spatial),
            format!("{:.4}", t.shading),
            format!("{total:.4}"),
            format!("{base:.4}"),
        ]);
    }
    w.csv(
        "frame_time.csv",
        &[
            "case",
            "k",
            "candidates_ms",
            "temporal_ms",
            "spatial_ms",
            "shading_ms",
            "frame_ms",
            "baseline_spp_ms",
        ],
        &rows,
    )?;
    // Per pixel: three reservoir regions and the accumulation buffers.
    let bytes = 3 * STORED_BYTES + 16 + 16 + 4;
    Ok(format!(
        "Lin et al. 2021's frame times on {} at {width}×{height}: device time per pass from timestamp queries, \
         mean of {frames} frames after {WARM_UP} warm-up frames (one sequence, M = 4, Q = 4, 3 neighbours \
         within 10 px, T̃ on mip 1, exact trilinear T in shading). \"baseline 1 spp\" is `volpath` with the \
         `restir_baseline` preset (super-voxels of 8³), median of 5 renders of 16 spp. The paper (RTX 3090, its scenes, \
         all passes): 55 ms at K = 1 and 142 ms at K = 3 (Fig. 1, bunny), 83.8 ms at K = 3 (Fig. 19, Disney \
         cloud); it matches the baseline's spp to the frame time but does not print them.\n\n\
         | scene | K | candidates ms | temporal ms | spatial ms | shading ms | frame ms | baseline 1 spp ms | frame / baseline spp |\n\
         |---|---|---|---|---|---|---|---|---|\n{}\n\n\
         Memory per pixel: {bytes} bytes ({} MiB at {width}×{height}): three reservoir regions of {STORED_BYTES} bytes \
         (candidates, temporal output, the previous frame's; paths of up to 8 vertices) and the accumulation buffers.\n",
        gpu.describe(),
        table.join("\n"),
        (bytes * width as u64 * height as u64) >> 20
    ))
}

#[cfg(test)]
mod smoke_test {
    use crate::harness::timing::timestamp_test_gpu;
    use crate::harness::Writer;

    /// The experiment runs end to end (at 32×18, one measured frame) on
    /// whatever device there is — lavapipe in CI — and writes its table and
    /// CSV with one row per case; the times themselves mean nothing there.
    #[test]
    fn frame_time_table_is_written() {
        let Some(gpu) = timestamp_test_gpu() else {
            return;
        };
        let mut w = Writer::temp("fogbank_gpu_frame_time");
        let summary = super::run_on(&gpu, &mut w, Some(1), 32, 18).unwrap();
        assert!(summary.contains("| explosion | 3 |"), "{summary}");
        let csv = std::fs::read_to_string(w.path("frame_time.csv")).unwrap();
        assert_eq!(csv.lines().count(), 5, "{csv}");
        for line in csv.lines().skip(1) {
            let frame_ms: f64 = line.split(',').nth(6).unwrap().parse().unwrap();
            assert!(frame_ms > 0.0 && frame_ms.is_finite(), "{line}");
        }
    }
}
