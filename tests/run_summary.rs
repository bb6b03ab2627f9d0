//! The run summary's energy error and the divergence watchdog: the error is
//! `max |ΔE − W_torque| / scale` with a scale that is never near zero, and a run whose error
//! exceeds `output.energy_watchdog` stops with an error naming the time and the energies.

use crate::common;
use common::Extremes;

use std::path::PathBuf;

use pendulum_fem::commands::run::{run, EnergyAudit, RunOptions, RunSummary};
use pendulum_fem::simulation::Model;
use pendulum_fem::store::Table;
use pendulum_fem::{mesh, Config};

fn out_dir(name: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("summary-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn config(sets: &[&str]) -> Config {
    let mut all: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    for off in ["plots", "animation", "paraview", "viewer"] {
        all.push(format!("output.{off}=false"));
    }
    Config::load(None, &all).unwrap()
}

fn run_into(name: &str, config: Config) -> (Result<RunSummary, pendulum_fem::Error>, PathBuf) {
    let dir = out_dir(name);
    let opts = RunOptions {
        config,
        out: Some(dir.clone()),
        observers: vec![pendulum_fem::render::pictures::attach()],
        ..Default::default()
    };
    (run(&opts), dir)
}

/// `(max |ΔE − W|, scale)` recomputed from `results.csv` by the definition in [`EnergyAudit`]: the
/// scale is the available energy, the initial kinetic energy plus the weight times the centroid's
/// possible height change `m g (d + |h₀|)` plus the largest |W|, at least the floor.
fn energy_error_from_csv(dir: &std::path::Path, cfg: &Config) -> (f64, f64) {
    let (names, rows) = Table::read(&dir.join("results.csv"))
        .map(|t| (t.names, t.rows))
        .unwrap();
    let col = |n: &str| names.iter().position(|c| c == n).unwrap();
    let (k, e, w) = (col("kinetic_J"), col("total_J"), col("torque_work_J"));
    let model = Model::new(cfg, mesh::generate(cfg).unwrap()).unwrap();
    let floor = 1e-3 * model.mass_kg() * 9.81 * model.length_scale();
    let first = &rows[0];
    let largest_work = rows.iter().map(|r| r[w].abs()).max_of();
    let scale = floor.max(first[k] + model.potential_range() + largest_work);
    let defect = rows.iter().map(|r| (r[e] - first[e] - r[w]).abs()).max_of();
    (defect, scale)
}

#[test]
fn with_a_torque_the_energy_error_is_the_energy_change_minus_the_torque_work_over_the_scale() {
    let cfg = config(&["torque.profile=constant", "torque.amplitude=0.5", "time.end=0.5"]);
    let (summary, dir) = run_into("torque", cfg.clone());
    let summary = summary.unwrap();
    let (defect, scale) = energy_error_from_csv(&dir, &cfg);
    // the same numbers in the same order: equal up to rounding of the final division
    assert!(
        (summary.energy_scale - scale).abs() <= 1e-15 * scale,
        "{} vs {scale}",
        summary.energy_scale
    );
    assert!(
        (summary.energy_error - defect / scale).abs() <= 1e-12 * (defect / scale),
        "{} vs {}",
        summary.energy_error,
        defect / scale
    );
    // the torque did work of the order of the kinetic energy, and the balance holds to 1e-4;
    // ignoring the work would give an error of order 1
    assert!(summary.energy_error < 1e-4, "energy error {:.3e}", summary.energy_error);
}

/// A step torque switching on exactly at a step's start (0.7 N·m at 0.4954 s, `time.dt` =
/// 4.954e-3 s, on the tutorial's pendulum): the step's dynamics and the torque's work must both
/// take the torque as on from that start. A start time recomputed as `(t₀ + Δt) − Δt`, a rounding
/// below `t₀`, would count the torque off in the work while the dynamics had it on: half a step's
/// work of the torque, far above the bar of 1e-9.
#[test]
fn a_step_torque_switching_on_at_a_step_start_keeps_the_energy_balanced() {
    let cfg = config(&[
        "torque.profile=step",
        "torque.amplitude=0.7",
        "torque.start=0.4954",
        "time.dt=4.954e-3",
        "time.end=0.52",
    ]);
    let (summary, _) = run_into("step-torque", cfg);
    let summary = summary.unwrap();
    // the solver's tolerance per step, far below the half step's work of the torque a wrong start
    // time would leave
    assert!(summary.energy_error < 1e-9, "energy error {:.3e}", summary.energy_error);
}

#[test]
fn without_gravity_the_energy_error_is_finite_and_small() {
    for (name, sets) in [
        (
            "g0-torque",
            &[
                "gravity.g=0",
                "torque.profile=constant",
                "torque.amplitude=0.05",
                "time.end=0.5",
            ][..],
        ),
        ("g0-rest", &["gravity.g=0", "time.end=0.2"][..]),
    ] {
        let cfg = config(sets);
        let (summary, dir) = run_into(name, cfg.clone());
        let summary = summary.unwrap();
        let (defect, scale) = energy_error_from_csv(&dir, &cfg);
        assert!((summary.energy_error - defect / scale).abs() <= 1e-12 * (defect / scale).max(1e-300));
        // the floor (1e-3 m g0 L, about 3.2e-3 J here) keeps the scale away from zero
        assert!(summary.energy_scale >= 3e-3, "{name}: scale {}", summary.energy_scale);
        assert!(
            summary.energy_error.is_finite() && summary.energy_error < 1e-4,
            "{name}: energy error {:.3e}",
            summary.energy_error
        );
    }
}

#[test]
fn the_energy_scale_floor_is_a_thousandth_of_lifting_the_body_by_its_length() {
    let cfg = config(&["gravity.g=0"]);
    let model = Model::new(&cfg, mesh::generate(&cfg).unwrap()).unwrap();
    let floor = model.energy_floor();
    assert_eq!(floor, 1e-3 * model.mass_kg() * 9.81 * model.length_scale());
    // without gravity there is no potential to fall through: the floor is the scale
    assert_eq!(model.potential_range(), 0.0);
    let audit = EnergyAudit::of(&model);
    assert_eq!((audit.scale(), audit.error()), (floor, 0.0), "before any record");
}

#[test]
fn the_energy_scale_is_the_available_energy_from_the_first_step_on() {
    // the tutorial's pendulum at 20°: d = 0.18165 m, m = 1.0843 kg; the centroid can move from
    // h₀ = −d cos 20° up to +d, so m g (d + d cos 20°) (the exact rigid values of
    // tests/data/README.md; the mesh's area and first moment agree to 5e-7, hence 1e-5)
    let cfg = Config::default();
    let model = Model::new(&cfg, mesh::generate(&cfg).unwrap()).unwrap();
    let (m, d) = (common::exact::MASS, common::exact::CENTROID_DISTANCE);
    let exact = m * 9.81 * d * (1.0 + 20f64.to_radians().cos());
    assert!(
        (model.potential_range() - exact).abs() < 1e-5 * exact,
        "{} vs {exact}",
        model.potential_range()
    );
    let audit = EnergyAudit::of(&model);
    assert_eq!(audit.scale(), model.potential_range(), "before any record");
}

#[test]
fn the_watchdog_stops_a_run_whose_energy_error_exceeds_the_limit_naming_time_energies_and_a_hint() {
    // The trapezoidal rule's error on the default swing grows to 2e-4 of its scale (the default
    // energy-momentum scheme's stays near 1e-10); a limit of 1e-6 must trip early.
    let cfg = config(&["output.energy_watchdog=1e-6", "time.scheme=\"trapezoidal\""]);
    let (result, dir) = run_into("watchdog", cfg);
    let err = result.unwrap_err().to_string();
    for needle in ["t = ", "energy error", "output.energy_watchdog", "kinetic", "time.dt"] {
        assert!(err.contains(needle), "`{needle}` missing in: {err}");
    }
    let status = pendulum_fem::run::status::RunStatus::read(&dir.join("status.json")).unwrap();
    assert_eq!(status.status, "failed");
    let step = status.step.unwrap();
    assert!(step > 0 && step < 100, "stopped at step {step}");
    assert!(err.contains(&format!("step {step},")), "{err}");
    // and the default limit lets the same run finish
    let (ok, _) = run_into("watchdog-default", config(&[]));
    assert!(ok.unwrap().energy_error < 0.01);
}

#[test]
fn the_largest_von_mises_of_csv_and_summary_is_the_largest_value_of_the_frames_field() {
    use pendulum_fem::commands::run::run_with;
    let cfg = config(&["time.end=0.3"]);
    let dir = out_dir("von-mises");
    std::fs::create_dir_all(&dir).unwrap();
    let opts = RunOptions {
        config: cfg,
        out: Some(dir.clone()),
        ..Default::default()
    };
    let mut largest_shown = 0.0f64;
    let summary = run_with(&opts, dir, |sim, record| {
        // the nodal field the frames (ParaView, animations, viewer) are made of
        let shown = sim
            .model
            .nodal_stress(sim.displacement())
            .von_mises
            .iter()
            .copied()
            .max_of();
        assert_eq!(record.von_mises_max, shown, "step {}", record.step);
        largest_shown = [largest_shown, shown].into_iter().max_of();
        Ok(())
    })
    .unwrap();
    assert_eq!(summary.von_mises_max, largest_shown);
    // the default swing's largest stress, where the rod meets the ring (docs/src/outputs.md)
    assert!((8e4..1e5).contains(&largest_shown), "{largest_shown:.4e} Pa");
}

#[test]
fn a_time_end_off_the_dt_grid_ends_with_one_shorter_step() {
    use pendulum_fem::commands::run::StepPlan;
    let plan = |end: f64, dt: f64| {
        let mut t = Config::default().time;
        (t.end, t.dt) = (end, dt);
        StepPlan::of(&t)
    };
    assert_eq!(plan(1.0, 0.01), StepPlan { full: 100, last: None });
    // 0.3 / 0.1 = 2.9999999999999996 in floating point: on the grid
    assert_eq!(plan(0.3, 0.1), StepPlan { full: 3, last: None });
    let p = plan(0.015, 0.01);
    assert_eq!((p.full, p.steps()), (1, 2));
    assert!((p.last.unwrap() - 0.005).abs() < 1e-15);
}

#[test]
fn a_run_to_an_off_grid_end_lands_on_it_and_says_so() {
    let (summary, dir) = run_into("off-grid", config(&["time.end=0.015"]));
    let summary = summary.unwrap();
    assert_eq!(summary.steps, 2);
    assert_eq!(summary.time_reached, 0.015, "exactly time.end");
    assert!((summary.last_step.unwrap() - 0.005).abs() < 1e-15);
    let (_, rows) = Table::read(&dir.join("results.csv"))
        .map(|t| (t.names, t.rows))
        .unwrap();
    let times: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    assert_eq!(times, [0.0, 0.01, 0.015]);
    // the same instant with dt = 0.005 throughout: the two differ by the integrator's
    // second-order error, below 5e-6 rad; a step of the wrong length would be above it
    let (fine, dir_fine) = run_into("off-grid-fine", config(&["time.end=0.015", "time.dt=0.005"]));
    assert_eq!(fine.unwrap().last_step, None);
    let (_, fine_rows) = Table::read(&dir_fine.join("results.csv"))
        .map(|t| (t.names, t.rows))
        .unwrap();
    let (a, b) = (rows.last().unwrap()[1], fine_rows.last().unwrap()[1]);
    assert!((a - b).abs() < 5e-6, "theta {a} vs {b}");
}

#[test]
fn with_every_seven_the_last_step_is_still_written() {
    let mut cfg = config(&["time.end=0.1", "output.every=7"]);
    cfg.output.paraview = true;
    let (summary, dir) = run_into("every7", cfg);
    summary.unwrap();
    let pvd = std::fs::read_to_string(dir.join("pendulum.pvd")).unwrap();
    let files: Vec<&str> = pvd
        .lines()
        .filter_map(|l| l.split("file=\"").nth(1))
        .map(|f| f.trim_end_matches("\"/>"))
        .collect();
    assert_eq!(
        files,
        [
            "frames/step_00000.vtu",
            "frames/step_00007.vtu",
            "frames/step_00010.vtu"
        ]
    );
}

#[test]
fn a_restarted_run_reports_the_impacts_and_the_largest_contact_force_of_the_uninterrupted_run() {
    // the rigid wall: the first impact at about 0.24 s, its rebound before the checkpoint at 0.5 s
    let cfg = config(&["wall.kind=\"rigid\""]);
    let (whole, _) = run_into("restart-whole", cfg.clone());
    let whole = whole.unwrap();
    let mut first = cfg.clone();
    first.time.end = 0.5;
    let dir = out_dir("restart-part");
    let opts = RunOptions {
        config: first,
        out: Some(dir.clone()),
        checkpoint_every: Some(10),
        ..Default::default()
    };
    run(&opts).unwrap();
    let restarted = run(&RunOptions {
        config: cfg,
        out: Some(dir),
        restart: true,
        ..Default::default()
    })
    .unwrap();
    let (a, b) = (whole.impacts.unwrap(), restarted.impacts.unwrap());
    assert!(a.count >= 2, "{a:?}");
    // the same records and events in the same order: the same figures, bit for bit
    assert_eq!(a, b);
    assert_eq!(whole.contact, restarted.contact);
}
