//! Any text must convert to a scene document or to an error — no panic,
//! abort, stack overflow or outsized allocation — and a converted document
//! must deserialise (or be refused) as a scene description. Files it names
//! resolve in an empty folder; device files are skipped so that the target
//! never reads unbounded input.
#![no_main]

use fogbank_render::SceneDesc;
use fogbank_scene::mitsuba::load_xml_str;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if ["/dev", "/proc", "/sys"].iter().any(|d| text.contains(d)) {
        return;
    }
    let dir = std::env::temp_dir().join("fogbank-fuzz-xml-empty");
    let _ = std::fs::create_dir_all(&dir);
    if let Ok(doc) = load_xml_str(text, &dir.join("fuzz.xml"), &[]) {
        let _ = toml::Value::Table(doc).try_into::<SceneDesc>();
    }
});
