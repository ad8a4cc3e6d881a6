//! The Slurm recipes of `deploy/slurm` on a real engine: a single-node
//! cluster (slurmctld + slurmd on this machine, munge) runs the array job of
//! 4 shards and the dependent merge job, and the merged image equals the
//! single-process render byte for byte.
//!
//! Needs Debian's `slurm-wlm` and `munge` and root. Without them the test
//! says why and passes — unless `FOGBANK_REQUIRE_SLURM=1` (which CI's
//! `.ci/run` sets after installing them): then it fails.

use crate::support;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};
use support::*;

fn deploy(script: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../deploy/slurm")
        .join(script)
}

/// Why a single-node cluster cannot run here, if it cannot.
fn missing_requirement() -> Option<String> {
    for tool in ["slurmctld", "slurmd", "sbatch", "munged"] {
        let found = Command::new("sh")
            .args(["-c", &format!("command -v {tool}")])
            .output()
            .is_ok_and(|o| o.status.success());
        if !found {
            return Some(format!(
                "{tool} not found (apt-get install slurm-wlm munge)"
            ));
        }
    }
    let uid = Command::new("id").arg("-u").output().ok()?;
    (String::from_utf8_lossy(&uid.stdout).trim() != "0")
        .then(|| "not root: slurmd must run as root".to_string())
}

/// Fails under `FOGBANK_REQUIRE_SLURM=1`, otherwise says why and skips.
fn unavailable(why: &str) {
    if std::env::var("FOGBANK_REQUIRE_SLURM").is_ok_and(|v| v == "1") {
        panic!("FOGBANK_REQUIRE_SLURM=1 but the single-node Slurm cannot run: {why}");
    }
    eprintln!("skipped: the single-node Slurm cannot run: {why}");
}

/// Stops the cluster however the test ends.
struct Cluster(PathBuf);

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new(deploy("single_node.sh"))
            .arg("stop")
            .arg(&self.0)
            .status();
    }
}

#[test]
fn slurm_array_job_renders_shards_that_merge_to_the_single_run() {
    if let Some(why) = missing_requirement() {
        return unavailable(&why);
    }
    let dir = tmp_dir("slurm");
    let cluster_dir = dir.join("cluster");
    for old in ["out.exr", "out.json", "single.exr"] {
        let _ = std::fs::remove_file(dir.join(old));
    }
    let _ = std::fs::remove_dir_all(dir.join("out_parts"));
    let start = Command::new(deploy("single_node.sh"))
        .arg("start")
        .arg(&cluster_dir)
        .output()
        .unwrap();
    let _cluster = Cluster(cluster_dir.clone());
    if !start.status.success() {
        return unavailable(&format!(
            "single_node.sh start failed: {}{}",
            String::from_utf8_lossy(&start.stdout),
            String::from_utf8_lossy(&start.stderr)
        ));
    }
    let conf = cluster_dir.join("slurm.conf");
    let mut render_args = vec!["--spp", "8", "--set", "integrator.type=volpath"];
    render_args.extend(SMALL);
    let submit = run_ok(
        Command::new(deploy("submit.sh"))
            .current_dir(&dir)
            .env("SLURM_CONF", &conf)
            .env("FOGBANK", env!("CARGO_BIN_EXE_fogbank"))
            .args(["4", TRANSMITTANCE, dir.join("out.exr").to_str().unwrap()])
            .args(&render_args),
    );
    eprintln!("jobs: {}", String::from_utf8_lossy(&submit.stdout).trim());
    let deadline = Instant::now() + Duration::from_secs(240);
    while !dir.join("out.json").exists() {
        if Instant::now() > deadline {
            let queue = Command::new("squeue")
                .env("SLURM_CONF", &conf)
                .output()
                .unwrap();
            let logs: String = std::fs::read_dir(&dir)
                .unwrap()
                .flatten()
                .filter(|e| e.file_name().to_string_lossy().ends_with(".out"))
                .map(|e| std::fs::read_to_string(e.path()).unwrap_or_default())
                .collect();
            panic!(
                "the jobs did not finish within 240 s; squeue:\n{}\njob logs:\n{logs}",
                String::from_utf8_lossy(&queue.stdout)
            );
        }
        std::thread::sleep(Duration::from_millis(250));
    }
    run_ok(
        fogbank()
            .args([
                "render",
                TRANSMITTANCE,
                "--quiet",
                "-o",
                dir.join("single.exr").to_str().unwrap(),
            ])
            .args(&render_args),
    );
    let merged = std::fs::read(dir.join("out.exr")).unwrap();
    assert!(
        merged == std::fs::read(dir.join("single.exr")).unwrap(),
        "merged image differs from the single run"
    );
    let stats = read_json(&dir.join("out.json"));
    assert_eq!(stats["shards"].as_array().unwrap().len(), 4);
}
