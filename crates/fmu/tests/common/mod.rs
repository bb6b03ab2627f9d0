//! Helpers of the FMU's importer tests (`fmu_with_importers.rs`, `fmi3.rs`): the FMUs packed from
//! the shared object cargo built next to the test, the Python of `scripts/test-env`, the scripts of
//! `tests/python/` and the CLI's reference runs.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use pendulum_fem_fmu::package::{write_fmu, write_fmu3, LIBRARY_FILE};

pub fn manifest_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn workspace_root() -> PathBuf {
    manifest_dir()
        .join("../..")
        .canonicalize()
        .expect("the workspace root exists")
}

/// A scratch folder for this test binary's files (next to it; the next run overwrites them).
pub fn scratch() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable path");
    let dir = exe.parent().expect("deps folder").join("fmu-test");
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// The shared object cargo built next to this test binary.
fn library() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable path");
    let deps = exe.parent().expect("deps folder");
    [deps.join(LIBRARY_FILE), deps.join("..").join(LIBRARY_FILE)]
        .into_iter()
        .find(|p| p.is_file())
        .unwrap_or_else(|| panic!("{LIBRARY_FILE} not found next to {}", exe.display()))
}

/// The FMU `name` written by `write` from [`library`], once per test binary (in `slot`).
fn packed(
    slot: &'static OnceLock<PathBuf>,
    name: &str,
    write: fn(&Path, &Path) -> std::io::Result<()>,
) -> &'static Path {
    slot.get_or_init(|| {
        let fmu = scratch().join(name);
        write(&library(), &fmu).expect("FMU packed");
        fmu
    })
}

/// The FMI 2.0 FMU, packed once per test binary.
pub fn fmu() -> &'static Path {
    static FMU: OnceLock<PathBuf> = OnceLock::new();
    packed(&FMU, "PendulumFem.fmu", write_fmu)
}

/// The FMI 3.0 FMU (`PendulumFem3`), packed once per test binary.
pub fn fmu3() -> &'static Path {
    static FMU: OnceLock<PathBuf> = OnceLock::new();
    packed(&FMU, "PendulumFem3.fmu", write_fmu3)
}

/// The test environment's Python (`scripts/test-env`); panics with its error output if it fails.
pub fn python() -> &'static Path {
    static PYTHON: OnceLock<PathBuf> = OnceLock::new();
    PYTHON.get_or_init(|| {
        let script = workspace_root().join("scripts/test-env");
        let out = Command::new("bash")
            .arg(&script)
            .output()
            .unwrap_or_else(|e| panic!("cannot run {}: {e}", script.display()));
        assert!(
            out.status.success(),
            "{} failed ({}), so the FMU cannot be tested with fmpy, libcosimpy and syssimx:\n{}",
            script.display(),
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
        let path = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim().to_string());
        assert!(
            path.is_file(),
            "scripts/test-env printed `{}`, not a Python",
            path.display()
        );
        path
    })
}

/// Runs `tests/python/<script>` with `args`; asserts success and returns its JSON line.
pub fn run_script(script: &str, args: &[String]) -> String {
    let dir = manifest_dir().join("tests/python");
    let out = Command::new(python())
        .arg(dir.join(script))
        .args(args)
        .current_dir(&dir)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {script}: {e}"));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let line = stdout
        .lines()
        .rev()
        .find(|l| l.starts_with('{'))
        .unwrap_or("")
        .to_string();
    eprintln!("{script}: {line}");
    assert!(
        out.status.success() && line.contains("\"ok\": true"),
        "{script} failed ({}):\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    line
}

/// The CLI binary that `cargo test --release` builds beside this test (the workspace's default
/// members include the CLI), so that the FMU is compared with the files the CLI writes.
pub fn cli_binary() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable path");
    let bin = exe
        .parent()
        .and_then(Path::parent)
        .expect("the profile folder")
        .join(format!("pendulum-fem{}", std::env::consts::EXE_SUFFIX));
    assert!(
        bin.is_file(),
        "{} not found: these tests compare the FMU with the CLI's files; run `cargo test --release` at the \
         workspace root (or `cargo build --release` first)",
        bin.display()
    );
    bin
}

/// Runs the CLI, `pendulum-fem run --set …` with `overrides` (pictures off: they do not feed the CSV
/// files), into the fresh folder `scratch()/name`; returns the folder, with the CLI's
/// `results.csv` (and `events.csv` with a wall), stepped by the CLI's own step plan.
pub fn cli_run(name: &str, overrides: &[String]) -> PathBuf {
    let dir = scratch().join(name);
    let _ = std::fs::remove_dir_all(&dir);
    let mut cmd = Command::new(cli_binary());
    cmd.args(["run", "-q", "--out"]).arg(&dir);
    for set in [
        "output.plots=false",
        "output.animation=false",
        "output.paraview=false",
        "output.viewer=false",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain(overrides.iter().cloned())
    {
        cmd.args(["--set", &set]);
    }
    let out = cmd.output().expect("the CLI runs");
    assert!(
        out.status.success(),
        "pendulum-fem run {overrides:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    dir
}
