//! The tutorial notebooks of `examples/notebooks/`: stored without outputs, and every one runs,
//! cell by cell, against the installed wheel.
//!
//! The run builds the package's abi3 wheel, installs it into the clean environment of
//! `scripts/wheel-env` (no maturin, no Rust; matplotlib, ipykernel, nbclient and fmpy pinned in
//! `scripts/requirements-wheel.txt`) and executes each notebook with nbclient
//! (`scripts/run-notebook.py`) in its own folder, `examples/notebooks/`, as Jupyter runs it; an
//! error in any cell fails the test, and so does any file the notebooks leave in the checkout
//! (outside `target/`). The basics notebook gets the results.csv of the CLI's default run
//! (`PENDULUM_FEM_RESULTS_CSV`) and writes its θ(t) to a temporary folder, printing the path; this
//! test compares that file with the CLI's `results.csv` bit for bit. The co-simulation notebook gets
//! the FMU, packed here from the library built with this test, in `PENDULUM_FEM_FMU`. A missing tool
//! fails the test with the reason; nothing is skipped.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::common;
use common::python as python_env;
use python_env::run;

/// The notebooks, in the order a reader takes them.
const NOTEBOOKS: [&str; 4] = [
    "01-basics.ipynb",
    "02-torque-and-wall.ipynb",
    "03-cosimulation.ipynb",
    "04-parameter-study.ipynb",
];

/// Writes `line` to the test's stderr past libtest's capture, so that the log of a passing run
/// names each notebook and its time too.
fn report(line: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr().lock(), "notebooks: {line}");
}

fn notebook_dir() -> PathBuf {
    common::root().join("examples/notebooks")
}

/// The columns `time_s` and `theta_rad` of a CSV file with a header, as the bits of the doubles
/// its text reads as (Rust's parser rounds correctly, as Python's and the CLI's printing
/// round-trips).
fn time_and_theta_bits(path: &Path) -> Vec<(u64, u64)> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("{}: no {name}", path.display()))
    };
    let (t, theta) = (col("time_s"), col("theta_rad"));
    lines
        .map(|line| {
            let cells: Vec<&str> = line.split(',').collect();
            let bits = |j: usize| {
                cells[j]
                    .parse::<f64>()
                    .unwrap_or_else(|e| panic!("{}: {line}: {e}", path.display()))
                    .to_bits()
            };
            (bits(t), bits(theta))
        })
        .collect()
}

#[test]
fn the_notebooks_in_git_have_no_outputs() {
    let mut found: Vec<String> = std::fs::read_dir(notebook_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".ipynb"))
        .collect();
    found.sort();
    assert_eq!(
        found, NOTEBOOKS,
        "the notebooks of examples/notebooks/ (each must be listed here, so that it runs)"
    );
    for name in NOTEBOOKS {
        let path = notebook_dir().join(name);
        let nb: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap())
            .unwrap_or_else(|e| panic!("{name} is not JSON: {e}"));
        assert_eq!(nb["nbformat"], 4, "{name}: nbformat");
        let cells = nb["cells"].as_array().unwrap_or_else(|| panic!("{name}: no cells"));
        let code: Vec<_> = cells.iter().filter(|c| c["cell_type"] == "code").collect();
        assert!(code.len() >= 3, "{name}: {} code cells", code.len());
        for (k, cell) in code.iter().enumerate() {
            assert_eq!(
                cell["outputs"],
                serde_json::json!([]),
                "{name}: code cell {k} has outputs: strip them"
            );
            assert!(
                cell["execution_count"].is_null(),
                "{name}: code cell {k} has an execution count: strip it"
            );
        }
        println!("{name}: {} cells, {} of code, no outputs", cells.len(), code.len());
    }
}

/// The file the basics notebook says it wrote θ(t) to (`wrote N rows to PATH`), from the outputs
/// of its executed copy.
fn theta_csv_written_by(executed: &Path) -> PathBuf {
    let nb: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(executed).unwrap()).unwrap();
    let said = " rows to ";
    nb["cells"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|c| c["outputs"].as_array().cloned().unwrap_or_default())
        .filter_map(|o| match &o["text"] {
            serde_json::Value::Array(lines) => Some(lines.iter().filter_map(|l| l.as_str()).collect::<String>()),
            serde_json::Value::String(text) => Some(text.clone()),
            _ => None,
        })
        .flat_map(|text| text.lines().map(str::to_string).collect::<Vec<_>>())
        .find_map(|line| {
            let rest = line.strip_prefix("wrote ")?;
            Some(PathBuf::from(rest.split_once(said)?.1.trim()))
        })
        .unwrap_or_else(|| panic!("{} says nowhere that it wrote θ(t)", executed.display()))
}

#[test]
fn every_notebook_runs_against_the_installed_wheel_and_leaves_no_file_in_the_checkout() {
    let root = common::root();
    let scratch = common::scratch("notebooks");
    // the CLI's default run (1 s in steps of 10 ms)
    let results = python_env::cli_run(&scratch.join("cli-run"), &[]).join("results.csv");
    let fmu = python_env::pack_fmu(&scratch.join("fmu"));

    let env = python_env::wheel_env(root);
    report(&format!("installed {} into {}", env.wheel, env.python.display()));
    let before = common::source_tree_files();
    for name in NOTEBOOKS {
        let executed = scratch.join(name);
        let start = Instant::now();
        let cells = run(
            // the notebook's own folder is the kernel's working folder, as in Jupyter
            env.command(&env.python, &notebook_dir())
                .arg(root.join("scripts/run-notebook.py"))
                .arg(notebook_dir().join(name))
                .arg(&executed)
                .env("PENDULUM_FEM_RESULTS_CSV", &results)
                .env("PENDULUM_FEM_FMU", &fmu)
                // the kernel's own backend draws the figures into the outputs
                .env_remove("MPLBACKEND"),
            &format!("notebook {name}"),
        );
        report(&format!(
            "{name}: ran without error in {:.1} s ({}; executed copy in {})",
            start.elapsed().as_secs_f64(),
            cells.trim(),
            executed.display()
        ));
    }
    common::assert_no_new_files(&before, &common::source_tree_files(), "running the notebooks");

    // θ(t) of the basics notebook is the CLI's: the same doubles, bit for bit (both are the same
    // steps of the same code; any difference is a bug, not rounding)
    let theta_csv = theta_csv_written_by(&scratch.join(NOTEBOOKS[0]));
    assert!(
        !theta_csv.starts_with(root),
        "the notebook wrote θ(t) into the checkout: {}",
        theta_csv.display()
    );
    let cli_rows = time_and_theta_bits(&results);
    let notebook_rows = time_and_theta_bits(&theta_csv);
    assert_eq!(cli_rows.len(), 101, "the CLI's default run: 1 s in steps of 10 ms");
    assert_eq!(notebook_rows.len(), cli_rows.len(), "rows of θ(t)");
    for (k, (a, b)) in notebook_rows.iter().zip(&cli_rows).enumerate() {
        assert_eq!(
            a,
            b,
            "row {k}: the notebook's (t, θ) = ({}, {}), the CLI's ({}, {})",
            f64::from_bits(a.0),
            f64::from_bits(a.1),
            f64::from_bits(b.0),
            f64::from_bits(b.1)
        );
    }
    report(&format!(
        "01-basics.ipynb: θ(t) equals the CLI's results.csv bit for bit ({} rows)",
        cli_rows.len()
    ));
    if let Some(folder) = theta_csv.parent() {
        let _ = std::fs::remove_dir_all(folder);
    }
}
