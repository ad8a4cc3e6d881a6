//! The Kubernetes recipes of `deploy/kubernetes` validate against the
//! Kubernetes API schemas (strict: an unknown or misspelt field fails), and
//! the Indexed Job's shard count matches its completions. No cluster needed.
//!
//! The validator is `kubernetes-validate` (pip), found through
//! `FOGBANK_KUBE_VALIDATE` or PATH. Without it the test says so and passes
//! — unless `FOGBANK_REQUIRE_KUBE=1` (which CI's `.ci/run` sets after
//! installing it): then it fails.

use std::path::{Path, PathBuf};
use std::process::Command;

fn manifests() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../deploy/kubernetes");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .collect();
    v.sort();
    assert!(v.len() >= 2, "no manifests in {}", dir.display());
    v
}

#[test]
fn manifests_validate_against_the_kubernetes_schemas() {
    let validator =
        std::env::var("FOGBANK_KUBE_VALIDATE").unwrap_or_else(|_| "kubernetes-validate".into());
    // The oldest release with backoffLimitPerIndex in GA, and the newest the
    // validator knows.
    for version in ["1.33.0", ""] {
        let mut cmd = Command::new(&validator);
        cmd.arg("--strict");
        if !version.is_empty() {
            cmd.args(["-k", version]);
        }
        let out = match cmd.args(manifests()).output() {
            Ok(o) => o,
            Err(e) => {
                if std::env::var("FOGBANK_REQUIRE_KUBE").is_ok_and(|v| v == "1") {
                    panic!("FOGBANK_REQUIRE_KUBE=1 but `{validator}` cannot run: {e}");
                }
                eprintln!(
                    "skipped: `{validator}` cannot run ({e}); pip install kubernetes-validate"
                );
                return;
            }
        };
        let text = String::from_utf8_lossy(&out.stdout).to_string()
            + &String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{text}");
        assert!(
            text.contains("job/fogbank-render") && text.contains("job/fogbank-merge"),
            "{text}"
        );
    }
}

/// The first number after `key` in `text`.
fn number_after(text: &str, key: &str) -> u32 {
    let at = text.find(key).unwrap_or_else(|| panic!("no `{key}`")) + key.len();
    let digits: String = text[at..]
        .chars()
        .skip_while(|c| !c.is_ascii_digit())
        .take_while(|c| c.is_ascii_digit())
        .collect();
    digits.parse().unwrap()
}

#[test]
fn the_indexed_job_renders_as_many_shards_as_it_has_completions() {
    let path = manifests()
        .into_iter()
        .find(|p| p.ends_with("render-shards.yaml"))
        .unwrap();
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains("completionMode: Indexed"));
    assert!(text.contains("--shard \"$JOB_COMPLETION_INDEX/$SHARDS\""));
    assert!(text.contains("part_$JOB_COMPLETION_INDEX.fbpart"));
    assert_eq!(
        number_after(&text, "completions:"),
        number_after(&text, "name: SHARDS")
    );
}
