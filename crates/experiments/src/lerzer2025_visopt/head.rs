//! Lerzer and Dachsbacher 2025's head studies on the MNI152 T1 template (the paper's VISIBLE
//! HUMAN head replaced by a freely available brain; `tools/fetch_data.sh mni`):
//!
//! - Fig. 9: the three multiple-scattering settings of §5.4 (single
//!   scattering; optimised first NEE + plain multiple scattering; every NEE
//!   optimised), time per pass at equal spp and the images, lobe on, n = 40;
//! - Fig. 10: r swept over 0 … 70 (q = 70) with a two-valued importance
//!   (white matter ∧ right half → 0.75, white matter ∧ left half → 1), the
//!   images and their mean radiance;
//! - Fig. 12: light-ray list sizes, time per pass and RMSE against a
//!   reference with 1000-sample lists at 4× the spp (lobe off, as in Figs.
//!   10 and 12).
//!
//! Images are small (the CPU has 2 cores); the paper renders 800² on a GPU.

use crate::harness::protocol::{render_at, set};
use crate::harness::Writer;
use fogbank_image::metrics::{self, Image};
use fogbank_render::{parse_scene, Scene};
use std::path::PathBuf;

pub const DEFAULT_SPP: u64 = 16;
pub(super) const WIDTH: u32 = 96;

/// `data/mni/`, or an error saying how to fetch the templates.
pub(super) fn data() -> Result<PathBuf, String> {
    let d = fogbank_math::sample_data::mni_dir();
    if d.join("mni_t1.nii.gz").exists() {
        Ok(d)
    } else {
        Err(format!(
            "{}: the MNI152 templates are missing; run tools/fetch_data.sh mni",
            d.display()
        ))
    }
}

pub(super) fn scene(importance: &str, extra: &[String]) -> Result<Scene, String> {
    let d = data()?;
    let text = format!(
        "camera = {{ from = [-260.0, 60.0, 120.0], to = [0.0, -18.0, 10.0], width = {WIDTH}, height = {WIDTH} }}\n\
         lights = [{{ type = \"directional\", direction = [0.6, -0.5, -0.6], irradiance = [1.6, 1.6, 1.6] }}]\n\
         integrator = {{ type = \"visopt\" }}\n\
         [[media]]\ndensity = {{ nifti = \"mni_t1.nii.gz\" }}\nsigma_t_scale = 0.6\n\
         transfer = {{ opacity = [[60, 0], [140, 0.05], [200, 0.6], [255, 1]], color = [[0, 0.9, 0.6, 0.5], [255, 1, 0.95, 0.9]] }}\n\
         {importance}\n"
    );
    let desc = parse_scene(&text, "visopt-head", extra).map_err(|e| e.to_string())?;
    Scene::build(desc, &d).map_err(|e| e.to_string())
}

pub(super) const WHITE_MATTER: &str = "importance = [{ mask = { nifti = \"mni_wm.nii.gz\" } }]";
/// Fig. 10's two-valued importance: the right half (x ≥ 0 in RAS) 0.75.
const TWO_VALUED: &str = "importance = [{ value = 0.75, mask = { nifti = \"mni_wm.nii.gz\" }, half_space = [1.0, 0.0, 0.0, 0.0] }, \
                          { value = 1.0, mask = { nifti = \"mni_wm.nii.gz\" } }]";

/// (seconds per pass, image) of `spp` passes with seed `seed`, the
/// integrator prepared before timing.
pub(super) fn timed(s: &Scene, spp: u32, seed: u32) -> (f64, Vec<[f32; 3]>) {
    s.integrator.prepare(&s.world);
    let r = render_at(s, spp, seed);
    (r.seconds / spp as f64, r.film.mean())
}

fn rmse(a: &[[f32; 3]], b: &[[f32; 3]]) -> Result<f64, String> {
    let image = |rgb: &[[f32; 3]]| Image::new(WIDTH as usize, WIDTH as usize, rgb.to_vec());
    metrics::rmse(&image(b), &image(a))
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let spp = trials.unwrap_or(DEFAULT_SPP) as u32;
    let mut out = String::new();
    out += &fig9(w, spp)?;
    out += &fig10(w, spp)?;
    out += &fig12(w, spp)?;
    Ok(out)
}

