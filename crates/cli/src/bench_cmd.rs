//! `fogbank bench`: primary-ray transmittance throughput per estimator on a
//! procedural cloud, measured side by side in one run for each thread count.

use crate::{thread_pool, CliResult};
use clap::Args;
use fogbank_estimators::Estimator;
use fogbank_render::{parse_scene, render, Progress, RenderOptions, Scene};
use std::path::Path;

#[derive(Args)]
pub struct BenchArgs {
    /// Cloud resolution (voxels per side).
    #[arg(long, default_value_t = 256)]
    pub resolution: u32,
    /// Image width and height.
    #[arg(long, default_value_t = 512)]
    pub size: u32,
    /// Frames (1 spp each) per measurement.
    #[arg(long, default_value_t = 4)]
    pub frames: u32,
    /// Thread counts to measure, comma separated.
    #[arg(long, default_value = "1,2", value_delimiter = ',')]
    pub threads: Vec<usize>,
    /// Estimators (comma separated); default all.
    #[arg(long, value_delimiter = ',')]
    pub estimators: Vec<String>,
    /// Extinction scale of the cloud.
    #[arg(long, default_value_t = 60.0)]
    pub sigma_t_scale: f32,
    /// Also write the table as JSON.
    #[arg(long)]
    pub json: Option<std::path::PathBuf>,
}

pub fn run(a: BenchArgs) -> CliResult {
    let estimators: Vec<Estimator> = if a.estimators.is_empty() {
        Estimator::all()
    } else {
        a.estimators
            .iter()
            .map(|n| Estimator::parse(n).ok_or_else(|| format!("unknown estimator `{n}`")))
            .collect::<Result<_, _>>()?
    };
    let text = format!(
        r#"
[camera]
from = [0.0, 0.05, 2.2]
to = [0.0, -0.05, 0.0]
fov = 32.0
width = {s}
height = {s}
[[media]]
density = {{ procedural = "cloud", resolution = {r}, seed = 7 }}
sigma_t_scale = {k}
filter = "stochastic_trilinear"
[render]
spp = {f}
"#,
        s = a.size,
        r = a.resolution,
        k = a.sigma_t_scale,
        f = a.frames
    );
    eprintln!("building a {}³ cloud ...", a.resolution);
    let desc = parse_scene(&text, "bench scene", &[])?;
    let mut scene = Scene::build(desc, Path::new("."))?;
    let rays = (a.size as u64 * a.size as u64 * a.frames as u64) as f64;
    println!("| estimator | threads | ms/frame | Mrays/s | lookups/ray |");
    println!("|---|---:|---:|---:|---:|");
    let mut rows = Vec::new();
    for &threads in &a.threads {
        let pool = thread_pool(Some(threads))?;
        for e in estimators.iter().copied() {
            scene.integrator = fogbank_render::scene::IntegratorKind::Transmittance {
                estimator: e,
                background: glam::Vec3::ONE,
            };
            let opts = RenderOptions {
                spp: a.frames,
                seed: 1,
                time_budget: None,
            };
            let r = pool.install(|| render(&scene, &opts, &Progress::default()));
            let ms = r.seconds * 1000.0 / a.frames as f64;
            let mrays = rays / r.seconds / 1e6;
            let lpr = r.film.lookups as f64 / rays;
            println!(
                "| {} | {} | {:.1} | {:.2} | {:.1} |",
                e.name(),
                threads,
                ms,
                mrays,
                lpr
            );
            rows.push(serde_json::json!({"estimator": e.name(), "threads": threads, "ms_per_frame": ms, "mrays_per_s": mrays, "lookups_per_ray": lpr}));
        }
    }
    if let Some(p) = &a.json {
        std::fs::write(p, serde_json::to_string_pretty(&rows)?)
            .map_err(|e| format!("{}: {e}", p.display()))?;
    }
    Ok(())
}
