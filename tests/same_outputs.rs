//! The runs of `scripts/same-outputs`, made now, against the CSV files it saved in
//! `tests/same-outputs/`: every file, every column name, every row and every value.
//!
//! The script checks byte identity, which holds on the CPU where the files were saved; here the
//! values are compared to a fraction of their column's largest magnitude that any CPU meets: the
//! sparse factorisation picks its SIMD kernels at run time, and another instruction set (another
//! summation order, FMA or not) changes the last digits of each solve. Newton stops each step
//! within its tolerance, so such a change moves the converged state within that tolerance, which
//! is far wider than the rounding: the motion by about 1e-10 of its scale ([`MOTION`] allows
//! 1e-8), and the elastic deformation of the steel body, some 1e-8 of the motion, by about 1e-8
//! of itself, which the strain energy, the stresses and the hinge force carry ([`ELASTIC`]
//! allows 1e-6). Texts (the events' names) and the impact counts must be equal; a step's Newton
//! iterations may differ by one, as its convergence test may fall on either side of its
//! threshold.
//!
//! The runs are those of the script, with two differences that do not touch the compared files:
//! the default job runs without pictures (they do not feed the CSV files), and the reduced FMU
//! run uses the FMU packed from the shared object cargo built with this test (as
//! `cargo xtask fmu` packs it) instead of `target/fmu/PendulumFem.fmu`, simulated by fmpy in the
//! environment of `scripts/test-env`.

use crate::common;
use common::Extremes;

use std::path::{Path, PathBuf};

/// The largest difference allowed between a value of the motion (time, angle, rates, energies
/// but the strain energy, the contact's gap, force and energy) and its saved value, relative to
/// the largest magnitude in its column of the saved file. A column's largest magnitude is its
/// scale: a value near zero (θ crossing zero, an angular velocity at a turning point) carries the
/// rounding of the column's large values, not of its own size.
const MOTION: f64 = 1e-8;

/// The same for the columns that come from the body's elastic deformation.
const ELASTIC: f64 = 1e-6;

/// The columns of [`ELASTIC`].
const ELASTIC_COLUMNS: [&str; 4] = ["strain_J", "von_mises_max_Pa", "hinge_fx_N", "hinge_fy_N"];

/// Columns that count impacts and contact events: equal.
const COUNTS: [&str; 3] = ["impacts", "contact_count", "impact"];

/// The runs of `scripts/same-outputs`, by the names of their folders in `tests/same-outputs/`.
const RUNS: [&str; 8] = [
    "default",
    "rigid-wall",
    "deformable-wall",
    "torque",
    "restart",
    "reduced",
    "reduced-rigid-wall",
    "reduced-fmu",
];

fn saved() -> PathBuf {
    common::root().join("tests/same-outputs")
}

/// `pendulum-fem run -q` with `args` and the pictures off.
fn cli(args: &[&str]) {
    let mut cmd = common::bin();
    cmd.args(["run", "-q"]).args(args);
    for key in ["plots", "animation", "paraview", "viewer"] {
        cmd.args(["--set", &format!("output.{key}=false")]);
    }
    common::python::run(&mut cmd, &format!("pendulum-fem run {args:?}"));
}

/// Makes the run `name` as the script does into `dir/name` and returns that folder.
fn make(name: &str, dir: &Path) -> PathBuf {
    let out = dir.join(name);
    let o = out.to_str().expect("a UTF-8 path");
    match name {
        "default" => cli(&["--out", o]),
        "rigid-wall" => cli(&["--out", o, "--set", "wall.kind=rigid"]),
        "deformable-wall" => cli(&["--out", o, "--set", "wall.kind=deformable"]),
        "torque" => cli(&[
            "--out",
            o,
            "--set",
            "torque.profile=sine",
            "--set",
            "torque.amplitude=0.5",
            "--set",
            "torque.frequency=2",
            "--set",
            "wall.kind=rigid",
        ]),
        "restart" => {
            cli(&[
                "--out",
                o,
                "--set",
                "wall.kind=rigid",
                "--set",
                "time.end=0.5",
                "--checkpoint-every",
                "10",
            ]);
            let mut cmd = common::bin();
            cmd.args(["run", "-q", "--restart", o, "--set", "time.end=1"]);
            common::python::run(&mut cmd, "pendulum-fem run --restart");
        }
        "reduced" => cli(&["--out", o, "--set", "model.kind=reduced"]),
        "reduced-rigid-wall" => cli(&["--out", o, "--set", "model.kind=reduced", "--set", "wall.kind=rigid"]),
        "reduced-fmu" => {
            std::fs::create_dir_all(&out).unwrap();
            let python = common::python::test_env_python(common::root());
            let fmu = common::python::pack_fmu(dir);
            let script = common::root().join("crates/fmu/tests/python/simulate_to_csv.py");
            let mut cmd = std::process::Command::new(python);
            cmd.arg(script)
                .arg(fmu)
                .arg(out.join("outputs.csv"))
                .args(["1", "0.01", "model_kind=1", "wall_kind=1"]);
            common::python::run(&mut cmd, "simulate_to_csv.py");
        }
        other => panic!("no run named {other}"),
    }
    out
}

