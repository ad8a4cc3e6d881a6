//! Any text must convert to a scene document or to an error — no panic,
//! abort, stack overflow or outsized allocation — and a converted document
//! must deserialise (or be refused) as a scene description. Files it names
//! resolve in an empty folder; device files are skipped so that the target
//! never reads unbounded input. The reader caches inline meshes (and
//! resampled environment maps) as files in the temporary folder: the
//! target points that at a folder of its own and empties it after each
//! input, so that the run neither fills the disk nor touches the caches
//! of other programs.
#![no_main]

use fogbank_render::SceneDesc;
use fogbank_scene::pbrt::load_pbrt_str;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if ["/dev", "/proc", "/sys"].iter().any(|d| text.contains(d)) {
        return;
    }
    static TMP: std::sync::Once = std::sync::Once::new();
    TMP.call_once(|| {
        let tmp = std::env::temp_dir().join("fogbank-fuzz-pbrt-tmp");
        let _ = std::fs::create_dir_all(&tmp);
        std::env::set_var("TMPDIR", tmp);
    });
    let dir = std::env::temp_dir().join("fogbank-fuzz-pbrt-empty");
    let _ = std::fs::create_dir_all(&dir);
    if let Ok(doc) = load_pbrt_str(text, &dir.join("fuzz.pbrt")) {
        let _ = toml::Value::Table(doc).try_into::<SceneDesc>();
    }
    for cache in ["fogbank-pbrt-meshes", "fogbank-pbrt-envmaps"] {
        let _ = std::fs::remove_dir_all(std::env::temp_dir().join(cache));
    }
});
