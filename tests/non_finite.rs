//! NaN and infinity stop a run, through the command line: the error names the step, its time and
//! the quantity and says what to try, the exit is non-zero, `status.json` says failed, and no row
//! of `results.csv` and no frame holds a NaN or an infinity; the rows before stay as computed.
//! Both runs have finite configurations, which the validation accepts: the non-finite numbers
//! come from the arithmetic of the run.

use crate::common;

use std::path::Path;
use std::process::Output;

use pendulum_fem::run::status::RunStatus;
use pendulum_fem::Config;

/// `pendulum-fem run` into `out` with `--set` of each of `sets`.
fn run(out: &Path, sets: &[String]) -> Output {
    let mut cmd = common::bin();
    cmd.args(["run", "--quiet", "--out"]).arg(out).args(common::NO_PICTURES);
    for set in sets {
        cmd.args(["--set", set]);
    }
    cmd.output().unwrap()
}

/// The rows of a `results.csv` as numbers (a NaN or an infinity parses as one).
fn rows(path: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .skip(1)
        .map(|line| line.split(',').map(|v| v.parse::<f64>().unwrap()).collect())
        .collect()
}

#[test]
fn a_nan_kinetic_energy_at_the_start_stops_the_run_naming_step_time_and_quantity_watchdog_or_not() {
    for watchdog in ["0.01", "0"] {
        let out = common::scratch("start").join("out");
        // finite, so valid; its square in the kinetic energy is not. The zero start takes the
        // state as it is (no equilibrium is solved for it), so nothing fails before the records.
        let o = run(
            &out,
            &[
                "initial.angular_velocity=1e200".into(),
                "initial.acceleration=\"zero\"".into(),
                "time.end=0.05".into(),
                format!("output.energy_watchdog={watchdog}"),
            ],
        );
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "watchdog {watchdog}: {stderr}");
        assert!(
            stderr.contains("step 0 (t = 0.000000 s): the kinetic energy is NaN"),
            "watchdog {watchdog}: {stderr}"
        );
        assert!(stderr.contains("Try a smaller time.dt"), "what to try: {stderr}");
        let status = RunStatus::read(&out.join("status.json")).unwrap();
        assert_eq!((status.status.as_str(), status.step), ("failed", None));
        assert!(status.error.unwrap().contains("the kinetic energy is NaN"));
        // refused at the set-up, before results.csv is opened
        assert!(!out.join("results.csv").exists(), "watchdog {watchdog}");
    }
}

#[test]
fn a_stress_that_overflows_mid_run_stops_it_before_that_steps_row_and_frame() {
    // Density, modulus and the Newton tolerance (an energy) s times steel's: every force, energy
    // and stress is s times steel's and the motion is steel's. At 0.3 s a torque of s N m strains
    // the hub, and the largest von Mises stress, about 1e155 Pa, overflows to infinity.
    let steel = Config::default();
    let s = 7.5e148;
    let scaled = [
        format!("material.density={:e}", steel.material.density * s),
        format!("material.youngs_modulus={:e}", steel.material.youngs_modulus * s),
        format!("solver.tolerance={:e}", steel.solver.tolerance * s),
        "torque.profile=\"step\"".into(),
        "torque.start=0.3".into(),
        format!("torque.amplitude={s:e}"),
        "time.end=0.5".into(),
        // a frame every step: the last one is the last step kept
        "output.every=1".into(),
    ];
    let dir = common::scratch("overflow");
    let out = dir.join("out");
    let o = run(&out, &scaled);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("step 30 (t = 0.300000 s): the largest von Mises stress is inf"),
        "{stderr}"
    );
    let status = RunStatus::read(&out.join("status.json")).unwrap();
    assert_eq!(
        (status.status.as_str(), status.step, status.time_s),
        ("failed", Some(29), Some(0.29))
    );
    // the rows of steps 0 to 29, every value a number
    let kept = rows(&out.join("results.csv"));
    assert_eq!(kept.len(), 30);
    for (step, row) in kept.iter().enumerate() {
        assert!(row.iter().all(|v| v.is_finite()), "step {step}: {row:?}");
    }
    // and the last frame is step 29's: the refused state is in no frame
    let pvd = std::fs::read_to_string(out.join("pendulum.pvd")).unwrap();
    let last = pvd.lines().rfind(|l| l.contains("<DataSet")).unwrap();
    assert!(last.contains("timestep=\"0.29\""), "{last}");
    assert!(out.join("frames/step_00029.vtu").exists() && !out.join("frames/step_00030.vtu").exists());
    // the rows kept are the steel swing's: θ to 1e-9 rad, the rounding of the scaled arithmetic
    // (1.6e-14 rad measured) with room for another CPU's kernels, far below the swing's 0.35 rad
    let reference = dir.join("steel");
    let o = run(&reference, &["time.end=0.29".into()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let steel_rows = rows(&reference.join("results.csv"));
    assert_eq!(steel_rows.len(), kept.len());
    for (a, b) in kept.iter().zip(&steel_rows) {
        assert!((a[1] - b[1]).abs() <= 1e-9, "θ {} against steel's {}", a[1], b[1]);
    }
}
