//! Where the real volume files that scenes, experiments and tests read are
//! (`data/README.md` lists them with origin and licence). Small ones are
//! committed in the repository's `data/`, so the scenes of `scenes/` (all
//! but the MRI one) and the quick tests work on a plain clone; larger ones live outside the
//! repository: in the git-ignored `data/fetched/` and `data/mni/`, which
//! `tools/fetch_data.sh` fills, in `../shared/data` beside the repository,
//! or in a folder named by `FOGBANK_DATA_DIR`.
//! Scene files name committed data by relative paths (`../data/dragon.vdb`
//! from `scenes/`); code that needs an external file asks [`external`] and
//! says [`FETCH_HINT`] when it is missing.

use std::path::{Path, PathBuf};

/// What to tell a user about a missing external file.
pub const FETCH_HINT: &str = "run tools/fetch_data.sh, put ../shared/data beside the \
     repository or name a folder holding it in FOGBANK_DATA_DIR";

/// The repository root (two folders above this crate's manifest).
pub fn repo_root() -> PathBuf {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest
        .ancestors()
        .nth(2)
        .unwrap_or(manifest)
        .to_path_buf()
}

/// The committed sample file `name` of `data/` (always there in a checkout).
pub fn committed(name: &str) -> PathBuf {
    repo_root().join("data").join(name)
}

/// The variable naming a folder of external files, looked in first.
pub const DATA_DIR_VAR: &str = "FOGBANK_DATA_DIR";

/// The external file `name`, looked for in `$FOGBANK_DATA_DIR` (when set),
/// `data/fetched/` (tools/fetch_data.sh), then `../shared/data`; the error
/// names every place and how to fetch it.
pub fn external(name: &str) -> Result<PathBuf, String> {
    note_test_asking();
    let root = repo_root();
    let dirs = std::env::var_os(DATA_DIR_VAR).map(PathBuf::from);
    let places: Vec<PathBuf> = dirs
        .into_iter()
        .chain([
            root.join("data/fetched"),
            root.with_file_name("shared/data"),
        ])
        .map(|d| d.join(name))
        .collect();
    if let Some(p) = places.iter().find(|p| p.is_file()) {
        return Ok(p.clone());
    }
    let looked: Vec<String> = places.iter().map(|p| p.display().to_string()).collect();
    Err(format!(
        "{name} is not in {}: {FETCH_HINT}",
        looked.join(", ")
    ))
}

/// The sample file `name`: committed in `data/`, else [`external`].
pub fn find(name: &str) -> Result<PathBuf, String> {
    let committed = committed(name);
    if committed.is_file() {
        Ok(committed)
    } else {
        external(name)
    }
}

/// `data/mni/`, where `tools/fetch_data.sh mni` puts the MNI152 templates
/// (`mni_t1.nii.gz`, `mni_gm.nii.gz`, `mni_wm.nii.gz`), whether or not they
/// have been fetched.
pub fn mni_dir() -> PathBuf {
    note_test_asking();
    repo_root().join("data/mni")
}

/// The variable naming a file to which each test that asks for external
/// data appends its name: `.ci/run`'s second pass (tools/test_plain_clone.sh)
/// reruns just those tests without the data, to see them skip cleanly.
pub const DATA_LOG_VAR: &str = "FOGBANK_DATA_LOG";

/// Appends the running test's name to `$FOGBANK_DATA_LOG`. The test harness
/// names each test's thread after the test; other threads are no test's.
fn note_test_asking() {
    let Some(log) = std::env::var_os(DATA_LOG_VAR) else {
        return;
    };
    let thread = std::thread::current();
    if let Some(test) = thread.name().filter(|n| *n != "main") {
        append_line(Path::new(&log), test);
    }
}

/// Appends `line` and a newline to the file `path` (created if missing); a
/// failure is printed, not raised: the logs it serves are diagnostics.
pub(crate) fn append_line(path: &Path, line: &str) {
    let file = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path);
    let written =
        file.and_then(|mut f| std::io::Write::write_all(&mut f, format!("{line}\n").as_bytes()));
    if let Err(e) = written {
        eprintln!("{}: {e}", path.display());
    }
}
