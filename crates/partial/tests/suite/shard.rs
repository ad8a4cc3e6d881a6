//! Sharded renders: the parts' films merged equal the single run bit for bit
//! (sample-range and tile shards, `transmittance` and `volpath`), merging is
//! associative, partial files round-trip, and every refusal of `merge` and
//! of the partial reader is a clear error.

use fogbank_partial::merge::merge;
use fogbank_partial::partial::{Partial, PartialHeader, ShardRun};
use fogbank_render::shard::{Shard, ShardMode};
use fogbank_render::{parse_scene, render, render_piece, Film, Progress, RenderOptions, Scene};
use std::path::Path;

const SCENE: &str = include_str!("../scenes/shard_cloud.toml");

const SPP: u32 = 10;

fn scene(integrator: &str, seed: u32) -> Scene {
    scene_with(integrator, seed, &[])
}

fn scene_with(integrator: &str, seed: u32, extra: &[&str]) -> Scene {
    let mut set = vec![
        format!("integrator.type={integrator}"),
        format!("render.seed={seed}"),
    ];
    set.extend(extra.iter().map(|s| s.to_string()));
    let desc = parse_scene(SCENE, "test", &set).unwrap();
    Scene::build(desc, Path::new(".")).unwrap()
}

fn opts(scene: &Scene) -> RenderOptions {
    RenderOptions::new(SPP, scene.desc.render.seed)
}

fn shard_partial(scene: &Scene, shard: Shard) -> Partial {
    let piece = shard.piece(SPP);
    let r = render_piece(scene, &opts(scene), &piece, &Progress::default());
    let run = ShardRun {
        shard,
        piece,
        seconds: r.seconds,
        threads: 1,
        host: "test".into(),
    };
    Partial {
        header: PartialHeader::for_shard(
            "render",
            scene,
            scene.desc.render.seed,
            SPP,
            &r.film,
            run,
        ),
        film: r.film,
        covered: None,
    }
}

fn shards(scene: &Scene, n: u32, mode: ShardMode) -> Vec<(String, Partial)> {
    (0..n)
        .map(|i| {
            let s = Shard {
                index: i,
                count: n,
                mode,
            };
            // Through the file format, as merge sees them.
            let p = Partial::from_bytes(&shard_partial(scene, s).to_bytes()).unwrap();
            (format!("part{i}.fbpart"), p)
        })
        .collect()
}

fn assert_same_film(a: &Film, b: &Film, what: &str) {
    assert_eq!(a.count, b.count, "{what}: counts");
    assert!(a.sums == b.sums, "{what}: sums differ");
    assert_eq!(a.lookups, b.lookups, "{what}: lookups");
    assert_eq!(a.mean(), b.mean(), "{what}: mean");
    assert_eq!(
        a.variance_of_mean(),
        b.variance_of_mean(),
        "{what}: variance"
    );
}

#[test]
fn merged_shards_equal_the_single_run_bit_for_bit() {
    // The pin stream changes the grids every pass: a sample-range shard
    // replays the streams before its first pass.
    let streamed: &[&str] = &[
        "integrator.pins=ms",
        "integrator.pin_grid.positions=4",
        "integrator.pin_grid.stream=50",
    ];
    let cases = [
        ("transmittance", &[][..]),
        ("volpath", &[][..]),
        ("volpath", streamed),
    ];
    for (integrator, extra) in cases {
        let s = scene_with(integrator, 5, extra);
        let integrator = format!("{integrator} {extra:?}");
        let single = render(&s, &opts(&s), &Progress::default()).film;
        assert!(single.image_mean()[0] > 0.0);
        for mode in [ShardMode::Samples, ShardMode::Tiles] {
            let parts = shards(&s, 4, mode);
            let merged = merge(&parts, false).unwrap();
            assert!(merged.missing.is_empty());
            assert_same_film(
                &merged.partial.film,
                &single,
                &format!("{integrator} {mode:?}"),
            );
            // Associative: (0+1) + (2+3) through files again.
            let left = merge(&parts[..2], true).unwrap().partial;
            let right = merge(&parts[2..], true).unwrap().partial;
            let again = merge(
                &[
                    (
                        "left".into(),
                        Partial::from_bytes(&left.to_bytes()).unwrap(),
                    ),
                    (
                        "right".into(),
                        Partial::from_bytes(&right.to_bytes()).unwrap(),
                    ),
                ],
                false,
            )
            .unwrap();
            assert_same_film(
                &again.partial.film,
                &single,
                &format!("{integrator} {mode:?} regrouped"),
            );
        }
    }
}

