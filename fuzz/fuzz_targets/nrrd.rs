//! Any byte string must decode to a NRRD volume or to an error — with the
//! data attached, and with the same bytes as a detached data file: no panic,
//! abort or outsized allocation.
#![no_main]

use std::path::Path;

use fogbank_volume::loaders::{nrrd, scalar};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let check = |v: scalar::ScalarVolume| {
        let _ = v.range();
        let _ = v.histogram(16);
        let _ = v.normalised_grid();
    };
    if let Ok(v) = nrrd::parse(Path::new("fuzz.nrrd"), data, None, 0) {
        check(v);
    }
    if let Ok(v) = nrrd::parse(Path::new("fuzz.nhdr"), data, Some(data), 1) {
        check(v);
    }
});