/// The CSV files of a folder, by name.
fn csv_files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".csv"))
        .collect();
    names.sort();
    names
}

/// The differences of `now` from `saved` (both CSV texts with a header), at most a few per
/// column: `label` names the file.
fn differences(label: &str, saved: &str, now: &str) -> Vec<String> {
    let rows = |text: &str| -> Vec<Vec<String>> {
        text.lines()
            .map(|l| l.split(',').map(str::to_string).collect())
            .collect()
    };
    let (saved, now) = (rows(saved), rows(now));
    if saved.first() != now.first() {
        return vec![format!("{label}: columns {:?}, saved {:?}", now.first(), saved.first())];
    }
    if saved.len() != now.len() {
        return vec![format!("{label}: {} rows, saved {}", now.len() - 1, saved.len() - 1)];
    }
    let header = &saved[0];
    let mut found = Vec::new();
    for (c, name) in header.iter().enumerate() {
        let numbers: Vec<Option<f64>> = saved[1..].iter().map(|r| r[c].parse::<f64>().ok()).collect();
        // 0 for a column of texts; a NaN saved fails here
        let scale = numbers.iter().flatten().map(|v| v.abs()).chain([0.0]).max_of();
        let mut in_column = 0;
        for (k, (s, n)) in saved[1..].iter().zip(&now[1..]).enumerate() {
            let (s, n) = (&s[c], &n[c]);
            // a NaN fails: no comparison with it holds
            let same = match (s.parse::<f64>(), n.parse::<f64>()) {
                (Ok(a), Ok(b)) if COUNTS.contains(&name.as_str()) => a == b,
                (Ok(a), Ok(b)) if name == "newton_iterations" => (b - a).abs() <= 1.0,
                (Ok(a), Ok(b)) if ELASTIC_COLUMNS.contains(&name.as_str()) => (b - a).abs() <= ELASTIC * scale,
                (Ok(a), Ok(b)) => (b - a).abs() <= MOTION * scale,
                _ => s == n,
            };
            if !same {
                in_column += 1;
                if in_column <= 3 {
                    found.push(format!(
                        "{label} row {}: {name} = {n}, saved {s} (column scale {scale:e})",
                        k + 1
                    ));
                }
            }
        }
        if in_column > 3 {
            found.push(format!("{label}: {name} differs in {in_column} rows"));
        }
    }
    found
}

#[test]
fn the_saved_runs_are_exactly_the_runs_of_the_script() {
    let mut folders: Vec<String> = std::fs::read_dir(saved())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    folders.sort();
    let mut runs = RUNS.map(String::from).to_vec();
    runs.sort();
    assert_eq!(folders, runs, "tests/same-outputs/ against the runs this test makes");
    let script = std::fs::read_to_string(common::root().join("scripts/same-outputs")).unwrap();
    let listed = format!("runs=({})", RUNS.join(" "));
    assert!(
        script.contains(&listed),
        "scripts/same-outputs does not list `{listed}`"
    );
}

#[test]
fn the_runs_of_scripts_same_outputs_write_the_saved_values_to_1e_8_of_the_motion_and_1e_6_of_the_strain() {
    let dir = common::scratch("runs");
    let mut found = Vec::new();
    for name in RUNS {
        let out = make(name, &dir);
        let files = csv_files(&saved().join(name));
        assert!(!files.is_empty(), "{name}: no saved CSV file");
        assert_eq!(csv_files(&out), files, "{name}: the files written");
        for file in files {
            let read = |p: PathBuf| std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            found.extend(differences(
                &format!("{name}/{file}"),
                &read(saved().join(name).join(&file)),
                &read(out.join(&file)),
            ));
        }
    }
    assert!(
        found.is_empty(),
        "{} differences from tests/same-outputs/ (tolerances {MOTION:e} and, elastic, {ELASTIC:e} of the column's largest value):\n{}",
        found.len(),
        found.join("\n")
    );
    let _ = std::fs::remove_dir_all(&dir);
}