/// Fig. 9: the three multiple-scattering settings, `fig9_<mode>.png` and
/// `fig9.csv`; returns its section of the summary.
fn fig9(w: &mut Writer, spp: u32) -> Result<String, String> {
    let mut lines = Vec::new();
    let mut rows = Vec::new();
    let mut base = 0.0;
    for mode in ["single", "first", "all"] {
        let s = scene(
            WHITE_MATTER,
            &set(&[
                &format!("integrator.scattering=\"{mode}\""),
                "integrator.max_depth=8",
                "integrator.shading=true",
            ]),
        )?;
        let (secs, img) = timed(&s, spp, 3);
        if mode == "single" {
            base = secs;
        }
        w.png(&format!("fig9_{mode}.png"), WIDTH, WIDTH, &img, 0.0)?;
        rows.push(vec![
            mode.to_string(),
            format!("{secs:.4}"),
            format!("{:.3}", secs / base),
        ]);
        lines.push(format!("| {mode} | {secs:.3} | {:.2}× |", secs / base));
    }
    w.csv(
        "fig9.csv",
        &["scattering", "seconds_per_pass", "ratio"],
        &rows,
    )?;
    Ok(format!(
        "## Fig. 9: multiple-scattering settings ({WIDTH}², {spp} spp, max_depth 8, lobe on)\n\n\
         | setting | s per pass | / single |\n|---|---|---|\n{}\n\n\
         Paper (2000 spp, GPU): 12.13 s / 72.16 s / 157.21 s, i.e. 1 : 5.9 : 13.0. Images: fig9_*.png.\n\n",
        lines.join("\n")
    ))
}

/// Fig. 10: the r sweep with the two-valued importance, `fig10_r<r>.png`
/// and `fig10.csv`; returns its section of the summary.
fn fig10(w: &mut Writer, spp: u32) -> Result<String, String> {
    let mut lines = Vec::new();
    let mut rows = Vec::new();
    for r in [0.0f32, 10.0, 30.0, 50.0, 70.0] {
        let s = scene(TWO_VALUED, &set(&[&format!("integrator.r={r}")]))?;
        let (secs, img) = timed(&s, spp, 3);
        let mean: f64 = img.iter().map(|p| p[0] as f64).sum::<f64>() / img.len() as f64;
        w.png(&format!("fig10_r{r}.png"), WIDTH, WIDTH, &img, 0.0)?;
        rows.push(vec![
            r.to_string(),
            format!("{secs:.4}"),
            format!("{mean:.5}"),
        ]);
        lines.push(format!("| {r} | {secs:.3} | {mean:.4} |"));
    }
    w.csv(
        "fig10.csv",
        &["r", "seconds_per_pass", "mean_radiance"],
        &rows,
    )?;
    Ok(format!(
        "## Fig. 10: r sweep with the two-valued importance (white matter right 0.75, left 1; q = 70)\n\n\
         | r | s per pass | mean radiance |\n|---|---|---|\n{}\n\n\
         Paper: larger r removes more of the matter behind the important region (less background clutter). \
         Images: fig10_r*.png.\n\n",
        lines.join("\n")
    ))
}

/// Fig. 12: light-ray list sizes against 1000-sample lists at 4× the spp,
/// `fig12.csv`; returns its section of the summary.
fn fig12(w: &mut Writer, spp: u32) -> Result<String, String> {
    let reference = scene(WHITE_MATTER, &set(&["integrator.light_samples=1000"]))?;
    let (ref_secs, ref_img) = timed(&reference, 4 * spp, 99);
    let mut lines = Vec::new();
    let mut rows = Vec::new();
    for n in [0u32, 25, 50, 100, 200, 400] {
        let s = scene(
            WHITE_MATTER,
            &set(&[&format!("integrator.light_samples={n}")]),
        )?;
        let (secs, img) = timed(&s, spp, 3);
        let e = rmse(&img, &ref_img)?;
        rows.push(vec![n.to_string(), format!("{secs:.4}"), format!("{e:.5}")]);
        lines.push(format!("| {n} | {secs:.3} | {e:.4} |"));
    }
    w.csv(
        "fig12.csv",
        &["light_samples", "seconds_per_pass", "rmse_vs_1000"],
        &rows,
    )?;
    Ok(format!(
        "## Fig. 12: light-ray list sizes ({WIDTH}², {spp} spp; reference: 1000-sample lists at {} spp, {ref_secs:.3} s \
         per pass)\n\n| light samples | s per pass | RMSE vs 1000 |\n|---|---|---|\n{}\n\n\
         Paper (5000 spp): 21.47 / 27.17 / 28.2 / 37 s for unstated counts, reference 51.7 s; it settles on 200. \
         The RMSE includes the Monte Carlo noise of both images (independent seeds).\n",
        4 * spp,
        lines.join("\n")
    ))
}
