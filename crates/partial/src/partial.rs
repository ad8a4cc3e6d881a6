//! Partial results of sharded renders (`.fbpart`): what `fogbank render
//! --shard I/N` and `fogbank stats --shard I/N` write and `fogbank merge`
//! adds up.
//!
//! Format, version 1 (all integers little-endian):
//!
//! | bytes | content |
//! |---|---|
//! | 8 | magic `FBPART\r\n` |
//! | 4 | version (1) |
//! | 4 | header length H (≤ 1 MiB) |
//! | H | header: UTF-8 JSON, [`PartialHeader`] |
//! | … | one record per pixel, row-major: sample count (u32); when nonzero, Σx then Σx² for R, G, B as 256-bit two's-complement fixed point with 128 fraction bits (6 × 32 bytes, [`ExactSum`]) |
//! | ⌈W·H/8⌉ | stats partials only: the covered-pixel mask, bit i of byte i/8 |
//! | 8 | FNV-1a 64 of every byte before it |
//!
//! Writers write `NAME.tmp` and rename it on success, so a shard killed
//! mid-run leaves no file that `merge` would accept.

use fogbank_math::ExactSum;
use fogbank_render::shard::{tile_of, tiles_across, Piece, Shard, TILE};
use fogbank_render::world::film::{Film, PixelSums};
use serde::{Deserialize, Serialize};
use std::path::Path;

const MAGIC: &[u8; 8] = b"FBPART\r\n";
const VERSION: u32 = 1;
const MAX_HEADER: usize = 1 << 20;
/// Pixels a partial may hold (a 16k × 16k image).
const MAX_PIXELS: u64 = 1 << 28;
const SUMS_BYTES: usize = 6 * 32;
/// Shard records a partial may hold.
const MAX_RUNS: usize = 1 << 16;

/// What a partial is part of: these must agree between parts that merge.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Identity {
    /// `render` or `stats`.
    pub kind: String,
    /// FNV-1a 64 of the scene description without spp and seed
    /// ([`scene_hash`]), hex.
    pub scene_hash: String,
    pub seed: u32,
    pub width: u32,
    pub height: u32,
    /// The whole render's samples per pixel (stats: frames).
    pub spp: u32,
    /// The frame of an animated scene's sequence (`--frames`), whose parts
    /// share the scene description.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame: Option<u32>,
}

/// Where and how long one shard ran.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShardRun {
    pub shard: Shard,
    pub piece: Piece,
    pub seconds: f64,
    pub threads: usize,
    pub host: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartialHeader {
    pub identity: Identity,
    /// The pieces of work the file holds (one per shard merged into it).
    pub runs: Vec<ShardRun>,
    pub integrator: String,
    pub estimator: String,
    /// PNG settings of the scene, so `merge -o x.png` tone-maps as `render`.
    pub exposure: f32,
    pub tonemap: String,
    pub lookups: u64,
    pub nan_samples: u64,
    pub inf_samples: u64,
}

impl PartialHeader {
    /// The header of one shard's partial result (`kind`: render or stats)
    /// of `scene` rendered with `seed` and `spp` samples per pixel in all.
    pub fn for_shard(
        kind: &str,
        scene: &fogbank_render::scene::Scene,
        seed: u32,
        spp: u32,
        film: &Film,
        run: ShardRun,
    ) -> PartialHeader {
        let render = &scene.desc.render;
        PartialHeader {
            identity: Identity {
                kind: kind.into(),
                scene_hash: scene_hash(&scene.desc),
                seed,
                width: film.width,
                height: film.height,
                spp,
                frame: None,
            },
            runs: vec![run],
            integrator: scene.integrator.name().into(),
            estimator: scene.integrator.estimator_name().into(),
            exposure: render.exposure,
            tonemap: render.tonemap.name().into(),
            lookups: film.lookups,
            nan_samples: film.nan_samples,
            inf_samples: film.inf_samples,
        }
    }
}

/// A partial result: its header, its film and (stats) the covered pixels.
#[derive(Clone, Debug)]
pub struct Partial {
    pub header: PartialHeader,
    pub film: Film,
    pub covered: Option<Vec<bool>>,
}

