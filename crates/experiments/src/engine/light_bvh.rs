//! The light BVH against picking lights by power (Lin et al. 2021
//! Fig. 18's setting of many small emitters in a medium), on the CPU:
//! for each scene a reference through the BVH, then both samplers at the
//! same spp (time, MSE, relMSE and the mean per-pixel variance the films
//! report, over all pixels and over the darker 70 % — fog and road, where
//! NEE decides; bright pixels see windows directly) and at equal time (the
//! BVH given the power sampler's time). Scenes: `scenes/street` (3200
//! emitting triangles facing a foggy street) and
//! `scenes/mitsuba/fog_emitters.xml` (300 triangles of random facing
//! scattered in fog).

use crate::harness::protocol::scenes_dir;
use crate::harness::Writer;
use fogbank_image::metrics::{relmse, Image};
use fogbank_render::{render, Film, Progress, RenderOptions, Scene};
use fogbank_scene::load_scene;
use std::time::Duration;

struct Case {
    name: &'static str,
    file: &'static str,
    size: Option<(u32, u32)>,
    spp: u32,
    reference_spp: u32,
}

const CASES: [Case; 2] = [
    Case {
        name: "street (3200 triangles)",
        file: "street/window_street.xml",
        size: Some((160, 90)),
        spp: 64,
        reference_spp: 2048,
    },
    Case {
        name: "fog_emitters (300 triangles)",
        file: "mitsuba/fog_emitters.xml",
        size: None,
        spp: 1024,
        reference_spp: 16384,
    },
];

fn scene(case: &Case, selection: &str) -> Result<Scene, String> {
    let mut o = vec![format!("render.light_sampler={selection}")];
    if let Some((w, h)) = case.size {
        o.push(format!("camera.width={w}"));
        o.push(format!("camera.height={h}"));
    }
    load_scene(Some(&scenes_dir().join(case.file)), &o).map_err(|e| e.0)
}

fn image(f: &Film) -> Image {
    Image::new(f.width as usize, f.height as usize, f.mean())
}

/// (MSE, relMSE) against `reference`, mean variance of the pixel means
/// over all pixels and over the reference's darker 70 %.
fn errors(reference: &Film, test: &Film) -> Result<[f64; 4], String> {
    let (r, t) = (reference.mean(), test.mean());
    let mse = (r.iter().zip(&t))
        .map(|(a, b)| (0..3).map(|c| ((a[c] - b[c]) as f64).powi(2)).sum::<f64>() / 3.0)
        .sum::<f64>()
        / r.len() as f64;
    let var: Vec<f64> = (test.variance_of_mean().iter())
        .map(|v| (v[0] + v[1] + v[2]) as f64 / 3.0)
        .collect();
    let lum: Vec<f32> = r.iter().map(|&c| fogbank_image::luminance(c)).collect();
    let mut sorted = lum.clone();
    sorted.sort_by(f32::total_cmp);
    let cut = sorted[(0.7 * (sorted.len() - 1) as f64) as usize];
    let dark: Vec<f64> = (var.iter().zip(&lum))
        .filter(|(_, &l)| l <= cut)
        .map(|(v, _)| *v)
        .collect();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    Ok([
        mse,
        relmse(&image(reference), &image(test))?,
        mean(&var),
        mean(&dark),
    ])
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let mut rows = Vec::new();
    let mut table = Vec::new();
    for case in &CASES {
        let opts = |spp, seed, budget: Option<f64>| RenderOptions {
            spp,
            seed,
            time_budget: budget.map(Duration::from_secs_f64),
        };
        let reference_spp = trials.map_or(case.reference_spp, |t| t as u32);
        let reference = render(
            &scene(case, "bvh")?,
            &opts(reference_spp, 1000, None),
            &Progress::default(),
        )
        .film;
        let mut power_seconds = 0.0;
        for (selection, budget) in [("power", None), ("bvh", None), ("bvh", Some(()))] {
            let s = scene(case, selection)?;
            let r = match budget {
                None => render(&s, &opts(case.spp, 7, None), &Progress::default()),
                Some(()) => render(
                    &s,
                    &opts(1 << 20, 7, Some(power_seconds)),
                    &Progress::default(),
                ),
            };
            if selection == "power" {
                power_seconds = r.seconds;
            }
            let [mse, rel, var, dark] = errors(&reference, &r.film)?;
            let spp = r.film.min_spp();
            let label = match budget {
                None => selection.to_string(),
                Some(()) => format!("{selection}, power's time"),
            };
            rows.push(vec![
                case.name.to_string(),
                label.clone(),
                spp.to_string(),
                format!("{:.3}", r.seconds),
                format!("{mse:.4e}"),
                format!("{rel:.4e}"),
                format!("{var:.4e}"),
                format!("{dark:.4e}"),
            ]);
            table.push(format!(
                "| {} | {label} | {spp} | {:.2} | {mse:.3e} | {rel:.3e} | {var:.3e} | {dark:.3e} |",
                case.name, r.seconds
            ));
        }
    }
    w.csv(
        "light_bvh.csv",
        &[
            "scene",
            "light_sampler",
            "spp",
            "seconds",
            "mse",
            "relmse",
            "mean_variance",
            "mean_variance_darker_70",
        ],
        &rows,
    )?;
    Ok(format!(
        "Light selection by power against the light BVH (CPU, all threads), errors against a BVH reference \
         ({} / {} spp); variance is the films' own variance of each pixel mean.\n\n\
         | scene | light sampler | spp | s | MSE | relMSE | mean variance | variance, darker 70 % |\n\
         |---|---|---|---|---|---|---|---|\n{}",
        CASES[0].reference_spp,
        CASES[1].reference_spp,
        table.join("\n")
    ))
}
