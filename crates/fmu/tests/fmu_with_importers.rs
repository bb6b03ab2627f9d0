//! The packaged FMU driven by real importers, in the test environment of `scripts/test-env`
//! (fmpy, libcosimpy, syssimx): one Python script per claim under `tests/python/`, each printing
//! its figures as one JSON line. A missing Python environment fails the tests with the reason; it
//! never skips them.
//!
//! The FMU is packed from the shared object that cargo built next to this test
//! (`libpendulum_fem_fmu.so`), with [`pendulum_fem_fmu::package::write_fmu`], as `cargo xtask fmu`
//! does. The references are the files of the CLI binary itself (`pendulum-fem run`, built beside
//! these tests), stepped by its own step plan.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use pendulum_fem_core::{mesh, Config, Simulation};
use pendulum_fem_fmu::package::{write_fmu, LIBRARY_FILE};

fn manifest_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn workspace_root() -> PathBuf {
    manifest_dir()
        .join("../..")
        .canonicalize()
        .expect("the workspace root exists")
}

/// A scratch folder for this test binary's files (next to it; the next run overwrites them).
fn scratch() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable path");
    let dir = exe.parent().expect("deps folder").join("fmu-test");
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// The FMU, packed once per test binary.
fn fmu() -> &'static Path {
    static FMU: OnceLock<PathBuf> = OnceLock::new();
    FMU.get_or_init(|| {
        let exe = std::env::current_exe().expect("test executable path");
        let deps = exe.parent().expect("deps folder");
        let library = [deps.join(LIBRARY_FILE), deps.join("..").join(LIBRARY_FILE)]
            .into_iter()
            .find(|p| p.is_file())
            .unwrap_or_else(|| panic!("{LIBRARY_FILE} not found next to {}", exe.display()));
        let fmu = scratch().join("PendulumFem.fmu");
        write_fmu(&library, &fmu).expect("FMU packed");
        fmu
    })
}

/// The test environment's Python (`scripts/test-env`); panics with its error output if it fails.
fn python() -> &'static Path {
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
fn run_script(script: &str, args: &[String]) -> String {
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
fn cli_binary() -> PathBuf {
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
fn cli_run(name: &str, overrides: &[String]) -> PathBuf {
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

/// θ at 20° in radians: the FMU's default `theta_start` (the CLI's `initial.angle_deg = 20`).
const THETA_START: f64 = 0.3490658503988659;

#[test]
fn fmpy_validates_the_fmu_and_its_simulation_reproduces_the_cli_theta() {
    // theta_start = 0.35 rad is initial.angle_deg = 0.35.to_degrees() for the CLI, as the FMU sets it
    let angle = format!("initial.angle_deg={:?}", 0.35f64.to_degrees());
    let plain = vec![angle.clone(), "time.end=1.0".into()];
    let mut torque = plain.clone();
    torque.extend(["torque.profile=\"constant\"".to_string(), "torque.amplitude=0.0".into()]);
    let cli = cli_run("cli", &plain).join("results.csv");
    let cli_torque = cli_run("cli_zero_torque", &torque).join("results.csv");
    run_script(
        "validate_and_simulate.py",
        &[
            fmu().display().to_string(),
            cli.display().to_string(),
            cli_torque.display().to_string(),
        ],
    );
}

#[test]
fn fmu_state_round_trips_are_bit_identical_and_instances_are_independent() {
    run_script("fmu_state.py", &[fmu().display().to_string()]);
}

#[test]
fn libcosimpy_runs_the_fmu_and_agrees_with_fmpy() {
    run_script("libcosimpy_agrees.py", &[fmu().display().to_string()]);
}

#[test]
fn syssimx_pd_loop_settles_on_the_static_balance_and_rolls_back_exactly() {
    // m and the centre of mass of the default pendulum (the FMU's defaults), from the library
    let cfg = Config::default();
    let sim = Simulation::from_config(&cfg, mesh::generate(&cfg).expect("mesh")).expect("model");
    let p = &sim.model.projection;
    // ∫ r dA / A: the centre of mass hangs at (e, −d) in the reference configuration
    let (e, d) = (p.first_moment[0] / p.area, -p.first_moment[1] / p.area);
    run_script(
        "syssimx_closed_loop.py",
        &[
            fmu().display().to_string(),
            format!("{:?}", sim.model.mass_kg()),
            format!("{d:?}"),
            format!("{e:?}"),
        ],
    );
}

#[test]
fn errors_reach_the_importer_as_fmi2error_with_a_logged_reason() {
    run_script("errors_through_c.py", &[fmu().display().to_string()]);
}

#[test]
fn fmpy_with_the_rigid_wall_reproduces_the_cli_theta_gap_and_impacts() {
    let angle = format!("initial.angle_deg={:?}", THETA_START.to_degrees());
    let plain = vec![angle, "time.end=1.0".into()];
    let plain: Vec<String> = plain.into_iter().chain(["wall.kind=\"rigid\"".to_string()]).collect();
    let mut torque = plain.clone();
    torque.extend(["torque.profile=\"constant\"".to_string(), "torque.amplitude=0.0".into()]);
    let cli = cli_run("cli_wall", &plain).join("results.csv");
    let cli_torque = cli_run("cli_wall_zero_torque", &torque).join("results.csv");
    run_script(
        "wall_simulate.py",
        &[
            fmu().display().to_string(),
            cli.display().to_string(),
            cli_torque.display().to_string(),
        ],
    );
}

#[test]
fn syssimx_hybrid_algorithm_locates_the_wall_impacts_the_cli_reports() {
    // the CLI's own settings (no torque term), as `pendulum-fem run --set wall.kind="rigid"` runs
    let angle = format!("initial.angle_deg={:?}", THETA_START.to_degrees());
    let sets = [angle, "time.end=0.8".into(), "wall.kind=\"rigid\"".into()];
    let events = cli_run("cli_wall_0.8", &sets).join("events.csv");
    run_script(
        "syssimx_wall_impact.py",
        &[fmu().display().to_string(), events.display().to_string()],
    );
}
