//! The Blosc frame decoder on its own: the first two bytes give the size the
//! caller expects, the rest is the frame.
#![no_main]

use fogbank_volume::loaders::vdb::blosc;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if data.len() < 2 {
        return;
    }
    let expected = u16::from_le_bytes([data[0], data[1]]) as usize;
    if let Ok(out) = blosc::decompress(&data[2..], expected) {
        assert_eq!(out.len(), expected);
    }
});
