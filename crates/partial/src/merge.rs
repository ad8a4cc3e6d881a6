//! Adding up the partial results of a sharded render (`fogbank merge`):
//! checks that the parts belong to one render and cover its work exactly
//! once, then adds their exact sums — so the result is the single-process
//! film bit for bit, and merging merged parts gives the same film again.

use crate::partial::{Partial, PartialHeader, ShardRun};
use fogbank_render::shard::{tiles_across, TILE};

/// A merged partial and what it lacks (empty unless `allow_partial`).
pub struct Merged {
    pub partial: Partial,
    /// The missing work, one line each (shards when the parts tell which).
    pub missing: Vec<String>,
}

/// Merges `parts` (named for messages). Refuses parts of different scenes,
/// seeds, sizes, spp or kinds, duplicate or overlapping shards, and — unless
/// `allow_partial` — missing work, listing what is missing.
pub fn merge(parts: &[(String, Partial)], allow_partial: bool) -> Result<Merged, String> {
    let Some((first_name, first)) = parts.first() else {
        return Err("no partial files to merge".into());
    };
    let id = &first.header.identity;
    for (name, p) in &parts[1..] {
        let o = &p.header.identity;
        let differs = |what: &str, a: String, b: String| {
            Err(format!(
                "{name}: {what} {b} differs from {first_name}'s {a}: the parts are not of one render"
            ))
        };
        if o.kind != id.kind {
            return differs("kind", id.kind.clone(), o.kind.clone());
        }
        if o.scene_hash != id.scene_hash {
            return differs("scene (hash)", id.scene_hash.clone(), o.scene_hash.clone());
        }
        if o.seed != id.seed {
            return differs("seed", id.seed.to_string(), o.seed.to_string());
        }
        if (o.width, o.height) != (id.width, id.height) {
            return differs(
                "resolution",
                format!("{}×{}", id.width, id.height),
                format!("{}×{}", o.width, o.height),
            );
        }
        if o.frame != id.frame {
            let name = |f: Option<u32>| f.map_or("none".to_string(), |f| f.to_string());
            return differs("frame", name(id.frame), name(o.frame));
        }
        if o.spp != id.spp {
            return differs("total spp", id.spp.to_string(), o.spp.to_string());
        }
    }
    let runs: Vec<(&str, &ShardRun)> = parts
        .iter()
        .flat_map(|(n, p)| p.header.runs.iter().map(move |r| (n.as_str(), r)))
        .collect();
    let missing = coverage(&runs, id.width, id.height, id.spp)?;
    if !missing.is_empty() && !allow_partial {
        return Err(format!(
            "missing work (merge with --allow-partial to accept it):\n  {}",
            missing.join("\n  ")
        ));
    }
    // The reader bounds every part's sample counts by its shards, and the
    // shards do not overlap, so only the lookup counts can overflow.
    if parts
        .iter()
        .try_fold(0u64, |sum, (_, p)| sum.checked_add(p.film.lookups))
        .is_none()
    {
        return Err("the parts' lookup counts add up beyond 2⁶⁴: a part is damaged".into());
    }
    let mut film = first.film.clone();
    let mut covered = first.covered.clone();
    for (_, p) in &parts[1..] {
        film.merge(&p.film);
        if let (Some(c), Some(o)) = (covered.as_mut(), p.covered.as_ref()) {
            for (a, b) in c.iter_mut().zip(o) {
                *a |= *b;
            }
        }
    }
    let mut all_runs: Vec<ShardRun> = runs.iter().map(|(_, r)| (*r).clone()).collect();
    all_runs.sort_by_key(|r| (r.piece.samples, r.piece.tiles));
    let header = PartialHeader {
        runs: all_runs,
        lookups: film.lookups,
        nan_samples: film.nan_samples,
        inf_samples: film.inf_samples,
        ..first.header.clone()
    };
    Ok(Merged {
        partial: Partial {
            header,
            film,
            covered,
        },
        missing,
    })
}

