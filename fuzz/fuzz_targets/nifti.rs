//! Any byte string must decode to a NIfTI-1/2 volume or to an error — as a
//! single file, as a `.hdr` with the same bytes as its `.img`, and gzipped
//! input through the bounded gunzip: no panic, abort or outsized allocation.
#![no_main]

use std::path::Path;

use fogbank_volume::loaders::{nifti, scalar};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = Path::new("fuzz.nii");
    let check = |v: scalar::ScalarVolume| {
        let _ = v.range();
        let _ = v.histogram(16);
        let _ = v.normalised_grid();
    };
    if let Ok(v) = nifti::parse(path, data, None, 0) {
        check(v);
    }
    if let Ok(v) = nifti::parse(Path::new("fuzz.hdr"), data, Some(data), 1) {
        check(v);
    }
    if let Ok(bytes) = scalar::decompress_if_gzip(path, data.to_vec(), 1 << 20) {
        if let Ok(v) = nifti::parse(path, &bytes, None, 0) {
            check(v);
        }
    }
});
