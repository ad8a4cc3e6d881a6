//! The guide's file-format table (docs/guide/formats.md) and the volume
//! formats' registry (`fogbank_volume::formats`) agree: every
//! registered format has a row naming it, and that row says it is written
//! exactly when the format has a writer.

use fogbank_volume::formats::{self, VolumeFormat};
use std::path::Path;

/// The rows of the guide's "File formats" table: (format cell, written cell).
fn table_rows(guide: &str) -> Vec<(String, String)> {
    let start = guide
        .find("## File formats")
        .expect("a File formats section");
    (guide[start..].lines())
        .skip_while(|l| !l.starts_with("| format |"))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            let cells: Vec<&str> = l.trim_matches('|').split(" | ").map(str::trim).collect();
            (
                cells[0].to_string(),
                cells.last().copied().unwrap_or("").to_string(),
            )
        })
        .collect()
}

/// What is wrong between `rows` and `formats`, one line each.
fn disagreements(rows: &[(String, String)], formats: &[&VolumeFormat]) -> Vec<String> {
    let mut wrong = Vec::new();
    for f in formats {
        let row = rows.iter().find(|(cell, _)| cell.contains(f.name));
        match row {
            None => wrong.push(format!(
                "`{}` ({}): no row in the guide's table",
                f.key, f.name
            )),
            Some((cell, written)) => {
                let says_written = written != "—";
                if says_written != f.write.is_some() {
                    wrong.push(format!(
                        "`{}`: the row `{cell}` says written = {says_written}, the registry {}",
                        f.key,
                        f.write.is_some()
                    ));
                }
            }
        }
    }
    wrong
}

#[test]
fn the_guide_names_every_volume_format_and_what_is_written() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/guide/formats.md");
    let guide = std::fs::read_to_string(path).unwrap();
    let rows = table_rows(&guide);
    let wrong = disagreements(&rows, formats::all());
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    // The check catches a drifted table: a writable format marked unwritten,
    // and a missing row.
    let vdb = formats::by_key("vdb").unwrap();
    let drifted: Vec<(String, String)> = rows
        .iter()
        .map(|(c, w)| {
            (
                c.clone(),
                if c.contains(vdb.name) {
                    "—".into()
                } else {
                    w.clone()
                },
            )
        })
        .collect();
    assert_eq!(disagreements(&drifted, &[vdb]).len(), 1);
    assert_eq!(disagreements(&[], &[vdb]).len(), 1);
}