/// Checks that no sample of any tile is done twice and lists what is not
/// done at all.
fn coverage(
    runs: &[(&str, &ShardRun)],
    width: u32,
    height: u32,
    spp: u32,
) -> Result<Vec<String>, String> {
    for (name, r) in runs {
        if !r.piece.is_valid(spp) {
            return Err(format!(
                "{name}: shard {} holds an invalid piece ({})",
                r.shard.label(),
                r.piece.describe()
            ));
        }
    }
    let tiles = tiles_across(width) * height.div_ceil(TILE);
    // Which pieces hold a tile depends only on the tile's index modulo each
    // tile shard count n, so tiles congruent modulo the lcm of the n's (or
    // all tiles, when that is larger) stand for the rest: a sample-range
    // sharding checks one tile, N tile shards N tiles.
    let period = runs
        .iter()
        .filter_map(|(_, r)| r.piece.tiles.map(|[_, n]| n as u64))
        .fold(1u64, |l, n| (l / gcd(l, n) * n).min(tiles as u64)) as u32;
    let mut gaps: Vec<(u32, [u32; 2])> = Vec::new();
    for t in 0..period.min(tiles) {
        gaps.extend(tile_gaps(runs, t, spp)?.into_iter().map(|g| (t, g)));
    }
    if gaps.is_empty() {
        return Ok(Vec::new());
    }
    Ok(missing(runs, &gaps, tiles, period, spp))
}

/// The sample ranges of tile `t` that no run holds; an error when two
/// runs hold the same sample.
fn tile_gaps(runs: &[(&str, &ShardRun)], t: u32, spp: u32) -> Result<Vec<[u32; 2]>, String> {
    let mut gaps = Vec::new();
    let mut here: Vec<&(&str, &ShardRun)> = runs
        .iter()
        .filter(|(_, r)| r.piece.has_tile(t) && r.piece.samples[0] < r.piece.samples[1])
        .collect();
    here.sort_by_key(|(_, r)| r.piece.samples);
    let mut next = 0;
    for w in 0..here.len() {
        let (name, r) = here[w];
        let [a, b] = r.piece.samples;
        if a < next {
            let (prev_name, prev) = here[w - 1];
            return Err(if prev.piece == r.piece {
                format!(
                    "duplicate shard {} ({}): {prev_name} and {name}",
                    r.shard.label(),
                    r.piece.describe()
                )
            } else {
                format!(
                    "{name} (shard {}, {}) overlaps {prev_name} (shard {}, {}) in tile {t}",
                    r.shard.label(),
                    r.piece.describe(),
                    prev.shard.label(),
                    prev.piece.describe()
                )
            });
        }
        if a > next {
            gaps.push([next, a]);
        }
        next = next.max(b);
    }
    if next < spp {
        gaps.push([next, spp]);
    }
    Ok(gaps)
}

/// What is missing, in words: the missing shards when every part comes
/// from one N and mode, else the gaps grouped by sample range.
fn missing(
    runs: &[(&str, &ShardRun)],
    gaps: &[(u32, [u32; 2])],
    tiles: u32,
    period: u32,
    spp: u32,
) -> Vec<String> {
    let (n, mode) = (runs[0].1.shard.count, runs[0].1.shard.mode);
    if runs
        .iter()
        .all(|(_, r)| r.shard.count == n && r.shard.mode == mode)
    {
        return (0..n)
            .filter(|&i| !runs.iter().any(|(_, r)| r.shard.index == i))
            .map(|i| {
                let s = fogbank_render::shard::Shard {
                    index: i,
                    count: n,
                    mode,
                };
                format!("shard {} ({})", s.label(), s.piece(spp).describe())
            })
            .collect();
    }
    // Otherwise the gaps, grouped by sample range.
    let mut by_range: Vec<([u32; 2], u32)> = Vec::new();
    for (t, g) in gaps {
        // Tile t stands for every tile congruent to it modulo the period.
        let k = (tiles - t).div_ceil(period);
        match by_range.iter_mut().find(|(r, _)| r == g) {
            Some(e) => e.1 += k,
            None => by_range.push((*g, k)),
        }
    }
    by_range
        .into_iter()
        .map(|([a, b], k)| format!("samples {a}..{b} of {k} of the {tiles} tiles"))
        .collect()
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}
