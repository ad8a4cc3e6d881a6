//! Malformed NanoVDB input must produce clear errors (naming the file and
//! what is wrong): never a panic, and never an allocation out of
//! proportion to the input. Works from the committed fixtures, and from
//! an uncompressed file and a raw grid buffer made from them by inflating
//! the ZIP fixture's grid.

use crate::support;

use std::io::Read;
use std::path::{Path, PathBuf};
use support::{largest, panic_message, Rng};

use fogbank_volume::loaders::nanovdb;

/// No single allocation may exceed this: the largest legitimate one is a
/// fixture's decoded grid buffer (at most 820 KiB) or its leaf list.
const ALLOC_LIMIT: usize = 8 << 20;

fn fixture(name: &str) -> (PathBuf, Vec<u8>) {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/nanovdb")
        .join(name);
    let bytes = std::fs::read(&p).unwrap();
    (p, bytes)
}

const FILES: [&str; 5] = [
    "fog_zip.nvdb",
    "fog_blosc.nvdb",
    "fog_fp8_zip.nvdb",
    "vec3_zip.nvdb",
    "density_vel_zip.nvdb",
];

/// Segment header (16 B) plus the first grid's metadata (176 B) and name.
fn first_grid_start(bytes: &[u8]) -> usize {
    let name_size = u32::from_le_bytes(bytes[16 + 136..16 + 140].try_into().unwrap());
    16 + 176 + name_size as usize
}

/// `fog_zip.nvdb` with its grid stored uncompressed (codec 0), and the raw
/// grid buffer alone.
fn uncompressed_fog() -> (Vec<u8>, Vec<u8>) {
    let (_, zip) = fixture("fog_zip.nvdb");
    let start = first_grid_start(&zip);
    let mut grid = Vec::new();
    flate2::read::ZlibDecoder::new(&zip[start + 8..])
        .read_to_end(&mut grid)
        .unwrap();
    let mut file = zip[..start].to_vec();
    file[14..16].copy_from_slice(&0u16.to_le_bytes());
    file[16 + 8..16 + 16].copy_from_slice(&(grid.len() as u64).to_le_bytes());
    file[16 + 168..16 + 170].copy_from_slice(&0u16.to_le_bytes());
    file.extend_from_slice(&grid);
    (file, grid)
}

/// Lists the grids and reads the default float and vector grids; returns
/// a description of a panic, if any.
fn try_parse(path: &Path, bytes: &[u8]) -> Option<String> {
    panic_message(|| {
        let _ = nanovdb::list_grids_from_bytes(path, bytes);
        if let Ok(g) = nanovdb::read_grid_from_bytes(path, bytes, None) {
            let _ = (
                g.active_voxel_count(),
                g.active_bbox(),
                g.active_value_sum(),
            );
        }
        let _ = nanovdb::read_vec3_grid_from_bytes(path, bytes, None);
    })
}

fn read_err(bytes: &[u8]) -> String {
    nanovdb::read_grid_from_bytes(Path::new("x.nvdb"), bytes, None)
        .unwrap_err()
        .to_string()
}

#[test]
fn uncompressed_file_and_raw_grid_buffer_read_like_the_zip_file() {
    let (path, zip) = fixture("fog_zip.nvdb");
    let expected = nanovdb::read_grid_from_bytes(&path, &zip, None).unwrap();
    let (file, grid) = uncompressed_fog();
    let from_file = nanovdb::read_grid_from_bytes(&path, &file, None).unwrap();
    assert_eq!(from_file.leaves, expected.leaves);
    assert_eq!(from_file.compression, "none");
    // A raw buffer (32.6+): "NanoVDB0" grid magic of older writers, and
    // "NanoVDB1"; several grids one after another.
    let raw = nanovdb::read_grid_from_bytes(&path, &grid, None).unwrap();
    assert_eq!(raw.leaves, expected.leaves);
    let mut grid1 = grid.clone();
    grid1[7] = b'1';
    grid1.extend_from_slice(&grid);
    let listed = nanovdb::list_grids_from_bytes(&path, &grid1).unwrap();
    assert_eq!(listed.len(), 2);
    assert_eq!(
        nanovdb::read_grid_from_bytes(&path, &grid1, None)
            .unwrap()
            .leaves,
        expected.leaves
    );
}

#[test]
fn several_segments_are_one_file() {
    let (path, a) = fixture("fog_zip.nvdb");
    let (_, b) = fixture("density_vel_zip.nvdb");
    let both = [a, b].concat();
    let names: Vec<String> = nanovdb::list_grids_from_bytes(&path, &both)
        .unwrap()
        .into_iter()
        .map(|d| d.name)
        .collect();
    assert_eq!(names, ["density", "curl", "density", "vel"]);
    let vel = nanovdb::read_vec3_grid_from_bytes(&path, &both, None).unwrap();
    assert_eq!(vel[0].name, "vel.x");
}

