//! Scientific volumes placed as their files say: a NIfTI and a NRRD file written by
//! nibabel/pynrrd with non-trivial affines (oblique, flipped axes, LPS)
//! render at the same world place as the same voxels in a Mitsuba `.vol`
//! placed by the equivalent `to_world` (computed by the reference tools in
//! `make_placement.py`), pixel by pixel. The transmittance of the exact
//! trilinear integral is deterministic, so the two images agree to float
//! rounding; a one-voxel shift of the twin breaks the agreement (power).

use fogbank_render::{parse_scene, render, Progress, RenderOptions, Scene};
use std::path::{Path, PathBuf};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../volume/tests/fixtures/sci")
}

fn build(text: &str) -> Scene {
    let desc = parse_scene(text, "test", &[]).unwrap();
    Scene::build(desc, &fixtures()).unwrap()
}

/// Transmittance image of one medium (`density` and `to_world` as TOML)
/// seen from a fixed oblique direction around `centre`.
fn image(density: &str, to_world: &str, centre: [f32; 3], extent: f32, scale: f32) -> Vec<f32> {
    let [cx, cy, cz] = centre;
    let d = 2.5 * extent;
    let text = format!(
        "[camera]\nfrom = [{}, {}, {}]\nto = [{cx}, {cy}, {cz}]\nfov = 40.0\nwidth = 40\nheight = 30\n\
         [[media]]\ndensity = {density}\nto_world = {to_world}\nsigma_t_scale = {scale}\n\
         filter = \"trilinear\"\nprecision = \"f32\"\n\
         [integrator]\ntype = \"transmittance\"\nestimator = \"analytic_trilinear\"\n",
        cx + 0.6 * d,
        cy + 0.5 * d,
        cz + 0.62 * d
    );
    let opts = RenderOptions::new(1, 1);
    let film = render(&build(&text), &opts, &Progress::default()).film;
    film.mean().iter().map(|p| p[0]).collect()
}

fn check(file: &str, key: &str) {
    let twin = std::fs::read_to_string(fixtures().join(format!("{file}.to_world"))).unwrap();
    let twin = twin.trim();
    let original = format!("{{ {key} = \"{file}\" }}");
    let vol = format!("{{ vol = \"{file}.vol\" }}");
    let scene = build(&format!("[[media]]\ndensity = {original}\n"));
    let b = scene.world.media[0].medium.world_bounds();
    let (c, e) = ((b.min + b.max) * 0.5, (b.max - b.min).max_element());
    // Optical depth of order one across the box.
    let scale = 2.0 / e;
    let a = image(&original, "{}", c.into(), e, scale);
    let t = image(&vol, twin, c.into(), e, scale);
    let max_diff = a
        .iter()
        .zip(&t)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max);
    let min_t = a.iter().copied().fold(1.0, f32::min);
    let covered = a.iter().filter(|&&v| v < 0.999).count();
    assert!(
        min_t < 0.7,
        "{file}: the medium barely shows (min T {min_t})"
    );
    assert!(
        covered > a.len() / 10 && covered < a.len() * 9 / 10,
        "{file}: {covered} px covered"
    );
    assert!(
        max_diff < 2e-4,
        "{file}: max |ΔT| {max_diff} between the file and its twin"
    );

    // Power: the twin one voxel off (a tenth of the box) is caught.
    let off = {
        let inner = twin.trim_start_matches('{').trim_end_matches('}');
        let (tr, rest) = inner.split_once("],").unwrap();
        let nums: Vec<f32> = tr
            .split_once('[')
            .unwrap()
            .1
            .split(',')
            .map(|s| s.trim().parse().unwrap())
            .collect();
        format!(
            "{{ translate = [{}, {}, {}],{rest} }}",
            nums[0] + 0.1 * e,
            nums[1],
            nums[2]
        )
    };
    let moved = image(&vol, &off, c.into(), e, scale);
    let moved_diff = a
        .iter()
        .zip(&moved)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max);
    assert!(
        moved_diff > 0.05,
        "{file}: a shifted twin differs by only {moved_diff}"
    );
}

#[test]
fn nifti_renders_where_its_vol_twin_with_equivalent_to_world_renders() {
    check("oblique_i16.nii.gz", "nifti");
}

#[test]
fn nrrd_renders_where_its_vol_twin_with_equivalent_to_world_renders() {
    check("lps_gzip.nrrd", "nrrd");
}
