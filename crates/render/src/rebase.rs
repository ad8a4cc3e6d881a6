//! A scene written to another folder: relative file names resolve against
//! the scene file's folder (`Scene::build`'s base), so a scene saved
//! elsewhere — the viewer's "save scene" — would lose its volumes, maps and
//! transfer functions unless their names are rewritten.

use std::path::{Path, PathBuf};

/// Keys whose string values name files beside the volume formats' (a
/// field's source, `fogbank_volume::formats`): ParaView colour maps, every
/// `file` (environment maps, meshes, velocity and transfer files) and bitmap
/// textures' `filename`.
const OTHER_FILE_KEYS: [&str; 3] = ["paraview", "file", "filename"];

/// Whether the string value of key `k` names a file: a volume format's key
/// (`vdb`, `nrrd`, …; also the velocity's `vdb`/`nvdb`) or one of
/// [`OTHER_FILE_KEYS`].
pub fn is_file_key(k: &str) -> bool {
    fogbank_volume::formats::by_key(k).is_some() || OTHER_FILE_KEYS.contains(&k)
}

/// Rewrites the relative file names of `scene` (resolved against `from`)
/// so they name the same files from `to`: unchanged when the two folders
/// are one, else absolute (canonical where the file exists; per-frame
/// patterns such as `plume_{frame:04}.vdb` stay patterns).
pub fn rebase_paths(scene: &mut toml::Value, from: &Path, to: &Path) {
    if same_folder(from, to) {
        return;
    }
    rebase(scene, from);
}

fn same_folder(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

fn rebase(v: &mut toml::Value, from: &Path) {
    match v {
        toml::Value::Table(t) => {
            for (k, x) in t.iter_mut() {
                match x {
                    toml::Value::String(s) if is_file_key(k) => {
                        if Path::new(s.as_str()).is_relative() {
                            *s = absolute(&from.join(s.as_str())).display().to_string();
                        }
                    }
                    _ => rebase(x, from),
                }
            }
        }
        toml::Value::Array(a) => a.iter_mut().for_each(|x| rebase(x, from)),
        _ => {}
    }
}

fn absolute(p: &Path) -> PathBuf {
    p.canonicalize()
        .or_else(|_| std::path::absolute(p))
        .unwrap_or_else(|_| p.to_path_buf())
}

#[cfg(test)]
mod rebase_test {
    use super::*;

    fn scene() -> toml::Value {
        toml::from_str(
            "[[media]]\ndensity = { vdb = \"smoke/plume_{frame:04}.vdb\", grid = \"density\" }\n\
             albedo = { vol = \"/data/albedo.vol\" }\n\
             [[lights]]\ntype = \"envmap\"\nfile = \"probes/sky.hdr\"\n\
             [camera]\nfov_axis = \"x\"\n",
        )
        .unwrap()
    }

    #[test]
    fn relative_names_become_absolute_in_another_folder() {
        let mut s = scene();
        rebase_paths(
            &mut s,
            Path::new("/nowhere/scenes"),
            Path::new("/elsewhere"),
        );
        let m = &s["media"][0];
        assert_eq!(
            m["density"]["vdb"].as_str(),
            Some("/nowhere/scenes/smoke/plume_{frame:04}.vdb")
        );
        assert_eq!(m["density"]["grid"].as_str(), Some("density"));
        assert_eq!(m["albedo"]["vol"].as_str(), Some("/data/albedo.vol"));
        assert_eq!(
            s["lights"][0]["file"].as_str(),
            Some("/nowhere/scenes/probes/sky.hdr")
        );
        assert_eq!(s["camera"]["fov_axis"].as_str(), Some("x"));
    }

    #[test]
    fn the_same_folder_keeps_relative_names() {
        let mut s = scene();
        rebase_paths(
            &mut s,
            Path::new("/nowhere/scenes"),
            Path::new("/nowhere/scenes"),
        );
        assert_eq!(s, scene());
    }
}