/// FNV-1a 64 (a stable, dependency-free content hash; not cryptographic).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The scene's identity for merging: its description as canonical TOML
/// with spp and seed (checked separately) and the PNG settings (which do not
/// change the sums) cleared. Paths are hashed as written, not the files'
/// contents.
pub fn scene_hash(desc: &fogbank_render::scene::SceneDesc) -> String {
    let mut d = desc.clone();
    d.render.spp = 0;
    d.render.seed = 0;
    d.render.exposure = 0.0;
    d.render.tonemap = Default::default();
    let text = toml::to_string(&d).unwrap_or_default();
    format!("{:016x}", fnv1a(text.as_bytes()))
}

impl Partial {
    /// The file's bytes (see the module's table).
    pub fn to_bytes(&self) -> Vec<u8> {
        let header = serde_json::to_vec(&self.header).expect("a header serialises");
        let f = &self.film;
        let mut b = Vec::with_capacity(16 + header.len() + f.count.len() * 8);
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&VERSION.to_le_bytes());
        b.extend_from_slice(&(header.len() as u32).to_le_bytes());
        b.extend_from_slice(&header);
        for (n, s) in f.count.iter().zip(&f.sums) {
            b.extend_from_slice(&n.to_le_bytes());
            if *n > 0 {
                for v in s.sum.iter().chain(&s.sum_sq) {
                    b.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
        if let Some(c) = &self.covered {
            let mut mask = vec![0u8; c.len().div_ceil(8)];
            for (i, _) in c.iter().enumerate().filter(|(_, &v)| v) {
                mask[i / 8] |= 1 << (i % 8);
            }
            b.extend_from_slice(&mask);
        }
        let h = fnv1a(&b);
        b.extend_from_slice(&h.to_le_bytes());
        b
    }

    /// Writes `path` through `path.tmp` and a rename.
    pub fn write(&self, path: &Path) -> Result<(), String> {
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".tmp");
        let tmp = std::path::PathBuf::from(tmp);
        std::fs::write(&tmp, self.to_bytes()).map_err(|e| format!("{}: {e}", tmp.display()))?;
        std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))
    }

    pub fn read(path: &Path) -> Result<Partial, String> {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Partial::from_bytes(&bytes).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Parses a partial, validating every size before allocating.
    pub fn from_bytes(b: &[u8]) -> Result<Partial, String> {
        let mut r = Reader { b, at: 0 };
        if r.take(8, "magic")? != MAGIC {
            return Err("not a fogbank partial (bad magic at byte 0)".into());
        }
        let version = r.u32("version")?;
        if version != VERSION {
            return Err(format!(
                "partial format version {version} (byte 8); this fogbank reads version {VERSION}"
            ));
        }
        // The checksum first: a truncated or damaged file fails here with
        // one clear message instead of somewhere in the records.
        if b.len() < 24 {
            return Err(format!("truncated: {} bytes", b.len()));
        }
        let (body, sum) = b.split_at(b.len() - 8);
        if fnv1a(body).to_le_bytes() != sum {
            return Err(format!(
                "checksum mismatch (file truncated or damaged; {} bytes)",
                b.len()
            ));
        }
        let len = r.u32("header length")? as usize;
        if len > MAX_HEADER {
            return Err(format!(
                "header length {len} at byte 12 exceeds {MAX_HEADER}"
            ));
        }
        let header: PartialHeader = serde_json::from_slice(r.take(len, "header")?)
            .map_err(|e| format!("header at byte 16: {e}"))?;
        if header.runs.is_empty() || header.runs.len() > MAX_RUNS {
            return Err(format!(
                "header: {} shard records (1 to {MAX_RUNS})",
                header.runs.len()
            ));
        }
        let id = &header.identity;
        let pixels = id.width as u64 * id.height as u64;
        if id.width == 0 || id.height == 0 || pixels > MAX_PIXELS {
            return Err(format!(
                "header: image {}×{} is empty or over {MAX_PIXELS} pixels",
                id.width, id.height
            ));
        }
        // Every record takes at least 4 bytes: bound the allocation by the file.
        if pixels * 4 > body.len() as u64 {
            return Err(format!(
                "{pixels} pixels cannot fit in {} bytes",
                body.len()
            ));
        }
        let mut film = read_sums(&mut r, id.width, id.height)?;
        check_counts(&header, &film)?;
        film.lookups = header.lookups;
        film.nan_samples = header.nan_samples;
        film.inf_samples = header.inf_samples;
        let covered = if id.kind == "stats" {
            let mask = r.take((pixels as usize).div_ceil(8), "covered mask")?;
            Some(
                (0..pixels as usize)
                    .map(|i| mask[i / 8] >> (i % 8) & 1 == 1)
                    .collect(),
            )
        } else {
            None
        };
        if r.at != body.len() {
            return Err(format!(
                "{} unexpected bytes after the records at byte {}",
                body.len() - r.at,
                r.at
            ));
        }
        Ok(Partial {
            header,
            film,
            covered,
        })
    }
}

