//! The Python package (`crates/python`): builds its wheel with maturin into the test environment
//! (`scripts/test-env`: a virtual environment with maturin, pytest, numpy and syssimx), installs it
//! and runs its pytest suite (`crates/python/tests`). The suite compares `Simulation().run(1, 0.01)`
//! with the `results.csv` that the CLI built here writes, and the same with the rigid wall
//! (`results.csv` and `events.csv`), and `pendulum_fem.sweep` with the `summary.csv` of this
//! CLI's `sweep` (its path in `PENDULUM_FEM_CLI`); any failure fails this test with pytest's
//! output (nothing is skipped).

use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "common/python.rs"]
mod python_env;
use python_env::run;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The CLI's output folder (`results.csv`, and `events.csv` with a wall) of the default run to
/// `time.end = 1` with the overrides `sets` (no other outputs), in `dir/name`.
fn cli_results(dir: &Path, name: &str, sets: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let _ = std::fs::remove_dir_all(&out);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_pendulum-fem"));
    cmd.args(["run", "--quiet", "--set", "time.end=1"]);
    for set in sets {
        cmd.args(["--set", set]);
    }
    for key in ["plots", "animation", "paraview", "viewer"] {
        cmd.args(["--set", &format!("output.{key}=false")]);
    }
    cmd.arg("--out").arg(&out);
    run(&mut cmd, "pendulum-fem run");
    out
}

#[test]
fn python_package_builds_installs_and_passes_its_tests() {
    let root = root();
    let python = python_env::test_env_python(&root);
    let scratch = root.join("target/python-test");
    std::fs::create_dir_all(&scratch).unwrap();
    let results = cli_results(&scratch, "cli-run", &[]).join("results.csv");
    let wall = cli_results(&scratch, "cli-run-wall", &["wall.kind=\"rigid\""]);
    python_env::install_wheel(&root, &python, &scratch);
    let report = run(
        Command::new(&python)
            .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
            .arg(root.join("crates/python/tests"))
            .env("PENDULUM_FEM_RESULTS_CSV", &results)
            .env("PENDULUM_FEM_WALL_RESULTS_CSV", wall.join("results.csv"))
            .env("PENDULUM_FEM_WALL_EVENTS_CSV", wall.join("events.csv"))
            .env("PENDULUM_FEM_CLI", env!("CARGO_BIN_EXE_pendulum-fem"))
            .current_dir(&scratch),
        "pytest crates/python/tests",
    );
    let last = report.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or_default();
    assert!(
        last.contains("passed") && !last.contains("failed") && !last.contains("skipped"),
        "pytest: {last}\n{report}"
    );
    println!("{report}");
}
