//! Any text must parse to a mesh or to an error naming a line — no panic
//! or abort — and a parsed mesh must build its BVH.
#![no_main]

use fogbank_geometry::loaders::obj::parse_obj;
use fogbank_geometry::MeshAccel;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(m) = parse_obj(text, "fuzz.obj") {
            let _ = MeshAccel::new(m);
        }
    }
});
