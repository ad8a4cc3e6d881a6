//! Hansen 2025 Fig. 4.12 (and the boundary bias of hard-edged volumes, shown
//! and measured): the thesis finds PinMS's worst error at
//! the hard boundaries of dense volumes lit from the side — contrast lost
//! at the edges, the shadowed back brighter. fogbank measures it on the
//! Teapot stand-in of Fig. 4.11 (`sphere.vdb` as a dense fog, hard-edged)
//! against the soft procedural cloud, both lit from the left — by a square
//! area light as in the thesis (Figs. 4.12–4.13), and by a point light, the
//! harder case — plus a dim ambient, 8 bounces: the relative error of PinMS
//! and of ray marching in three bands of the unbiased reference's
//! brightness on the object (shadowed third, middle, lit third), on its
//! silhouette pixels, and the lit/shadowed contrast over the reference's.

use super::runtime::CASES;
use crate::harness::protocol::{build, lum, Reference};
use crate::harness::Writer;

pub const DEFAULT_SPP: u64 = 256;
const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;
/// The ambient light's radiance: what a pixel that misses the object shows.
const AMBIENT: f32 = 0.02;

/// (name, `[[media]]` text, ray-marching step) of the two volumes.
fn volumes() -> Result<[(&'static str, String, f32); 2], String> {
    Ok([
        (
            "hard-edged (Teapot stand-in: sphere.vdb fog, σ_t 40)",
            CASES[0].media()?,
            0.03,
        ),
        (
            "soft (procedural cloud 64³, σ_t 20)",
            "[[media]]\ndensity = { procedural = \"cloud\", resolution = 64, seed = 7 }\n\
             sigma_t_scale = 20.0\nalbedo = [0.95, 0.95, 0.95]\n"
                .into(),
            0.08,
        ),
    ])
}

/// (file key, label, scene text) of the two key lights, both at the left:
/// a 1 × 1 square facing the object (the thesis's area light) of radiance
/// 12, whose irradiance at the object nearly matches the point light's
/// (intensity 12 at distance 2.5).
pub const LIGHTS: [(&str, &str, &str); 2] = [
    (
        "area",
        "area light (thesis)",
        "[[shapes]]\ntype = \"rectangle\"\n\
         to_world = { translate = [-2.5, 0.4, 0.3], rotate = [0.0, 1.0, 0.0, 90.0], scale = 0.5 }\n\
         emitter = { radiance = [12.0, 12.0, 12.0] }\n",
    ),
    (
        "point",
        "point light",
        "[[lights]]\ntype = \"point\"\nposition = [-2.5, 0.4, 0.3]\nintensity = [12.0, 12.0, 12.0]\n",
    ),
];

pub fn scene(media: &str, light: &str) -> String {
    format!(
        "[camera]\nfrom = [0.0, 0.3, 2.4]\nto = [0.0, 0.0, 0.0]\nfov = 40.0\nwidth = {WIDTH}\nheight = {HEIGHT}\n\
         {media}{light}\
         [[lights]]\ntype = \"constant\"\nradiance = [{AMBIENT}, {AMBIENT}, {AMBIENT}]\n\
         [integrator]\ntype = \"volpath\"\nmax_depth = 8\n[render]\npixel_jitter = false\n"
    )
}

/// (label, overrides) of the methods at ray-marching step `step`.
pub fn methods(step: f32) -> [(&'static str, Vec<String>); 5] {
    let st = format!("integrator.march_step={step}");
    [
        (
            "ray marching",
            vec!["integrator.tracking=ray_marching".into(), st.clone()],
        ),
        (
            "PinMS (thesis: view ray and first NEE ray-marched)",
            vec!["integrator.pins=ms".into(), st],
        ),
        (
            "PinMS, view ray and first NEE unbiased (pins only)",
            vec![
                "integrator.pins=ms".into(),
                "integrator.tracking=unbiased".into(),
            ],
        ),
        (
            "PinMS as above, grid 10× the texture",
            vec![
                "integrator.pins=ms".into(),
                "integrator.tracking=unbiased".into(),
                "integrator.pin_grid.memory_ratio=10".into(),
            ],
        ),
        (
            "PinMS as above, unquantised pins (traced along each ray)",
            vec![
                "integrator.pins=ms".into(),
                "integrator.tracking=unbiased".into(),
                "integrator.pin_grid.unquantised=true".into(),
            ],
        ),
    ]
}

/// Pixel sets of the reference: the object (brighter or darker than the
/// ambient by 5 %), its brightness thirds, and its silhouette (object
/// pixels with a 4-neighbour off the object).
pub struct Regions {
    pub thirds: [Vec<usize>; 3],
    pub silhouette: Vec<usize>,
}

impl Regions {
    pub fn of(reference: &[[f32; 3]]) -> Regions {
        let a = lum(&[AMBIENT; 3]);
        let on: Vec<bool> = reference
            .iter()
            .map(|p| (lum(p) - a).abs() > 0.05 * a)
            .collect();
        let mut object: Vec<usize> = (0..on.len()).filter(|&i| on[i]).collect();
        object.sort_by(|&i, &j| lum(&reference[i]).total_cmp(&lum(&reference[j])));
        let n = object.len();
        let thirds = [
            object[..n / 3].to_vec(),
            object[n / 3..2 * n / 3].to_vec(),
            object[2 * n / 3..].to_vec(),
        ];
        let (w, h) = (WIDTH as usize, HEIGHT as usize);
        let silhouette = (0..on.len())
            .filter(|&i| {
                let (x, y) = (i % w, i / w);
                on[i]
                    && (x == 0
                        || y == 0
                        || x + 1 == w
                        || y + 1 == h
                        || !on[i - 1]
                        || !on[i + 1]
                        || !on[i - w]
                        || !on[i + w])
            })
            .collect();
        Regions { thirds, silhouette }
    }
}

/// Summed luminance of `img` over `set`.
fn sum(img: &[[f32; 3]], set: &[usize]) -> f64 {
    set.iter().map(|&k| lum(&img[k])).sum()
}

/// Relative error of the summed luminance of `img` over `set`.
fn relative(img: &[[f32; 3]], reference: &[[f32; 3]], set: &[usize]) -> f64 {
    sum(img, set) / sum(reference, set).max(1e-30) - 1.0
}

/// Lit third over shadowed third, relative to the reference's ratio.
fn contrast(img: &[[f32; 3]], reference: &[[f32; 3]], r: &Regions) -> f64 {
    let ratio = |i: &[[f32; 3]]| sum(i, &r.thirds[2]) / sum(i, &r.thirds[0]);
    ratio(img) / ratio(reference)
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let spp = trials.unwrap_or(DEFAULT_SPP).clamp(1, 1 << 16) as u32;
    let (mut rows, mut lines) = (Vec::new(), Vec::new());
    for (key, light_label, light) in LIGHTS {
        for (vi, (volume, media, step)) in volumes()?.into_iter().enumerate() {
            let text = scene(&media, light);
            let reference = Reference::render(&build(&text, &[])?, 4 * spp, 0x0B0D);
            let regions = Regions::of(&reference.rgb);
            let png = |w: &mut Writer, name: &str, rgb: &[[f32; 3]]| {
                w.png(
                    &format!("{key}_volume{vi}_{name}.png"),
                    WIDTH,
                    HEIGHT,
                    rgb,
                    0.0,
                )
            };
            png(w, "reference", &reference.rgb)?;
            let check = Reference::render(&build(&text, &[])?, spp, 0x0B0E);
            let mut all = vec![("unbiased volpath (noise only)", check.rgb)];
            for (mi, (label, set)) in methods(step).into_iter().enumerate() {
                let img = Reference::render(&build(&text, &set)?, spp, 0x0B0F);
                png(w, &format!("method{mi}"), &img.rgb)?;
                all.push((label, img.rgb));
            }
            for (label, img) in all {
                let e: Vec<f64> = regions
                    .thirds
                    .iter()
                    .chain([&regions.silhouette])
                    .map(|set| relative(&img, &reference.rgb, set))
                    .collect();
                let c = contrast(&img, &reference.rgb, &regions) - 1.0;
                lines.push(format!(
                    "| {light_label} | {volume} | {label} | {:+.1} % | {:+.1} % | {:+.1} % | {:+.1} % | {:+.1} % |",
                    100.0 * e[0],
                    100.0 * e[1],
                    100.0 * e[2],
                    100.0 * e[3],
                    100.0 * c
                ));
                let mut row = vec![
                    light_label.to_string(),
                    volume.to_string(),
                    label.to_string(),
                ];
                row.extend(e.iter().chain([&c]).map(|x| format!("{x:+.5}")));
                rows.push(row);
            }
        }
    }
    w.csv(
        "boundary.csv",
        &[
            "light",
            "volume",
            "method",
            "shadowed_third",
            "middle_third",
            "lit_third",
            "silhouette",
            "contrast",
        ],
        &rows,
    )?;
    Ok(format!(
        "Hansen 2025 Figs. 4.12–4.13, boundary bias: {WIDTH}×{HEIGHT}, a 1 × 1 area light (the thesis's) or a point light \
         from the left + ambient {AMBIENT}, \
         8 bounces, {spp} spp per method against unbiased `volpath` at {} spp. Relative error of the summed \
         luminance over the object's shadowed / middle / lit third of pixels (by the reference's brightness) \
         and over its silhouette; contrast = (lit ÷ shadowed) over the reference's, minus 1 (negative: contrast \
         lost). Images: L_volumeV_reference.png, L_volumeV_methodM.png (L: area or point; M as the rows, ray \
         marching first).\n\n\
         | light | volume | method | shadowed | middle | lit | silhouette | contrast |\n|---|---|---|---|---|---|---|---|\n{}\n",
        4 * spp,
        lines.join("\n")
    ))
}
