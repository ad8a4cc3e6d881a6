//! Every scene of `scenes/` (TOML and Mitsuba XML, in every subfolder but
//! the fragments of `include/` folders) renders through the `fogbank`
//! command at 8×6 and 1 spp, as a user would try them on a plain clone. A scene that reads the MNI templates
//! (`data/mni/`, fetched by `tools/fetch_data.sh mni`) is skipped with a
//! message when they are missing, unless `FOGBANK_REQUIRE_DATA=1`; every
//! other file a scene reads must be in the repository.

use crate::support;

use fogbank::testing::testdata::mni_data;
use std::path::{Path, PathBuf};
use support::{fogbank, tmp_dir};

fn scene_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        // Mitsuba scenes' `include/` folders hold fragments, not scenes.
        if p.is_dir() && p.file_name().is_some_and(|n| n == "include") {
            continue;
        }
        if p.is_dir() {
            scene_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "toml" || e == "xml") {
            out.push(p);
        }
    }
}

/// The MNI templates `text` names as files (`…data/mni/NAME"`; a mention
/// of the folder in a comment names none).
fn mni_files(text: &str) -> Vec<&str> {
    let file_name = |n: &&str| {
        !n.is_empty()
            && n.chars()
                .all(|c| c.is_ascii_alphanumeric() || "._-".contains(c))
    };
    text.split("data/mni/")
        .skip(1)
        .filter_map(|rest| rest.split('"').next())
        .filter(file_name)
        .collect()
}

#[test]
fn every_scene_renders_at_a_tiny_size() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut scenes = Vec::new();
    scene_files(&root, &mut scenes);
    assert!(scenes.len() >= 20, "only {} scenes found", scenes.len());
    let out = tmp_dir("scenes_test");
    let mut failures = Vec::new();
    let mut rendered = 0;
    for (i, scene) in scenes.iter().enumerate() {
        let text = std::fs::read_to_string(scene).unwrap();
        if mni_files(&text).iter().any(|f| mni_data(f).is_none()) {
            continue;
        }
        let exr = out.join(format!("{i}.exr"));
        let result = fogbank()
            .args(["render", "--quiet", "--spp", "1"])
            .args(["--set", "camera.width=8", "--set", "camera.height=6"])
            .arg(scene)
            .arg("-o")
            .arg(&exr)
            .output()
            .unwrap();
        if !result.status.success() || !exr.is_file() {
            failures.push(format!(
                "{}: {}",
                scene.display(),
                String::from_utf8_lossy(&result.stderr).trim()
            ));
        }
        rendered += 1;
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    eprintln!("{rendered} of {} scenes rendered", scenes.len());
}
