//! The Python package's suite (`python/tests`, pytest) and the example
//! notebooks (`examples/*.ipynb`, executed by nbmake), run from `cargo
//! test` so that the README's one test command covers them.
//!
//! The package's native module is built here with the test profile into
//! this build's target folder (`cargo build --profile test --manifest-path
//! python/Cargo.toml`, reusing the crates `cargo test` compiled) and staged
//! with the package's Python files under `target/python-stage/`; a venv in
//! `target/python-venv/` holds numpy, pytest, nbmake and matplotlib from
//! PyPI. `pip install ./python` builds the same package with maturin in the
//! release profile (docs/guide/python.md).
//!
//! Without python3's venv module, or without PyPI, the test says why and
//! passes, unless FOGBANK_REQUIRE_PYTHON=1 (set by `.ci/run`).

use std::path::{Path, PathBuf};
use std::process::Command;

const REQUIRE: &str = "FOGBANK_REQUIRE_PYTHON";
/// What the suite and the notebooks import besides fogbank.
const PACKAGES: [&str; 5] = ["numpy", "pytest", "nbmake", "matplotlib", "ipykernel"];

/// Skips with `why`, or fails when the Python suite is required.
fn skip(why: &str) {
    if std::env::var(REQUIRE).as_deref() == Ok("1") {
        panic!("{REQUIRE}=1 but {why}");
    }
    eprintln!("SKIPPED (the Python package's tests: {why})");
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn target_dir() -> PathBuf {
    // CARGO_TARGET_TMPDIR is <target>/tmp.
    Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("the target folder")
        .to_path_buf()
}

fn succeeds(cmd: &mut Command) -> Result<(), String> {
    match cmd.output() {
        Ok(o) if o.status.success() => Ok(()),
        Ok(o) => Err(format!(
            "{:?}: {}{}",
            cmd,
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        )),
        Err(e) => Err(format!("{cmd:?}: {e}")),
    }
}

/// The venv with [`PACKAGES`], made once per target folder.
fn venv() -> Result<PathBuf, String> {
    let venv = target_dir().join("python-venv");
    let python = venv.join("bin/python");
    let ready = venv.join(".fogbank-packages");
    if std::fs::read_to_string(&ready).ok().as_deref() == Some(&PACKAGES.join(" ")) {
        return Ok(python);
    }
    succeeds(Command::new("python3").args(["-c", "import venv, ensurepip"])).map_err(|_| {
        "python3 with its venv module (Debian: python3-venv) is not installed".to_string()
    })?;
    let _ = std::fs::remove_dir_all(&venv);
    succeeds(Command::new("python3").arg("-m").arg("venv").arg(&venv))?;
    succeeds(
        Command::new(&python)
            .args(["-m", "pip", "install", "-q"])
            .args(PACKAGES),
    )
    .map_err(|e| format!("could not install {} from PyPI: {e}", PACKAGES.join(", ")))?;
    std::fs::write(&ready, PACKAGES.join(" ")).map_err(|e| e.to_string())?;
    Ok(python)
}

/// Builds the native module and stages the package; returns the folder to
/// put on PYTHONPATH.
fn stage(python: &Path) -> PathBuf {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let target = target_dir();
    let out = Command::new(cargo)
        .args(["build", "--quiet", "--profile", "test", "--manifest-path"])
        .arg(repo().join("python/Cargo.toml"))
        .env("CARGO_TARGET_DIR", &target)
        // As maturin builds it: Python's symbols come from the interpreter
        // that loads the module, so no libpython is linked.
        .env("PYO3_BUILD_EXTENSION_MODULE", "1")
        .env("PYO3_PYTHON", python)
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "building the Python package's native module: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stage = target.join("python-stage");
    let pkg = stage.join("fogbank");
    let _ = std::fs::remove_dir_all(&pkg);
    std::fs::create_dir_all(&pkg).unwrap();
    for entry in std::fs::read_dir(repo().join("python/fogbank")).unwrap() {
        let p = entry.unwrap().path();
        let keep = p
            .extension()
            .is_some_and(|e| e == "py" || e == "pyi" || e == "typed");
        if keep {
            std::fs::copy(&p, pkg.join(p.file_name().unwrap())).unwrap();
        }
    }
    std::fs::copy(
        target.join("debug/lib_native.so"),
        pkg.join("_native.abi3.so"),
    )
    .unwrap();
    stage
}

fn pytest(python: &Path, stage: &Path, args: &[PathBuf]) {
    let work = target_dir().join("tmp/python");
    std::fs::create_dir_all(&work).unwrap();
    let status = Command::new(python)
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
        .args(args)
        .current_dir(&work)
        .env("PYTHONPATH", stage)
        .env("FOGBANK_CLI", env!("CARGO_BIN_EXE_fogbank"))
        .env("FOGBANK_REPO", repo())
        .env("MPLBACKEND", "Agg")
        .status()
        .expect("pytest runs");
    assert!(
        status.success(),
        "pytest {args:?} failed (its report is above)"
    );
}

#[test]
fn python_package_suite_and_notebooks() {
    if !cfg!(target_os = "linux") {
        return skip("the staged build is Linux's (lib_native.so)");
    }
    let python = match venv() {
        Ok(p) => p,
        Err(why) => return skip(&why),
    };
    let stage = stage(&python);
    pytest(&python, &stage, &[repo().join("python/tests")]);
    // Asked, not read: the MRI notebook reads data/mni when it is there and
    // a phantom otherwise, so CI's pass without external data reruns this.
    let _ = fogbank::testing::sample_data::mni_dir();
    let notebooks: Vec<PathBuf> = std::fs::read_dir(repo().join("examples"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ipynb"))
        .collect();
    assert!(!notebooks.is_empty(), "examples/ has no notebooks");
    let mut args = vec![
        PathBuf::from("--nbmake"),
        PathBuf::from("--nbmake-timeout=900"),
    ];
    args.extend(notebooks);
    pytest(&python, &stage, &args);
}
