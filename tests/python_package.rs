//! The Python package (`crates/python`): builds its abi3 wheel with the maturin of the test
//! environment (`scripts/test-env`), installs it with its extras into a clean virtual environment
//! without maturin or Rust (`scripts/wheel-env`, see `tests/common/python.rs`), and runs its pytest
//! suite (`crates/python/tests`) there, from a folder outside the source tree, so that the package
//! under test is the installed wheel. The suite compares `Simulation().run(1, 0.01)`
//! with the `results.csv` that the CLI built here writes, and the same with the rigid wall
//! (`results.csv` and `events.csv`), and `pendulum_fem.sweep` with the `summary.csv` of this
//! CLI's `sweep` (its path in `PENDULUM_FEM_CLI`); any failure fails this test with pytest's
//! output (nothing is skipped).

use crate::common;
use common::python as python_env;
use python_env::run;

#[test]
fn the_abi3_wheel_installs_into_a_clean_environment_and_passes_the_python_suite() {
    let root = common::root();
    let scratch = common::scratch("python-package");
    let results = python_env::cli_run(&scratch.join("cli-run"), &["time.end=1"]).join("results.csv");
    let wall = python_env::cli_run(&scratch.join("cli-run-wall"), &["time.end=1", "wall.kind=\"rigid\""]);
    // pytest's working folder: outside the source tree, so that `import pendulum_fem` can only
    // find the installed wheel
    let cwd = python_env::outside_the_source_tree("python-package");
    let env = python_env::wheel_env(root);
    println!("installed {} into {}", env.wheel, env.python.display());
    let report = run(
        env.command(&env.python, &cwd)
            .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
            // no `__pycache__` beside the suite's files: the checkout stays as it was, which the
            // notebook and documentation tests running beside this one check
            .env("PYTHONDONTWRITEBYTECODE", "1")
            .arg(root.join("crates/python/tests"))
            .env("PENDULUM_FEM_RESULTS_CSV", &results)
            .env("PENDULUM_FEM_WALL_RESULTS_CSV", wall.join("results.csv"))
            .env("PENDULUM_FEM_WALL_EVENTS_CSV", wall.join("events.csv"))
            .env("PENDULUM_FEM_CLI", env!("CARGO_BIN_EXE_pendulum-fem")),
        "pytest crates/python/tests",
    );
    let last = report.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or_default();
    assert!(
        last.contains("passed") && !last.contains("failed") && !last.contains("skipped"),
        "pytest: {last}\n{report}"
    );
    println!("{report}");
    let _ = std::fs::remove_dir_all(&cwd);
}
