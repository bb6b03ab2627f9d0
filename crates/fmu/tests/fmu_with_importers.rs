//! The packaged FMU driven by real importers, in the test environment of `scripts/test-env`
//! (fmpy, libcosimpy, syssimx): one Python script per claim under `tests/python/`, each printing
//! its figures as one JSON line. A missing Python environment fails the tests with the reason; it
//! never skips them.
//!
//! The FMU is packed from the shared object that cargo built next to this test
//! (`libpendulum_fem_fmu.so`), with [`pendulum_fem_fmu::package::write_fmu`], as `cargo xtask fmu`
//! does. The references are the files of the CLI binary itself (`pendulum-fem run`, built beside
//! these tests), stepped by its own step plan.

use pendulum_fem_core::{Config, Simulation};

use crate::common;
use common::{cli_run, fmu, run_script};

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
    let sim = Simulation::build(&cfg).expect("model").simulation;
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