#[test]
fn merge_refuses_parts_of_different_renders() {
    let s = scene("transmittance", 5);
    let parts = shards(&s, 2, ShardMode::Samples);
    let other_seed = shards(&scene("transmittance", 6), 2, ShardMode::Samples);
    let other_scene = shards(&scene("volpath", 5), 2, ShardMode::Samples);
    let err = |p: Vec<(String, Partial)>| merge(&p, false).err().expect("must refuse");
    assert!(err(vec![parts[0].clone(), other_seed[1].clone()]).contains("seed 6 differs"));
    assert!(err(vec![parts[0].clone(), other_scene[1].clone()]).contains("scene (hash)"));
    let mut small = parts[1].clone();
    small.1.header.identity.width = 64;
    assert!(err(vec![parts[0].clone(), small]).contains("resolution 64×40"));
    let mut more = parts[1].clone();
    more.1.header.identity.spp = 12;
    assert!(err(vec![parts[0].clone(), more]).contains("total spp 12"));
    let mut stats = parts[1].clone();
    stats.1.header.identity.kind = "stats".into();
    assert!(err(vec![parts[0].clone(), stats]).contains("kind stats"));
    assert!(merge(&[], false).is_err());
}

#[test]
fn merge_refuses_duplicate_overlapping_and_missing_shards() {
    let s = scene("transmittance", 5);
    let parts = shards(&s, 4, ShardMode::Samples);
    let e = merge(
        &[parts[0].clone(), parts[1].clone(), parts[1].clone()],
        false,
    )
    .err()
    .unwrap();
    assert!(e.contains("duplicate shard 1/4"), "{e}");
    // Shard 0 of 2 (samples 0..5) overlaps shard 1 of 4 (samples 2..5).
    let halves = shards(&s, 2, ShardMode::Samples);
    let e = merge(&[halves[0].clone(), parts[1].clone()], false)
        .err()
        .unwrap();
    assert!(e.contains("overlaps"), "{e}");
    let e = merge(&[parts[0].clone(), parts[2].clone()], false)
        .err()
        .unwrap();
    assert!(
        e.contains("shard 1/4 (samples 2..5)") && e.contains("shard 3/4 (samples 7..10)"),
        "{e}"
    );
    // Allowed: the merge says what is missing and holds the rest (0..2, 5..7).
    let m = merge(&[parts[0].clone(), parts[2].clone()], true).unwrap();
    assert_eq!(m.missing.len(), 2);
    assert!(m.partial.film.count.iter().all(|&c| c == 4));
    // Mixed shardings that leave a gap name the samples and tiles.
    let tiles = shards(&s, 2, ShardMode::Tiles);
    let e = merge(&[tiles[0].clone(), parts[0].clone()], false)
        .err()
        .unwrap();
    assert!(e.contains("overlaps"), "{e}");
    let e = merge(&[tiles[0].clone()], false).err().unwrap();
    assert!(e.contains("shard 1/2"), "{e}");
}

