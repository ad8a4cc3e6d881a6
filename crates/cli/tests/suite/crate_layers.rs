//! The workspace's crates are one-way layers: this reads every crate's
//! `Cargo.toml` (and the Python package's) and fails when a crate depends
//! on one of its own layer or above, and when a front end (the command, the
//! viewer, Python) reaches an inner crate: front ends go through `fogbank`
//! alone, besides their own UI crates (the viewer for the command, the
//! papers' experiments for the command and Python), which the list below
//! names.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Each crate's layer: a crate may depend only on crates of lower layers.
const LAYERS: &[(&str, u32)] = &[
    ("fogbank-math", 0),
    ("fogbank-image", 0),
    ("fogbank-geometry", 1),
    ("fogbank-volume", 1),
    ("fogbank-estimators", 2),
    ("fogbank-render", 3),
    ("fogbank-scene", 4),
    ("fogbank-partial", 4),
    ("fogbank-gpu", 5),
    ("fogbank-eval", 6),
    ("fogbank", 7),
    ("fogbank-viewer", 8),
    ("fogbank-experiments", 8),
    ("fogbank-cli", 9),
    ("fogbank-python", 9),
];

/// The front ends, and the crates each may depend on besides `fogbank`:
/// its own UI crates.
const FRONT_ENDS: &[(&str, &[&str])] = &[
    (
        "fogbank-cli",
        // `fogbank view` and `fogbank experiment`.
        &["fogbank-viewer", "fogbank-experiments"],
    ),
    ("fogbank-viewer", &[]),
    // `fogbank.experiment`.
    ("fogbank-python", &["fogbank-experiments"]),
];

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Every workspace crate's name and its `fogbank*` dependencies (normal
/// and dev: a test may not reach above its crate either, or cargo would
/// build the crate twice).
fn manifests(root: &Path) -> BTreeMap<String, Vec<String>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root.join("crates"))
        .unwrap()
        .map(|e| e.unwrap().path().join("Cargo.toml"))
        .filter(|p| p.exists())
        .collect();
    let python = root.join("python/Cargo.toml");
    if python.exists() {
        files.push(python);
    }
    let mut out = BTreeMap::new();
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        let doc: toml::Table =
            toml::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let name = doc["package"]["name"].as_str().unwrap().to_string();
        let mut deps = Vec::new();
        for section in ["dependencies", "dev-dependencies"] {
            if let Some(t) = doc.get(section).and_then(|v| v.as_table()) {
                deps.extend(t.keys().filter(|k| k.starts_with("fogbank")).cloned());
            }
        }
        out.insert(name, deps);
    }
    out
}

fn layer(name: &str) -> Option<u32> {
    LAYERS.iter().find(|(n, _)| *n == name).map(|(_, l)| *l)
}

/// What is wrong with the workspace's dependencies, one line each.
fn violations(crates: &BTreeMap<String, Vec<String>>) -> Vec<String> {
    let mut bad = Vec::new();
    for (name, deps) in crates {
        let Some(own) = layer(name) else {
            bad.push(format!("{name} has no layer in LAYERS"));
            continue;
        };
        for d in deps {
            match layer(d) {
                Some(l) if l < own => {}
                Some(l) => bad.push(format!("{name} (layer {own}) depends on {d} (layer {l})")),
                None => bad.push(format!("{name} depends on {d}, which has no layer")),
            }
        }
        if let Some((_, allowed)) = FRONT_ENDS.iter().find(|(n, _)| n == name) {
            for d in deps.iter().filter(|d| *d != "fogbank") {
                if !allowed.contains(&d.as_str()) {
                    bad.push(format!(
                        "front end {name} depends on inner crate {d}: go through `fogbank`"
                    ));
                }
            }
            for a in *allowed {
                if !deps.iter().any(|d| d == a) {
                    bad.push(format!(
                        "{name} no longer depends on {a}: strike it from FRONT_ENDS"
                    ));
                }
            }
        }
    }
    bad
}

#[test]
fn crates_depend_only_on_lower_layers_and_front_ends_on_fogbank() {
    let bad = violations(&manifests(&repo()));
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn the_checker_finds_a_layer_broken_and_a_front_end_reaching_in() {
    let mut crates = manifests(&repo());
    crates
        .get_mut("fogbank-render")
        .unwrap()
        .push("fogbank-gpu".into());
    crates
        .get_mut("fogbank-cli")
        .unwrap()
        .push("fogbank-scene".into());
    let bad = violations(&crates);
    assert!(
        bad.iter()
            .any(|b| b.contains("fogbank-render (layer 3) depends on fogbank-gpu")),
        "{bad:?}"
    );
    assert!(
        bad.iter()
            .any(|b| b.contains("front end fogbank-cli depends on inner crate fogbank-scene")),
        "{bad:?}"
    );
}
