//! Any byte string must parse to a Mitsuba grid or to an error, and a parsed
//! grid must convert to a brick grid: no panic, abort or outsized allocation.
#![no_main]

use std::path::Path;

use fogbank_volume::loaders::vol;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(v) = vol::parse_vol(Path::new("fuzz.vol"), data) {
        for c in 0..v.channels {
            let _ = v.channel_grid(c);
        }
        let _ = v.index_to_world();
    }
});
