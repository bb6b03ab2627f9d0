//! The FMI 3.0 FMU `PendulumFem3` through its C ABI, driven by fmpy in the test environment of
//! `scripts/test-env` (one Python script per claim under `tests/python/`, each printing its
//! figures as one JSON line; a missing environment fails the tests with the reason, it never skips
//! them). The FMUs are packed from the shared object cargo built next to this test, as
//! `cargo xtask fmu --fmi 3` packs it; the impact references are the CLI's `events.csv`.

use crate::common;
use common::{cli_run, fmu, fmu3, run_script};

/// θ at 20° in radians: the FMU's default `theta_start` (the CLI's `initial.angle_deg = 20`).
const THETA_START: f64 = 0.3490658503988659;

/// The wall runs' end: two impacts and the swings after them.
const STOP_TIME: f64 = 1.0;

#[test]
fn fmi3_fmu_validates_and_returns_early_at_each_impact_within_a_microsecond_of_the_cli() {
    // the CLI's own settings (no torque term), as `pendulum-fem run --set wall.kind="rigid"` runs
    let angle = format!("initial.angle_deg={:?}", THETA_START.to_degrees());
    let sets = [angle, format!("time.end={STOP_TIME:?}"), "wall.kind=\"rigid\"".into()];
    let events = cli_run("fmi3_cli_wall", &sets).join("events.csv");
    run_script(
        "fmi3_wall_events.py",
        &[
            fmu().display().to_string(),
            fmu3().display().to_string(),
            events.display().to_string(),
            format!("{STOP_TIME:?}"),
        ],
    );
}

#[test]
fn fmi3_state_get_set_and_serialise_replay_bit_identically_across_an_early_return() {
    run_script("fmi3_state.py", &[fmu3().display().to_string()]);
}

#[test]
fn fmi3_functions_not_offered_answer_fmi3error_and_log_the_reason() {
    run_script("fmi3_errors.py", &[fmu3().display().to_string()]);
}
