//! Hansen 2025, fogbank's bias bar for pins (not the thesis's): PinMS on
//! an albedo-1 isotropic cloud, 8 bounces, under an environment light and
//! under a point light, rendered to convergence, against unbiased `volpath`;
//! the relative error of the image mean and the mean per-pixel relative
//! error (pixels brighter than 5 % of the mean; includes what noise is
//! left), as the pin grid grows (0.1×, 1×, 10× the half-float texture).
//! PinMS's view ray and first NEE use the unbiased samplers here
//! (`tracking = "unbiased"`), so the table isolates the pins' bias; one row
//! per case adds the thesis's ray marching (step 0.03) for those rays.

use crate::harness::protocol::{build, Reference};
use crate::harness::trials::Moments;
use crate::harness::Writer;

pub const DEFAULT_SPP: u64 = 1024;

/// Pin grids are one random realisation each: every cell holds one pin
/// with one draw of its bits, and a light seen from one direction reads the
/// same few pins from every point of a cell, so one grid's image mean
/// scatters by several percent around the method's expectation. Each row
/// is the mean over this many grid seeds (`pin_grid.seed`), with the
/// standard error across them.
pub const GRID_SEEDS: u64 = 4;

const CLOUD: &str =
    "[camera]\nfrom = [0.0, 0.1, 2.0]\nto = [0.0, 0.0, 0.0]\nfov = 40.0\nwidth = 48\nheight = 36\n\
    [[media]]\ndensity = { procedural = \"cloud\", resolution = 64, seed = 7 }\n\
    sigma_t_scale = 20.0\nalbedo = [1.0, 1.0, 1.0]\n\
    [integrator]\ntype = \"volpath\"\nmax_depth = 8\n[render]\npixel_jitter = false\n";

pub fn cases() -> [(&'static str, String); 2] {
    [
        (
            "environment",
            format!("{CLOUD}[[lights]]\ntype = \"envmap\"\nfile = \"probes/sky.hdr\"\n"),
        ),
        (
            "point light",
            format!(
                "{CLOUD}[[lights]]\ntype = \"point\"\nposition = [0.8, 0.7, 0.6]\nintensity = [3.0, 3.0, 3.0]\n\
                 [[lights]]\ntype = \"constant\"\nradiance = [0.02, 0.02, 0.02]\n"
            ),
        ),
    ]
}

/// (label, overrides) of the rows of one case.
pub fn settings() -> Vec<(String, Vec<String>)> {
    let mut v: Vec<(String, Vec<String>)> = ["0.1", "1", "10"]
        .iter()
        .map(|r| {
            (
                format!("PinMS, grid {r}×"),
                vec![
                    "integrator.pins=ms".to_string(),
                    "integrator.tracking=unbiased".to_string(),
                    format!("integrator.pin_grid.memory_ratio={r}"),
                ],
            )
        })
        .collect();
    v.push((
        "PinMS, unquantised pins (traced along each ray)".into(),
        vec![
            "integrator.pins=ms".into(),
            "integrator.tracking=unbiased".into(),
            "integrator.pin_grid.unquantised=true".into(),
        ],
    ));
    v.push((
        "PinMS, grid 0.1×, ray marching 0.03 for the other rays".into(),
        vec![
            "integrator.pins=ms".into(),
            "integrator.march_step=0.03".into(),
        ],
    ));
    v
}

fn stats(img: &[[f32; 3]], reference: &[[f32; 3]]) -> (f64, f64) {
    let sum = |i: &[[f32; 3]]| i.iter().map(|p| (p[0] + p[1] + p[2]) as f64).sum::<f64>();
    let (a, r) = (sum(img), sum(reference));
    let floor = 0.05 * r / reference.len() as f64;
    let (mut rel, mut n) = (0.0, 0);
    for (p, q) in img.iter().zip(reference) {
        let (x, y) = ((p[0] + p[1] + p[2]) as f64, (q[0] + q[1] + q[2]) as f64);
        if y > floor {
            rel += (x - y).abs() / y;
            n += 1;
        }
    }
    (a / r - 1.0, rel / n.max(1) as f64)
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let spp = trials.unwrap_or(DEFAULT_SPP).clamp(1, 1 << 16) as u32;
    let mut rows = Vec::new();
    let mut lines = Vec::new();
    for (case, text) in cases() {
        let reference = Reference::render(&build(&text, &[])?, 2 * spp, 0x0B1A);
        // The noise of a render at this spp, for scale: an unbiased one.
        let check = Reference::render(&build(&text, &[])?, spp, 0x0B1B);
        let (b0, r0) = stats(&check.rgb, &reference.rgb);
        lines.push(format!(
            "| {case} | unbiased volpath (noise only) | {:+.2} % | {:.2} % |",
            100.0 * b0,
            100.0 * r0
        ));
        rows.push(vec![
            case.to_string(),
            "unbiased".into(),
            format!("{b0:+.5}"),
            String::new(),
            format!("{r0:.5}"),
        ]);
        for (label, set) in settings() {
            let mut means = Moments::default();
            let mut pixel = 0.0;
            for g in 0..GRID_SEEDS {
                let mut set = set.clone();
                set.push(format!("integrator.pin_grid.seed={}", 0x51D0 + g));
                let img = Reference::render(&build(&text, &set)?, spp, 0x0B1C + g as u32);
                let (b, r) = stats(&img.rgb, &reference.rgb);
                means.push(b);
                pixel += r / GRID_SEEDS as f64;
            }
            let (b, se) = (means.mean(), means.std_error());
            lines.push(format!(
                "| {case} | {label} | {:+.2} ± {:.2} % | {:.2} % |",
                100.0 * b,
                100.0 * se,
                100.0 * pixel
            ));
            rows.push(vec![
                case.to_string(),
                label,
                format!("{b:+.5}"),
                format!("{se:.5}"),
                format!("{pixel:.5}"),
            ]);
        }
    }
    w.csv(
        "bias.csv",
        &[
            "case",
            "setting",
            "mean_relative_error",
            "standard_error_over_grid_seeds",
            "mean_pixel_relative_error",
        ],
        &rows,
    )?;
    Ok(format!(
        "Hansen 2025 bias bar: 48×36, 64³ cloud, albedo 1, isotropic, 8 bounces; {spp} spp per row against unbiased \
         `volpath` at {} spp. \"mean\": relative error of the image mean; \"per pixel\": mean |x − r|/r over pixels \
         above 5 % of the mean (noise included; the unbiased row shows its size). Pin rows: mean over {GRID_SEEDS} pin-grid \
         seeds ± the standard error across them (one grid is one random realisation). Goal: ≤ 2 %, falling as \
         the grid grows.\n\n| case | setting | mean | per pixel |\n|---|---|---|---|\n{}\n",
        2 * spp,
        lines.join("\n")
    ))
}
