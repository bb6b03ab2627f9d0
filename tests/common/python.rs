//! The test environment's Python with this checkout's `pendulum_fem` wheel installed, for the
//! tests that run Python (`tests/python_package.rs`, `tests/docs.rs`).

#![allow(dead_code)]
use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs `cmd` and returns its stdout; panics with everything it printed when it fails.
pub fn run(cmd: &mut Command, what: &str) -> String {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot start {cmd:?}: {e}"));
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        out.status.success(),
        "{what} failed ({}):\n--- stdout ---\n{stdout}\n--- stderr ---\n{stderr}",
        out.status
    );
    stdout
}

/// The interpreter of `scripts/test-env` (a virtual environment in `target/test-venv` with the
/// pinned test requirements, created on first use).
pub fn test_env_python(root: &Path) -> PathBuf {
    let python = run(&mut Command::new(root.join("scripts/test-env")), "scripts/test-env");
    PathBuf::from(python.trim())
}

/// Builds the wheel of `crates/python` with maturin (release) into `scratch/wheels` and installs it
/// into the environment of `python`, replacing any earlier build, so that the package imported
/// there is this checkout's.
pub fn install_wheel(root: &Path, python: &Path, scratch: &Path) {
    // a fresh wheel folder, so that exactly the wheel built now is installed
    let wheels = scratch.join("wheels");
    let _ = std::fs::remove_dir_all(&wheels);
    run(
        Command::new(python)
            .args(["-m", "maturin", "build", "--release", "--quiet", "--manifest-path"])
            .arg(root.join("crates/python/Cargo.toml"))
            .arg("--out")
            .arg(&wheels),
        "maturin build",
    );
    let wheel = std::fs::read_dir(&wheels)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "whl"))
        .expect("maturin wrote a wheel");
    run(
        Command::new(python)
            .args(["-m", "pip", "install", "--quiet", "--force-reinstall", "--no-deps"])
            .arg(&wheel),
        "pip install",
    );
}
