//! Which part of a render one shard does (`--shard I/N`): a disjoint block
//! of sample indices for every pixel (the default), or every N-th tile of
//! 32×32 pixels for all samples. A render is a function of (scene, seed,
//! pixel, sample index) and films sum exactly, so the parts' films added
//! together are the single run's film bit for bit (`fogbank merge`).

use serde::{Deserialize, Serialize};
use std::ops::Range;

/// Edge of a tile in pixels (tile shards).
pub const TILE: u32 = 32;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShardMode {
    /// Shard i of n renders sample indices ⌊i·spp/n⌋ .. ⌊(i+1)·spp/n⌋.
    Samples,
    /// Shard i of n renders the tiles t with t mod n = i (interleaved, so
    /// each shard gets a fair share of the image's hard parts).
    Tiles,
}

impl ShardMode {
    pub fn parse(s: &str) -> Result<ShardMode, String> {
        match s {
            "samples" => Ok(ShardMode::Samples),
            "tiles" => Ok(ShardMode::Tiles),
            _ => Err(format!("shard mode `{s}` is not samples or tiles")),
        }
    }
}

/// Shard `index` of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    pub index: u32,
    pub count: u32,
    pub mode: ShardMode,
}

impl Shard {
    /// Parses `I/N` (0 ≤ I < N).
    pub fn parse(s: &str, mode: ShardMode) -> Result<Shard, String> {
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| format!("--shard `{s}`: expected I/N, e.g. 0/4"))?;
        let parse = |v: &str| {
            v.trim()
                .parse::<u32>()
                .map_err(|_| format!("--shard `{s}`: `{v}` is not a whole number"))
        };
        let (index, count) = (parse(i)?, parse(n)?);
        if count == 0 || index >= count {
            return Err(format!(
                "--shard `{s}`: need 0 ≤ I < N (shards are numbered from 0)"
            ));
        }
        Ok(Shard { index, count, mode })
    }

    /// The part of a `width`×`height`, `spp` render this shard does.
    pub fn piece(&self, spp: u32) -> Piece {
        match self.mode {
            ShardMode::Samples => {
                let at = |i: u32| (i as u64 * spp as u64 / self.count as u64) as u32;
                Piece {
                    samples: [at(self.index), at(self.index + 1)],
                    tiles: None,
                }
            }
            ShardMode::Tiles => Piece {
                samples: [0, spp],
                tiles: Some([self.index, self.count]),
            },
        }
    }

    pub fn label(&self) -> String {
        format!("{}/{}", self.index, self.count)
    }
}

/// A block of the work: sample indices `samples[0]..samples[1]` of the
/// tiles `t mod tiles[1] = tiles[0]` (all pixels when `tiles` is None).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Piece {
    pub samples: [u32; 2],
    pub tiles: Option<[u32; 2]>,
}

impl Piece {
    /// The whole render: every sample of every pixel.
    pub fn whole(spp: u32) -> Piece {
        Piece {
            samples: [0, spp],
            tiles: None,
        }
    }

    pub fn sample_range(&self) -> Range<u32> {
        self.samples[0]..self.samples[1]
    }

    /// Whether pixel (x, y) of an image `width` wide is in the piece.
    #[inline]
    pub fn has_pixel(&self, x: u32, y: u32, width: u32) -> bool {
        match self.tiles {
            None => true,
            Some([i, n]) => tile_of(x, y, width) % n == i,
        }
    }

    /// Pixel samples of a `width`×`height` image in the piece (a progress
    /// bar's length).
    pub fn pixel_samples(&self, width: u32, height: u32) -> u64 {
        let pixels = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .filter(|&(x, y)| self.has_pixel(x, y, width))
            .count() as u64;
        pixels * (self.samples[1] - self.samples[0]) as u64
    }

    /// Whether the piece is a piece of a render with `spp` samples per
    /// pixel: an ordered sample range within it, and a tile class `i` of
    /// `n > i` tile shards.
    pub fn is_valid(&self, spp: u32) -> bool {
        let [a, b] = self.samples;
        a <= b && b <= spp && self.tiles.is_none_or(|[i, n]| i < n)
    }

    /// Whether tile `t` is in the piece.
    pub fn has_tile(&self, t: u32) -> bool {
        self.tiles.is_none_or(|[i, n]| t % n == i)
    }

    pub fn describe(&self) -> String {
        let [a, b] = self.samples;
        match self.tiles {
            None => format!("samples {a}..{b}"),
            Some([i, n]) => format!("samples {a}..{b} of tiles ≡ {i} mod {n}"),
        }
    }
}

/// Tiles across an image `width` wide.
pub fn tiles_across(width: u32) -> u32 {
    width.div_ceil(TILE)
}

/// Row-major index of the tile holding pixel (x, y).
#[inline]
pub fn tile_of(x: u32, y: u32, width: u32) -> u32 {
    (y / TILE) * tiles_across(width) + x / TILE
}

#[cfg(test)]
mod shard_test {
    use super::*;

    #[test]
    fn sample_shards_partition_the_samples() {
        for (spp, n) in [(64, 4), (100, 3), (5, 8), (1, 1)] {
            let mut next = 0;
            for i in 0..n {
                let p = Shard::parse(&format!("{i}/{n}"), ShardMode::Samples)
                    .unwrap()
                    .piece(spp);
                assert_eq!(p.samples[0], next);
                next = p.samples[1];
            }
            assert_eq!(next, spp);
        }
    }

    #[test]
    fn tile_shards_partition_the_pixels() {
        let (w, h, n) = (70, 40, 3);
        for y in 0..h {
            for x in 0..w {
                let owners = (0..n)
                    .filter(|&i| {
                        Shard::parse(&format!("{i}/{n}"), ShardMode::Tiles)
                            .unwrap()
                            .piece(8)
                            .has_pixel(x, y, w)
                    })
                    .count();
                assert_eq!(owners, 1);
            }
        }
    }

    #[test]
    fn bad_shard_specs_are_refused() {
        for s in ["4/4", "1", "a/2", "0/0", "-1/3"] {
            assert!(Shard::parse(s, ShardMode::Samples).is_err(), "{s}");
        }
    }
}
