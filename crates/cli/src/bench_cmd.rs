//! `fogbank bench`: per-estimator cost and accuracy of the transmittance view
//! of a procedural cloud, measured side by side in one run
//! (`fogbank::bench`), printed as Markdown tables.

use crate::common::CliResult;
use clap::Args;
use fogbank::bench::{bench_estimators, integrator_scaling, BenchEvent, BenchSpec};

#[derive(Args)]
pub struct BenchArgs {
    /// Cloud resolution (voxels per side).
    #[arg(long, default_value_t = 256)]
    pub resolution: u32,
    /// Image width and height for timing.
    #[arg(long, default_value_t = 512)]
    pub size: u32,
    /// Frames (1 spp each) per timing.
    #[arg(long, default_value_t = 4)]
    pub frames: u32,
    /// Thread counts to time, comma separated.
    #[arg(long, default_value = "1,2", value_delimiter = ',')]
    pub threads: Vec<usize>,
    /// Estimators (comma separated), each `NAME` or `NAME:KEY=VALUE:…`
    /// (`ratio_tracking:roulette=0.1`); default all.
    #[arg(long, value_delimiter = ',')]
    pub estimators: Vec<String>,
    /// Extinction scale of the cloud.
    #[arg(long, default_value_t = 60.0)]
    pub sigma_t_scale: f32,
    /// Image size for the bias/std measurement (0 skips it).
    #[arg(long, default_value_t = 64)]
    pub stats_size: u32,
    /// Frames for the bias/std measurement.
    #[arg(long, default_value_t = 2048)]
    pub stats_frames: u32,
    /// Devices to time, comma separated: `cpu` (at each of --threads) and/or
    /// `gpu` (wgpu; kernel time from timestamp queries when available).
    #[arg(long, default_value = "cpu", value_delimiter = ',')]
    pub device: Vec<String>,
    /// Also write the table as JSON.
    #[arg(long)]
    pub json: Option<std::path::PathBuf>,
    /// Also time these integrators (comma separated: transmittance, direct,
    /// volpath, point_mis, restir, ament, visopt) on the cloud lit by a sky
    /// and a sun, at each of --threads on the CPU, with each thread count's
    /// speed-up over the first: the thread-scaling table.
    #[arg(long, value_delimiter = ',')]
    pub integrators: Vec<String>,
    /// Rounds of the thread-scaling table: with N > 1, one untimed warm-up
    /// render per thread count, then N rounds, each timing every thread
    /// count in turn; the table gives the median ms per frame, its range,
    /// and the median of the rounds' speed-ups (pairing each round's
    /// timings keeps the ratio meaningful on a machine whose speed drifts).
    #[arg(long, default_value_t = 1)]
    pub repeat: u32,
}

pub fn run(a: BenchArgs) -> CliResult {
    let spec = BenchSpec {
        resolution: a.resolution,
        size: a.size,
        frames: a.frames,
        threads: a.threads,
        estimators: a.estimators,
        sigma_t_scale: a.sigma_t_scale,
        stats_size: a.stats_size,
        stats_frames: a.stats_frames,
        devices: a.device,
        integrators: a.integrators,
        repeat: a.repeat,
    };
    let rows = bench_estimators(&spec, &mut |event| match event {
        BenchEvent::Note(n) => eprintln!("{n}"),
        BenchEvent::Timing => {
            println!("| estimator | threads (or gpu) | ms/frame | Mrays/s | lookups/ray | mean abs bias | mean std |");
            println!("|---|---:|---:|---:|---:|---:|---:|");
        }
        BenchEvent::Estimator(r) => {
            let (bias, std) = r
                .accuracy
                .map_or(("–".to_string(), "–".to_string()), |(b, s)| {
                    (format!("{b:.5}"), format!("{s:.4}"))
                });
            println!(
                "| {} | {} | {:.1} | {:.2} | {:.1} | {bias} | {std} |",
                r.label, r.device, r.ms_per_frame, r.mrays_per_s, r.lookups_per_ray
            );
        }
        BenchEvent::Scaling(_) => {}
    })?;
    if let Some(p) = &a.json {
        let json: Vec<_> = rows.iter().map(|r| r.to_json()).collect();
        std::fs::write(p, serde_json::to_string_pretty(&json)?)
            .map_err(|e| format!("{}: {e}", p.display()))?;
    }
    if spec.integrators.is_empty() {
        return Ok(());
    }
    println!();
    println!(
        "| integrator | threads | ms/frame (median of {}) | range | speed-up over {} thread(s) (median) |",
        spec.repeat.max(1),
        spec.threads[0]
    );
    println!("|---|---:|---:|---:|---:|");
    integrator_scaling(&spec, &mut |event| {
        if let BenchEvent::Scaling(r) = event {
            println!(
                "| {} | {} | {:.1} | {:.1}–{:.1} | {:.2}× |",
                r.integrator, r.threads, r.ms_median, r.ms_min, r.ms_max, r.speedup
            );
        }
    })?;
    Ok(())
}