#[test]
fn bad_magic_byte_order_and_version_are_named() {
    let (_, zip) = fixture("fog_zip.nvdb");
    let mut bad = zip.clone();
    bad[0] = b'X';
    let e = read_err(&bad);
    assert!(
        e.contains("x.nvdb") && e.contains("not a NanoVDB file"),
        "{e}"
    );
    let mut swapped = zip.clone();
    swapped[..8].reverse();
    assert!(read_err(&swapped).contains("byte order"));
    let mut old = zip.clone();
    old[8..12].copy_from_slice(&(31u32 << 21 | 9 << 10).to_le_bytes());
    let e = read_err(&old);
    assert!(
        e.contains("31.9.0") && e.contains("major version 32"),
        "{e}"
    );
    let (mut file, _) = uncompressed_fog();
    let grid_version = first_grid_start(&file) + 16;
    file[grid_version..grid_version + 4].copy_from_slice(&(33u32 << 21).to_le_bytes());
    let e = read_err(&file);
    assert!(e.contains("33.0.0") && e.contains("offset"), "{e}");
    assert!(read_err(&zip[..10]).contains("too short"));
}

#[test]
fn corrupted_streams_are_errors() {
    let (_, zip) = fixture("fog_zip.nvdb");
    let start = first_grid_start(&zip) + 8;
    let mut bad = zip.clone();
    for b in &mut bad[start + 100..start + 140] {
        *b ^= 0x5a;
    }
    let e = read_err(&bad);
    assert!(e.contains("ZIP") && e.contains("density"), "{e}");
    let (_, blosc) = fixture("fog_blosc.nvdb");
    let frame = first_grid_start(&blosc) + 8;
    let mut bad = blosc.clone();
    // The frame's uncompressed size.
    bad[frame + 4] ^= 0x01;
    let e = read_err(&bad);
    assert!(e.contains("BLOSC"), "{e}");
    // A stream that would inflate past what the metadata declares is
    // cut there; one declaring far more than it can hold is refused
    // before anything is allocated.
    let mut huge = zip.clone();
    huge[16..24].copy_from_slice(&(1u64 << 40).to_le_bytes());
    let e = read_err(&huge);
    assert!(e.contains("cannot hold"), "{e}");
}

#[test]
fn changed_head_bytes_fail_the_checksum() {
    let (mut file, _) = uncompressed_fog();
    // The root's background value (root right after GridData and TreeData).
    let background = first_grid_start(&file) + 672 + 64 + 28;
    file[background] ^= 0x01;
    let e = read_err(&file);
    assert!(
        e.contains("checksum mismatch") && e.contains("density"),
        "{e}"
    );
}

#[test]
fn truncated_files_give_errors() {
    support::in_own_process(|| {
        let (file, grid) = uncompressed_fog();
        let mut inputs: Vec<(String, Vec<u8>)> = FILES
            .iter()
            .map(|f| (f.to_string(), fixture(f).1))
            .collect();
        inputs.push(("uncompressed".into(), file));
        inputs.push(("raw grid".into(), grid));
        for (name, bytes) in inputs {
            let path = PathBuf::from(&name);
            let step = (bytes.len() / 150).max(1);
            for cut in (0..bytes.len()).step_by(step) {
                let part = &bytes[..cut];
                if let Some(p) = try_parse(&path, part) {
                    panic!("{name} cut at {cut}: panic {p}");
                }
                let read = nanovdb::read_grid_from_bytes(&path, part, None);
                let vec3 = nanovdb::read_vec3_grid_from_bytes(&path, part, None);
                assert!(
                    read.is_err() && vec3.is_err(),
                    "{name} cut at {cut} was read"
                );
            }
        }
        assert!(largest() < ALLOC_LIMIT, "largest allocation {}", largest());
    });
}

#[test]
fn corrupted_bytes_never_panic() {
    support::in_own_process(|| {
        let (file, grid) = uncompressed_fog();
        let mut inputs: Vec<Vec<u8>> = FILES.iter().map(|f| fixture(f).1).collect();
        inputs.push(file);
        inputs.push(grid);
        let mut rng = Rng(0x6e76_6462);
        for bytes in inputs {
            for _ in 0..300 {
                let mut b = bytes.clone();
                for _ in 0..1 + rng.next() % 8 {
                    // Mostly the headers and the tree's upper levels, where
                    // offsets and counts live.
                    let span = if rng.next().is_multiple_of(2) {
                        4096
                    } else {
                        b.len()
                    };
                    let at = (rng.next() as usize) % span.min(b.len());
                    b[at] = rng.next() as u8;
                }
                if let Some(p) = try_parse(Path::new("corrupt.nvdb"), &b) {
                    panic!("panic on corrupted input: {p}");
                }
            }
        }
        assert!(largest() < ALLOC_LIMIT, "largest allocation {}", largest());
    });
}

/// The reader streams a BLOSC frame block by block, so the frame's block
/// offsets must increase as c-blosc writes them, and nothing may follow the
/// last chunk: both are errors naming the codec.
#[test]
fn streamed_blosc_frames_are_checked() {
    let (_, blosc) = fixture("fog_blosc.nvdb");
    let frame = first_grid_start(&blosc) + 8;
    // Block 0 said to start inside the frame's own header.
    let mut behind = blosc.clone();
    behind[frame + 16..frame + 20].copy_from_slice(&8u32.to_le_bytes());
    let e = read_err(&behind);
    assert!(
        e.contains("BLOSC") && e.contains("block 0 starts at byte 8"),
        "{e}"
    );

    // Five stored bytes more than the chunks hold.
    let mut longer = blosc.clone();
    let stored = u64::from_le_bytes(longer[16 + 8..16 + 16].try_into().unwrap());
    longer[16 + 8..16 + 16].copy_from_slice(&(stored + 5).to_le_bytes());
    longer.extend_from_slice(&[0; 5]);
    let e = read_err(&longer);
    assert!(e.contains("after the last BLOSC chunk"), "{e}");
}
