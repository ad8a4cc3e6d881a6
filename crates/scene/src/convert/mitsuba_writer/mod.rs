//! A fogbank scene written as a Mitsuba 3 XML scene: the inverse of the
//! reader in [`crate::mitsuba`], for what Mitsuba can express. Reading the
//! written file back with fogbank's reader gives the same scene up to float
//! rounding of the camera frame and the grids' placement (and the media's
//! bounding cubes, which are invisible), so it renders the same image in
//! expectation.
//!
//! | fogbank | Mitsuba |
//! |---|---|
//! | `[camera]` | `perspective` with `fov`, `fov_axis`, a `lookat` `to_world` (a `mirror`ed camera: `scale x=-1` first), `near_clip` (0 becomes 10⁻⁴: Mitsuba needs a positive one, noted), `far_clip` (none becomes 10⁷) |
//! | `[render]` | `hdrfilm` width/height with a box `rfilter`; `independent` sampler with `sample_count` = spp and `seed` |
//! | `[integrator]` volpath | `volpath`, `max_depth` + 1 (fogbank counts scattering vertices, Mitsuba segments), `rr_depth` |
//! | `[[media]]` | `heterogeneous` over a `gridvolume` (`.vol`) inside a null `cube`, see `media` |
//! | `[[lights]]` | `constant`, `envmap`, `point`, `directional`, `spot`, see `emitters` |
//! | `[[shapes]]` | the same shape types, BSDFs and textures, `area` emitters, see `shapes` |
//!
//! Refused, with an error naming the key: integrators other than volpath
//! (Mitsuba has none of fogbank's others), emitting media, transfer
//! functions, albedo grids, RGB densities other than a 3-channel `.vol`,
//! per-channel scales of a non-constant medium, medium instances, non-HG
//! phase functions. Changed or dropped with a note in
//! [`Converted::notes`]: a zero near clip, `pixel_jitter = false`, the
//! exposure and tone curve, the light sampler, an `[animation]` (frame 0
//! is written), medium velocity and importance rules, a nearest-neighbour
//! grid filter or environment lookup, the gradient sky (baked into an
//! environment map), a smoothstep spot falloff, procedural fields
//! (voxelised) and overlapping media (fogbank adds them, Mitsuba has one
//! medium per region).

mod emitters;
mod media;
mod notes;
mod sensor;
mod shapes;
mod xml;

pub use notes::{medium_id, Notes};

use super::output::{write_file, Converted};
use super::scene_toml::{folder_of, scene_toml};
use fogbank_math::Vec3;
use fogbank_render::error::SceneError;
use fogbank_render::scene::{parse_scene, SceneDesc};
use std::path::Path;
use xml::El;

/// Converts the scene `input` (any format fogbank reads) to the Mitsuba
/// XML file `output`; grids go beside it as `STEM_mediumI.vol`.
pub fn convert(input: &Path, output: &Path) -> Result<Converted, SceneError> {
    let dir = folder_of(output);
    // File names relative to the output's folder, as Mitsuba resolves them.
    let (text, _) = scene_toml(input, output)?;
    let desc = parse_scene(&text, &input.display().to_string(), &[])?;
    let stem = output
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("scene")
        .to_string();
    let mut notes = Notes::default();
    let root = scene_xml(&desc, dir, &stem, &mut notes)?;
    let mut xml = String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
    xml.push_str(&format!(
        "<!-- Converted by `fogbank convert` from {} -->\n",
        input.display().to_string().replace("--", "- -")
    ));
    root.write(&mut xml, 0);
    write_file(output, xml.as_bytes())?;
    Ok(Converted {
        summary: format!(
            "{}: {} media, {} lights, {} shapes ({} notes)",
            output.display(),
            desc.media.len(),
            desc.lights.len(),
            desc.shapes.len(),
            notes.0.len()
        ),
        notes: notes.0,
    })
}

/// Notes media whose boxes may overlap: fogbank adds overlapping media,
/// Mitsuba has one medium in each region (that of the last cube entered).
fn overlaps(media: &[media::Medium], notes: &mut Notes) {
    let boxes: Vec<_> = media.iter().map(media::Medium::world_box).collect();
    for i in 0..boxes.len() {
        for j in i + 1..boxes.len() {
            let (a, b) = (boxes[i], boxes[j]);
            if a.min.cmplt(b.max).all() && b.min.cmplt(a.max).all() {
                notes.note(format!(
                    "media {i} and {j} may overlap: fogbank adds their densities where they do, \
                     Mitsuba has one medium in each region (the image differs there)"
                ));
            }
        }
    }
}

/// The `<scene>` element of `desc`, whose files resolve against `dir`
/// (where the XML goes); grids are written there as `STEM_mediumI.vol`.
pub fn scene_xml(
    desc: &SceneDesc,
    dir: &Path,
    stem: &str,
    notes: &mut Notes,
) -> Result<El, SceneError> {
    let mut root = El::new("scene").attr("version", "3.0.0");
    root.push(sensor::integrator(desc, notes)?);
    let mut media = Vec::new();
    for (i, m) in desc.media.iter().enumerate() {
        let name = format!("{stem}_medium{i}.vol");
        let target = media::VolTarget {
            path: dir.join(&name),
            name,
        };
        media.push(media::medium(m, i, dir, &target, notes)?);
    }
    overlaps(&media, notes);
    let from = Vec3::from(desc.camera.from);
    let around: Vec<usize> = (0..media.len())
        .filter(|&i| media[i].contains(from))
        .collect();
    if around.len() > 1 {
        notes.note(format!(
            "the camera is inside media {around:?}: Mitsuba's sensor sits in one, medium {} written",
            around[0]
        ));
    }
    let sensor_medium = around.first().map(|&i| medium_id(i));
    root.push(sensor::sensor(desc, sensor_medium.as_deref(), notes)?);
    for m in &media {
        root.push(m.element.clone());
    }
    for (i, l) in desc.lights.iter().enumerate() {
        root.push(emitters::emitter(l, i, (dir, stem), notes)?);
    }
    for e in shapes::shapes(&desc.shapes)? {
        root.push(e);
    }
    for (i, m) in media.into_iter().enumerate() {
        if !desc.shapes.iter().any(|s| s.interior == Some(i)) {
            root.push(m.cube);
        }
    }
    Ok(root)
}
