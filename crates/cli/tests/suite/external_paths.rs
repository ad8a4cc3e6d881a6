//! No code, test or scene names `../shared/data` (or a path into it) but
//! `fogbank_math::sample_data`, the one place that looks outside the
//! repository. Scenes name committed data (`../data/…`); code and tests ask
//! `sample_data` / `testdata`, which skip or explain when a file is
//! missing. This static check covers what `tools/test_plain_clone.sh` (the
//! suite from a clone with nothing beside it) leaves out: the GPU tests.

use std::path::{Path, PathBuf};

fn files(dir: &Path, exts: &[&str], out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            if p.file_name().is_some_and(|n| n != "target") {
                files(&p, exts, out);
            }
        } else if p
            .extension()
            .and_then(|x| x.to_str())
            .is_some_and(|x| exts.contains(&x))
        {
            out.push(p);
        }
    }
}

/// Whether `line` is a comment in a Rust, TOML or XML file.
fn is_comment(line: &str) -> bool {
    let t = line.trim_start();
    t.starts_with("//") || t.starts_with('#') || t.starts_with("<!--")
}

#[test]
fn only_sample_data_names_the_shared_folder() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut checked = Vec::new();
    files(&root.join("crates"), &["rs"], &mut checked);
    files(&root.join("scenes"), &["toml", "xml"], &mut checked);
    let allowed = [
        Path::new("crates/math/src/sample_data.rs"),
        Path::new("crates/cli/tests/suite/external_paths.rs"),
    ];
    let mut found = Vec::new();
    for p in &checked {
        let rel = p.strip_prefix(&root).unwrap();
        if allowed.contains(&rel) {
            continue;
        }
        let text = std::fs::read_to_string(p).unwrap();
        for (i, line) in text.lines().enumerate() {
            if line.contains("shared/data") && !is_comment(line) {
                found.push(format!("{}:{}: {}", rel.display(), i + 1, line.trim()));
            }
        }
    }
    assert!(checked.len() > 100, "only {} files checked", checked.len());
    assert!(
        found.is_empty(),
        "paths into ../shared/data outside fogbank_math::sample_data (use \
         sample_data::committed/external or testdata::external_data):\n{}",
        found.join("\n")
    );
}
