//! Malformed OpenVDB input (float and vec3 grids) must produce errors: never
//! a panic, and never an allocation out of proportion to the input. Truncates and corrupts the
//! fixtures deterministically; a counting allocator records the largest
//! single allocation the reader makes.

use crate::support;

use std::path::{Path, PathBuf};
use support::{largest, panic_message, Rng};

use fogbank_volume::loaders::vdb;

/// No single allocation may exceed this (the largest legitimate one is a
/// 32³ node's value buffer, 384 KiB for vec3 grids, or the leaf list of a
/// fixture).
const ALLOC_LIMIT: usize = 8 << 20;

fn fixture(name: &str) -> (PathBuf, Vec<u8>) {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/vdb")
        .join(name);
    let bytes = std::fs::read(&p).unwrap();
    (p, bytes)
}

/// Lists the grids and parses the default float and vec3 grids; returns a
/// description of a panic, if any.
fn try_parse(path: &Path, bytes: &[u8]) -> Option<String> {
    panic_message(|| {
        let _ = vdb::list_grids_from_bytes(path, bytes);
        let stats = |g: &vdb::VdbGrid| {
            let _ = (
                g.active_voxel_count(),
                g.active_bbox(),
                g.active_value_sum(),
            );
        };
        if let Ok(g) = vdb::parse_grid(path, bytes, None) {
            stats(&g);
        }
        if let Ok(v) = vdb::parse_vec3_grid(path, bytes, None) {
            v.iter().for_each(stats);
        }
    })
}

const FILES: [&str; 12] = [
    "tiles_f32_zip.vdb",
    "stream_tiles.vdb",
    "multi.vdb",
    "fog_half_blosc.vdb",
    "fog_f32_zip.vdb",
    "fog_half_zip.vdb",
    "fog_f32_active.vdb",
    "affine_half_blosc.vdb",
    "vec3_half_zip.vdb",
    "vec3_f32_blosc.vdb",
    "vec3_instance.vdb",
    "vec3_stream.vdb",
];

/// Whether the file's default grid is a vec3s one (no float grid in it).
fn vec3_only(name: &str) -> bool {
    name.starts_with("vec3_") && name != "vec3_stream.vdb"
}

#[test]
fn truncated_files_give_errors() {
    support::in_own_process(|| {
        let mut failures = Vec::new();
        for name in FILES {
            let (path, bytes) = fixture(name);
            // Every cut in the header and descriptor area, then ~400 spread cuts.
            let step = (bytes.len() / 400).max(1);
            let cuts = (0..bytes.len().min(600)).chain((600..bytes.len()).step_by(step));
            for cut in cuts {
                let data = &bytes[..cut];
                if let Some(msg) = try_parse(&path, data) {
                    failures.push(format!("{name} cut at {cut}: panic {msg}"));
                    continue;
                }
                // The whole grid is needed: any truncation is an error.
                let parsed = if vec3_only(name) {
                    vdb::parse_vec3_grid(&path, data, None).is_ok()
                } else {
                    vdb::parse_grid(&path, data, None).is_ok()
                };
                assert!(!parsed, "{name} cut at {cut} parsed");
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
        let largest = largest();
        assert!(largest <= ALLOC_LIMIT, "largest allocation {largest} bytes");
    });
}

#[test]
fn corrupted_bytes_never_panic() {
    support::in_own_process(|| {
        let mut failures = Vec::new();
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        for name in FILES {
            let (path, bytes) = fixture(name);
            for round in 0..500 {
                let mut data = bytes.clone();
                // Header bytes are where sizes and counts live: bias towards them.
                let span = if round % 2 == 0 {
                    data.len().min(2048)
                } else {
                    data.len()
                };
                let flips = 1 + (rng.next() % 4) as usize;
                for _ in 0..flips {
                    let at = (rng.next() as usize) % span;
                    data[at] ^= match rng.next() % 4 {
                        0 => 0xFF,
                        1 => 0x80,
                        2 => 1 << (rng.next() % 8),
                        _ => rng.next() as u8 | 1,
                    };
                }
                if let Some(msg) = try_parse(&path, &data) {
                    failures.push(format!("{name} round {round}: panic {msg}"));
                }
            }
            // Every byte of the first KiB set to 0xFF, one at a time.
            for at in 0..bytes.len().min(1024) {
                let mut data = bytes.clone();
                data[at] = 0xFF;
                if let Some(msg) = try_parse(&path, &data) {
                    failures.push(format!("{name} byte {at} = 0xFF: panic {msg}"));
                }
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
        let largest = largest();
        assert!(largest <= ALLOC_LIMIT, "largest allocation {largest} bytes");
    });
}

#[test]
fn corrupted_compressed_chunks_never_panic() {
    // Change bytes inside the leaf buffer area of compressed files: the
    // Blosc and Zip decoders see corrupt streams here, not the tree parser.
    let mut rng = Rng(12345);
    for name in [
        "fog_half_blosc.vdb",
        "fog_f32_zip.vdb",
        "vec3_half_blosc.vdb",
        "vec3_f32_zip.vdb",
    ] {
        let (path, bytes) = fixture(name);
        let start = bytes.len() / 2;
        for _ in 0..300 {
            let mut data = bytes.clone();
            let at = start + (rng.next() as usize) % (bytes.len() - start);
            data[at] = data[at].wrapping_add(1 + (rng.next() % 255) as u8);
            assert!(try_parse(&path, &data).is_none(), "{name} byte {at}");
        }
    }
}
