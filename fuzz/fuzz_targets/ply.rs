//! Any byte string must parse to a mesh or to an error — no panic, abort or
//! outsized allocation — and a parsed mesh must build its BVH.
#![no_main]

use fogbank_geometry::loaders::ply::parse_ply;
use fogbank_geometry::MeshAccel;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(m) = parse_ply(data, "fuzz.ply") {
        let _ = MeshAccel::new(m);
    }
});
