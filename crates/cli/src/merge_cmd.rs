//! `fogbank merge`: adds up the partial results of a sharded `render` or
//! `stats` (`--shard I/N`) into the image (or statistics) of the single run,
//! bit for bit; refuses parts of different renders and duplicate,
//! overlapping or missing shards (unless `--allow-partial`).

use crate::common::CliResult;
use clap::Args;
use fogbank::image::{ToneCurve, ToneMapping};
use fogbank::merge::merge;
use fogbank::merged::{merged_frame_stats, merged_render_stats};
use fogbank::partial::Partial;
use std::path::PathBuf;

#[derive(Args)]
pub struct MergeArgs {
    /// Partial results (`.fbpart`) of one render's shards, in any order;
    /// merged partials merge again.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// Output, repeatable: `.exr` (mean and variance), `.png` (tone-mapped
    /// as the scene says) or `.fbpart` (a merged partial). For `stats`
    /// parts: a folder, written as `fogbank stats --out` writes it.
    #[arg(short, long, required = true)]
    pub output: Vec<PathBuf>,
    /// Write the merged render's statistics as JSON (render parts).
    #[arg(long)]
    pub stats: Option<PathBuf>,
    /// Merge even when shards are missing (the image then holds fewer
    /// samples; the missing work is listed on stderr and in --stats).
    #[arg(long)]
    pub allow_partial: bool,
}

pub fn run(a: MergeArgs) -> CliResult {
    let parts = a
        .parts
        .iter()
        .map(|p| Partial::read(p).map(|r| (p.display().to_string(), r)))
        .collect::<Result<Vec<_>, _>>()?;
    let merged = merge(&parts, a.allow_partial)?;
    for m in &merged.missing {
        eprintln!("warning: missing {m}");
    }
    let p = &merged.partial;
    let h = &p.header;
    if h.identity.kind == "stats" {
        return write_stats(&a, p, &merged.missing);
    }
    let mut images = Vec::new();
    for out in &a.output {
        match out.extension().and_then(|e| e.to_str()) {
            Some("fbpart") => p.write(out)?,
            Some("exr") | Some("png") => images.push(out.clone()),
            _ => {
                return Err(format!(
                    "{}: output must end in .exr, .png or .fbpart",
                    out.display()
                )
                .into())
            }
        }
    }
    let tone = ToneMapping {
        exposure: h.exposure,
        curve: ToneCurve::parse(&h.tonemap)
            .map_err(|e| format!("{}: tonemap: {e}", a.parts[0].display()))?,
    };
    let bad_pixels = fogbank::output::write_images(&images, &p.film, &tone)?;
    let film = &p.film;
    eprintln!(
        "merged {} part(s), {} shard(s): {}×{}, {} spp{}; wrote {}",
        parts.len(),
        h.runs.len(),
        film.width,
        film.height,
        film.min_spp(),
        if merged.missing.is_empty() {
            ""
        } else {
            " (work missing)"
        },
        a.output
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    if let Some(path) = &a.stats {
        crate::common::write_json(path, &merged_render_stats(&merged, bad_pixels))?;
    }
    Ok(())
}

/// Merged `stats` parts: the statistics files of `fogbank stats`.
fn write_stats(a: &MergeArgs, p: &Partial, missing: &[String]) -> CliResult {
    let [out] = &a.output[..] else {
        return Err("stats parts merge into one output folder (-o DIR)".into());
    };
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let (st, json) = merged_frame_stats(p, missing);
    crate::stats_cmd::write_outputs(&st, &p.header.estimator, out, &json)
}