#[test]
fn damaged_partials_are_clear_errors() {
    let s = scene("transmittance", 5);
    let bytes = shard_partial(
        &s,
        Shard {
            index: 0,
            count: 2,
            mode: ShardMode::Tiles,
        },
    )
    .to_bytes();
    assert!(Partial::from_bytes(&bytes).is_ok());
    let e = Partial::from_bytes(&bytes[..bytes.len() - 100])
        .err()
        .unwrap();
    assert!(e.contains("checksum"), "{e}");
    let mut flipped = bytes.clone();
    flipped[200] ^= 1;
    assert!(Partial::from_bytes(&flipped)
        .err()
        .unwrap()
        .contains("checksum"));
    assert!(Partial::from_bytes(b"P6\n")
        .err()
        .unwrap()
        .contains("truncated"));
    let mut magic = bytes.clone();
    magic[0] = b'X';
    assert!(Partial::from_bytes(&magic)
        .err()
        .unwrap()
        .contains("bad magic"));
    let mut version = bytes.clone();
    version[8] = 9;
    assert!(Partial::from_bytes(&version)
        .err()
        .unwrap()
        .contains("version 9"));
    // A consistent checksum over a header that claims a huge image.
    let mut p = Partial::from_bytes(&bytes).unwrap();
    p.header.identity.width = 1 << 20;
    p.header.identity.height = 1 << 20;
    let e = Partial::from_bytes(&p.to_bytes()).err().unwrap();
    assert!(e.contains("over"), "{e}");
}

/// Version 1 files stay readable: a tile shard written by `fogbank render
/// --shard 1/2 --shard-mode tiles` (40×36, 4 spp) when the format was made.
#[test]
fn the_committed_version_1_partial_still_reads() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/tiles_1_of_2.fbpart");
    let p = Partial::read(&path).unwrap();
    let id = &p.header.identity;
    assert_eq!(
        (id.kind.as_str(), id.width, id.height, id.spp),
        ("render", 40, 36, 4)
    );
    let run = &p.header.runs[0];
    assert_eq!(
        (run.shard.index, run.shard.count, run.shard.mode),
        (1, 2, ShardMode::Tiles)
    );
    for y in 0..36 {
        for x in 0..40 {
            // Tiles are 32 px: x ≥ 32 is tile 1 or 3, this shard's.
            let expect = if x >= 32 { 4 } else { 0 };
            assert_eq!(p.film.count[(y * 40 + x) as usize], expect, "({x}, {y})");
        }
    }
    assert!(p.film.image_mean()[0] > 0.0);
}

/// Found by the `fbpart` fuzz target: a partial whose one shard takes no
/// samples (`samples [0, 0]`) but whose pixels hold counts near 2³¹; two
/// such parts do not overlap, so `merge` added the counts and overflowed.
/// The reader now checks every count against the samples its shards take.
#[test]
fn counts_beyond_what_the_shards_take_are_refused() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/fuzz/fbpart_counts_without_samples.fbpart");
    // The fuzzer's input, sealed with its checksum as the target does.
    let mut bytes = std::fs::read(path).unwrap();
    bytes.extend_from_slice(&fogbank_partial::partial::fnv1a(&bytes).to_le_bytes());
    let e = Partial::from_bytes(&bytes).err().unwrap();
    assert!(e.contains("samples but the shards take 0"), "{e}");

    // A valid part, then more samples in one pixel than its shard takes,
    // and more dropped samples than its shard leaves out of the sums.
    let s = scene("transmittance", 5);
    let half = Shard {
        index: 0,
        count: 2,
        mode: ShardMode::Samples,
    };
    let p = Partial::from_bytes(&shard_partial(&s, half).to_bytes()).unwrap();
    let mut more = p.clone();
    more.film.count[3] += 1;
    let e = Partial::from_bytes(&more.to_bytes()).err().unwrap();
    assert!(e.contains(&format!("holds {} samples", SPP / 2 + 1)), "{e}");
    let mut dropped = p.clone();
    dropped.header.nan_samples = u64::MAX;
    let e = Partial::from_bytes(&dropped.to_bytes()).err().unwrap();
    assert!(e.contains("dropped samples"), "{e}");

    // Lookup counts have no such bound: merging refuses their overflow.
    let other =
        Partial::from_bytes(&shard_partial(&s, Shard { index: 1, ..half }).to_bytes()).unwrap();
    let mut parts = [("a".to_string(), p), ("b".to_string(), other)];
    assert!(merge(&parts, false).is_ok());
    for (_, part) in parts.iter_mut() {
        part.film.lookups = u64::MAX / 2 + 1;
    }
    let e = merge(&parts, false).err().unwrap();
    assert!(e.contains("lookup"), "{e}");
}