/// Checks the counts against the shards that made them: a pixel holds at
/// most the samples its shards take of it, and the dropped (non-finite)
/// samples are at most those not held. So parts whose shards do not overlap
/// (what `merge` requires) add up to at most `spp` samples per pixel, and
/// no count can overflow.
fn check_counts(header: &PartialHeader, film: &Film) -> Result<(), String> {
    let id = &header.identity;
    if let Some(r) = header.runs.iter().find(|r| !r.piece.is_valid(id.spp)) {
        return Err(format!(
            "header: shard {} holds an invalid piece ({}) of {} spp",
            r.shard.label(),
            r.piece.describe(),
            id.spp
        ));
    }
    // Samples taken per tile: the runs are few, the tiles a thousandth of
    // the pixels.
    let tiles = tiles_across(id.width) * id.height.div_ceil(TILE);
    let taken: Vec<u64> = (0..tiles)
        .map(|t| {
            let runs = header.runs.iter().filter(|r| r.piece.has_tile(t));
            runs.map(|r| r.piece.sample_range().len() as u64).sum()
        })
        .collect();
    // Up to 2¹⁶ runs of 2³² samples over 2²⁸ pixels: beyond u64.
    let mut not_held = 0u128;
    for y in 0..id.height {
        for x in 0..id.width {
            let n = film.count[(y * id.width + x) as usize] as u64;
            let held = taken[tile_of(x, y, id.width) as usize];
            if n > held {
                return Err(format!(
                    "pixel ({x}, {y}) holds {n} samples but the shards take {held} of it"
                ));
            }
            not_held += (held - n) as u128;
        }
    }
    let dropped = header.nan_samples as u128 + header.inf_samples as u128;
    if dropped > not_held {
        return Err(format!(
            "header: {dropped} dropped samples, but only {not_held} of the shards' samples are not in the sums"
        ));
    }
    Ok(())
}

/// The per-pixel sample counts and exact sums of a `width` × `height`
/// film (a pixel without samples stores only its count).
fn read_sums(r: &mut Reader, width: u32, height: u32) -> Result<Film, String> {
    let mut film = Film::new(width, height);
    let pixels = width as usize * height as usize;
    for i in 0..pixels {
        let n = r.u32("sample count")?;
        film.count[i] = n;
        if n > 0 {
            let raw = r.take(SUMS_BYTES, "pixel sums")?;
            let v: [ExactSum; 6] = std::array::from_fn(|k| {
                ExactSum::from_le_bytes(raw[32 * k..32 * k + 32].try_into().unwrap())
            });
            film.sums[i] = PixelSums {
                sum: [v[0], v[1], v[2]],
                sum_sq: [v[3], v[4], v[5]],
            };
        }
    }
    Ok(film)
}

struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        // The trailing checksum is not record data.
        let end = self.b.len().saturating_sub(8);
        if self.at.checked_add(n).is_none_or(|e| e > end) {
            return Err(format!(
                "truncated: {what} at byte {} needs {n} bytes",
                self.at
            ));
        }
        let s = &self.b[self.at..self.at + n];
        self.at += n;
        Ok(s)
    }

    fn u32(&mut self, what: &str) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(4, what)?.try_into().unwrap()))
    }
}
