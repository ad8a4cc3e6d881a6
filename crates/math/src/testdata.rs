//! For tests: the optional real-world data in `../shared/data`, beside the
//! repository root. Tests that need it skip with a visible message when it
//! is missing, unless `FOGBANK_REQUIRE_DATA=1` (set by `.ci/run`) makes a
//! missing folder or file a failure, so that CI cannot pass by skipping.

use std::path::{Path, PathBuf};

/// The variable that turns missing shared data into a test failure.
pub const REQUIRE_DATA_VAR: &str = "FOGBANK_REQUIRE_DATA";

/// `../shared/data` seen from the repository root, whether or not it exists.
fn shared_data_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data")
}

/// The shared data folder, or `None` after printing
/// `SKIPPED (no ../shared/data)`. Panics instead when `FOGBANK_REQUIRE_DATA=1`.
pub fn shared_data_dir() -> Option<PathBuf> {
    let dir = shared_data_path();
    if dir.is_dir() {
        Some(dir)
    } else {
        missing("no ../shared/data", &dir)
    }
}

/// The file `name` of the shared data folder, with the same rules as
/// [`shared_data_dir`] for a missing folder or file.
pub fn shared_data(name: &str) -> Option<PathBuf> {
    let path = shared_data_dir()?.join(name);
    if path.exists() {
        Some(path)
    } else {
        missing(&format!("no ../shared/data/{name}"), &path)
    }
}

fn missing<T>(what: &str, path: &Path) -> Option<T> {
    if std::env::var(REQUIRE_DATA_VAR).as_deref() == Ok("1") {
        panic!(
            "{REQUIRE_DATA_VAR}=1 but {what}: {} not found",
            path.display()
        );
    }
    eprintln!("SKIPPED ({what})");
    None
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
