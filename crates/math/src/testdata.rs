//! For tests: the policy for data outside the repository. A test that needs
//! an external file ([`crate::sample_data::external`]: cube.vdb, Mitsuba's
//! grids, openvdb.org's original sphere, the MNI templates) asks for it here;
//! without it the test prints what it skipped and passes, unless
//! `FOGBANK_REQUIRE_DATA=1` (set by `.ci/run`) makes a missing file a
//! failure, so that CI cannot pass by skipping. Committed files
//! ([`crate::sample_data::committed`]) need no such care. No test reads a
//! file outside the repository by any other way: `.ci/run` runs the suite
//! again from a clone with nothing beside it to keep it so.

use crate::sample_data;
use crate::{Pcg32, Ray, Vec3};
use std::path::PathBuf;

/// The variable that turns missing external data into a test failure.
pub const REQUIRE_DATA_VAR: &str = "FOGBANK_REQUIRE_DATA";

/// The external file `name` (`data/fetched/` or `../shared/data`), or `None`
/// after printing `SKIPPED (no NAME …)`. Panics instead when
/// `FOGBANK_REQUIRE_DATA=1`.
pub fn external_data(name: &str) -> Option<PathBuf> {
    sample_data::external(name)
        .map_err(|e| skip_unless_required::<()>(&e))
        .ok()
}

/// The MNI152 template `name` in `data/mni/` (tools/fetch_data.sh mni), with
/// the same rules as [`external_data`].
pub fn mni_data(name: &str) -> Option<PathBuf> {
    let path = sample_data::mni_dir().join(name);
    if path.is_file() {
        Some(path)
    } else {
        skip_unless_required(&format!(
            "no {}; run tools/fetch_data.sh mni",
            path.display()
        ))
    }
}

/// A file to which every skip is also appended as `TEST: what` (captured
/// output of passing tests is not shown; `tools/test_plain_clone.sh` lists
/// the skips from it).
pub const SKIP_LOG_VAR: &str = "FOGBANK_SKIP_LOG";

/// `None` after printing `SKIPPED (what)`, for a test whose external input
/// is missing; panics instead when `FOGBANK_REQUIRE_DATA=1`.
pub fn skip_unless_required<T>(what: &str) -> Option<T> {
    skip_unless(REQUIRE_DATA_VAR, what)
}

/// `None` after printing (and logging) `SKIPPED (what)`; panics instead
/// when the variable `require` is `1`.
fn skip_unless<T>(require: &str, what: &str) -> Option<T> {
    if std::env::var(require).as_deref() == Ok("1") {
        panic!("{require}=1 but {what}");
    }
    eprintln!("SKIPPED ({what})");
    if let Some(log) = std::env::var_os(SKIP_LOG_VAR) {
        // The test harness names each test's thread after the test.
        let test = std::thread::current().name().unwrap_or("?").to_string();
        sample_data::append_line(std::path::Path::new(&log), &format!("{test}: {what}"));
    }
    None
}

/// The command-line tool `name` found on `PATH`, or `None` after printing
/// `SKIPPED (no NAME on PATH …)` with `install` (how to get it). Panics
/// instead when the variable `require` is `1` (`.ci/run` sets it for the
/// tools it installs), so that CI cannot pass by skipping.
pub fn tool_on_path(name: &str, require: &str, install: &str) -> Option<PathBuf> {
    let found = std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|d| d.join(name))
            .find(|p| p.is_file())
    });
    found.or_else(|| skip_unless(require, &format!("no {name} on PATH ({install})")))
}

/// A Python interpreter that imports `module`, or `None` (after saying so)
/// when there is none; a failure instead when the variable `require` is
/// `1`. Debian's bindings live in `/usr/bin/python3`'s site packages, so
/// that interpreter is preferred to whatever `python3` a virtual
/// environment puts first on `PATH`.
pub fn python_with_module(module: &str, require: &str, install: &str) -> Option<PathBuf> {
    let system = PathBuf::from("/usr/bin/python3");
    let candidates = [system, PathBuf::from("python3")];
    let imports = |py: &PathBuf| {
        std::process::Command::new(py)
            .args(["-c", &format!("import {module}")])
            .output()
            .is_ok_and(|o| o.status.success())
    };
    match candidates.into_iter().find(imports) {
        Some(py) => Some(py),
        None => skip_unless(
            require,
            &format!("no python3 that imports {module} ({install})"),
        ),
    }
}

/// A 24³ f32 raw grid for integrator tests without faint fringes (seed
/// 002's unbiasedness tests, CPU and GPU): its far half (k < 12) is dense
/// everywhere, so every ray through the front face meets many events, and
/// its near half a checkerboard of 3-voxel columns and holes, so a shifted
/// vertex often lands at zero density. Written to the temp folder (once per
/// process and name); returns the path with forward slashes.
pub fn checker_slab_raw(name: &str) -> String {
    let path = std::env::temp_dir().join(format!("{name}_{}.raw", std::process::id()));
    let n = 24usize;
    let mut bytes = Vec::with_capacity(n * n * n * 4);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let d: f32 = if k < n / 2 {
                    0.5 + 0.5 * (((i * 7 + j * 13 + k * 5) % 11) as f32 / 10.0)
                } else if (i / 3 + j / 3) % 2 == 0 {
                    1.0
                } else {
                    0.0
                };
                bytes.extend_from_slice(&d.to_le_bytes());
            }
        }
    }
    // Written beside and renamed into place: tests of one binary run in
    // parallel threads, and one truncating the file while another read it
    // made the reader see 0 bytes (restir_gpu_test, CI).
    static WRITES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let k = WRITES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let tmp = path.with_extension(format!("raw.{k}.tmp"));
    std::fs::write(&tmp, bytes).expect("writing the test volume");
    std::fs::rename(&tmp, &path).expect("moving the test volume into place");
    path.display().to_string().replace('\\', "/")
}

/// Ray `k` of a BVH test, drawn from `rng`: from around a sphere of radius
/// 2.5 toward a random point of the box [−1.2, 1.2]³; every seventh ray
/// axis-parallel (the slab test's 0·∞) and every third with a finite
/// `t_max` of 0.9. Returns the ray and its `t_max`.
pub fn probe_ray(rng: &mut Pcg32, k: usize) -> (Ray, f32) {
    let mut r = || 2.0 * rng.next_f32() - 1.0;
    let o = Vec3::new(r(), r(), r()) * 2.5;
    let target = Vec3::new(r(), r(), r()) * 1.2;
    let d = if k.is_multiple_of(7) {
        Vec3::new(0.0, 0.0, -o.z.signum())
    } else {
        target - o
    };
    let t_max = if k.is_multiple_of(3) {
        0.9
    } else {
        f32::INFINITY
    };
    (Ray::new(o, d), t_max)
}
