//! The reduced body (`model.kind = "reduced"`, a floating frame with elastic modes) through the
//! command line's run driver (with its watchdog), against exact rigid rotation and against the
//! full model.
//!
//! Tolerances: the claims the reduced body's rule makes exactly (a free spin in its relative
//! equilibrium, the angular momentum under a torque, the energy) to 1e-9, the solver's tolerance
//! (1e-12 of the velocities per step) accumulated over a thousand steps with margin; the comparisons
//! with the full model at the bars of issue 20, which the measured differences (in the asserts'
//! messages) meet with a margin of 1.5 to 60.

use std::path::{Path, PathBuf};
use std::process::Command;

const QUIET: [&str; 8] = [
    "--set",
    "output.plots=false",
    "--set",
    "output.animation=false",
    "--set",
    "output.paraview=false",
    "--set",
    "output.viewer=false",
];

fn out_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pendulum-fem-reduced-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Runs the CLI with `sets` (`key=value`) into a fresh folder and returns it.
fn run(name: &str, sets: &[&str]) -> PathBuf {
    let dir = out_dir(name);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_pendulum-fem"));
    cmd.arg("run").args(QUIET).arg("-o").arg(&dir);
    for s in sets {
        cmd.arg("--set").arg(s);
    }
    let out = cmd.output().expect("the CLI runs");
    assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
    dir
}

/// The columns of a CSV file by name.
fn columns(path: &Path) -> std::collections::HashMap<String, Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().expect("a header").split(',').map(String::from).collect();
    let mut cols: std::collections::HashMap<String, Vec<f64>> =
        header.iter().map(|h| (h.clone(), Vec::new())).collect();
    for line in lines {
        for (h, v) in header.iter().zip(line.split(',')) {
            if let Ok(x) = v.parse::<f64>() {
                cols.get_mut(h).expect("a column").push(x);
            }
        }
    }
    cols
}

fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

fn largest(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

#[test]
fn a_free_spin_of_the_reduced_body_advances_at_exactly_its_rate_and_keeps_energy_and_momentum() {
    let dir = run(
        "spin",
        &[
            "model.kind=reduced",
            "gravity.g=0",
            "initial.angular_velocity=30",
            "time.dt=0.01",
            "time.end=10",
        ],
    );
    let c = columns(&dir.join("results.csv"));
    let (t, theta) = (&c["time_s"], &c["theta_rad"]);
    let worst = t
        .iter()
        .zip(theta)
        .skip(1)
        .map(|(t, th)| ((th - theta[0]) - 30.0 * t).abs() / (30.0 * t))
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "θ − θ₀ against 30 t: {worst:e} relative");
    for key in ["total_J", "angular_momentum_kg_m2_s"] {
        let v = &c[key];
        let drift = largest(&v.iter().map(|x| x - v[0]).collect::<Vec<_>>()) / v[0].abs();
        assert!(drift < 1e-9, "{key} drifts by {drift:e} relative");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_constant_torque_spins_the_reduced_body_up_with_its_momentum_and_energy_exact_and_no_phase_error() {
    let sets = |dt: &'static str| {
        [
            "model.kind=reduced",
            "gravity.g=0",
            "torque.profile=constant",
            "torque.amplitude=1",
            dt,
            "time.end=1.5",
        ]
    };
    let coarse = run("spinup", &sets("time.dt=0.01"));
    let c = columns(&coarse.join("results.csv"));
    let (t, l) = (&c["time_s"], &c["angular_momentum_kg_m2_s"]);
    // p_θ changes by exactly h M per step
    let worst = t
        .iter()
        .zip(l)
        .skip(1)
        .map(|(t, l)| (l - t).abs() / t)
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "L(t) against M t: {worst:e} relative");
    let balance = c["total_J"]
        .iter()
        .zip(&c["torque_work_J"])
        .map(|(e, w)| (e - c["total_J"][0] - w).abs())
        .fold(0.0, f64::max)
        / largest(&c["torque_work_J"]);
    assert!(balance < 1e-9, "energy less the torque's work: {balance:e} of the work");
    // the rotation carries no phase error from the scheme: a ten times finer step turns it by the
    // same angle to 1e-6 (the displacement-based full model lags by (ω Δt)²/18 = 0.63 % here).
    // Against ½ (M/I₀) t² the flexible body lags by 3.3e-6: its centrifugal stretch raises I.
    let fine = run("spinup-fine", &sets("time.dt=0.001"));
    let f = columns(&fine.join("results.csv"));
    let (a, b) = (
        c["theta_rad"].last().unwrap() - c["theta_rad"][0],
        f["theta_rad"].last().unwrap() - f["theta_rad"][0],
    );
    assert!((a - b).abs() / b < 1e-6, "θ(1.5 s) at dt = 0.01: {a}, at 0.001: {b}");
    let inertia = 1.0 / c["alpha_rad_s2"][0];
    let rigid = 0.5 * 1.5 * 1.5 / inertia;
    let lag = (rigid - b) / rigid;
    assert!(
        lag > 0.0 && lag < 1e-5,
        "θ(1.5 s) = {b} against the rigid {rigid}: {lag:e}"
    );
    let _ = std::fs::remove_dir_all(&coarse);
    let _ = std::fs::remove_dir_all(&fine);
}

#[test]
fn the_reduced_steel_swing_follows_the_full_model_in_angle_hinge_force_and_stress() {
    let sets = ["time.dt=0.001", "time.end=5"];
    let full = run("steel-full", &sets);
    let reduced = run("steel-reduced", &[sets[0], sets[1], "model.kind=reduced"]);
    let (f, r) = (
        columns(&full.join("results.csv")),
        columns(&reduced.join("results.csv")),
    );
    let d_theta = largest_difference(&f["theta_rad"], &r["theta_rad"]);
    assert!(d_theta < 1e-5, "θ differs by {d_theta:e} rad");
    let scale = largest(&f["hinge_fy_N"]).max(largest(&f["hinge_fx_N"]));
    for key in ["hinge_fx_N", "hinge_fy_N"] {
        let d = largest_difference(&f[key], &r[key]) / scale;
        assert!(d < 1e-5, "{key} differs by {d:e} of the largest hinge force");
    }
    let d_vm = largest_difference(&f["von_mises_max_Pa"], &r["von_mises_max_Pa"]) / largest(&f["von_mises_max_Pa"]);
    assert!(d_vm < 0.01, "the largest von Mises stress differs by {d_vm:e}");
    let _ = std::fs::remove_dir_all(&full);
    let _ = std::fs::remove_dir_all(&reduced);
}

#[test]
fn the_reduced_body_strikes_the_rigid_wall_as_the_full_model_does() {
    let sets = ["wall.kind=rigid", "time.dt=0.01", "time.end=1.5"];
    let full = run("wall-full", &sets);
    let reduced = run("wall-reduced", &[sets[0], sets[1], sets[2], "model.kind=reduced"]);
    let events = |dir: &Path| {
        std::fs::read_to_string(dir.join("events.csv"))
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                (f[1].to_string(), f[0].parse::<f64>().unwrap())
            })
            .collect::<Vec<_>>()
    };
    let (ef, er) = (events(&full), events(&reduced));
    assert_eq!(ef.len(), er.len(), "{ef:?} against {er:?}");
    assert!(ef.len() >= 6, "three impacts: {ef:?}");
    for ((kf, tf), (kr, tr)) in ef.iter().zip(&er) {
        assert_eq!(kf, kr);
        assert!((tf - tr).abs() < 1e-4, "{kf} at {tf} s (full) and {tr} s (reduced)");
    }
    // the first rebound: the largest angle after the first impact's end
    let rebound = |dir: &Path, end: f64| {
        let c = columns(&dir.join("results.csv"));
        c["time_s"]
            .iter()
            .zip(&c["theta_rad"])
            .filter(|(t, _)| **t > end && **t < end + 0.5)
            .map(|(_, th)| *th)
            .fold(f64::NEG_INFINITY, f64::max)
            .to_degrees()
    };
    let (rf, rr) = (rebound(&full, ef[1].1), rebound(&reduced, er[1].1));
    assert!(
        (rf - rr).abs() < 0.005,
        "first rebound {rf}° (full) and {rr}° (reduced)"
    );
    let c = columns(&reduced.join("results.csv"));
    let balance =
        largest(&c["total_J"].iter().map(|e| e - c["total_J"][0]).collect::<Vec<_>>()) / c["total_J"][0].abs();
    assert!(
        balance < 1e-8,
        "the reduced body's energy drifts by {balance:e} relative"
    );
    let _ = std::fs::remove_dir_all(&full);
    let _ = std::fs::remove_dir_all(&reduced);
}

#[test]
fn a_reduced_run_stopped_and_restarted_from_its_snapshot_replays_bit_for_bit() {
    use pendulum_fem::{Config, Simulation, Snapshot};
    let mut cfg = Config::default();
    cfg.model.kind = pendulum_fem::config::ModelKind::Reduced;
    cfg.wall.kind = pendulum_fem::config::WallKind::Rigid;
    let mesh = pendulum_fem::mesh::generate(&cfg).unwrap();
    let mut a = Simulation::from_config(&cfg, mesh.clone()).unwrap();
    let mut b = Simulation::from_config(&cfg, mesh).unwrap();
    for _ in 0..20 {
        a.step(0.01).unwrap();
    }
    let bytes = a.snapshot().to_bytes();
    b.restore(&Snapshot::from_bytes(&bytes, "memory").unwrap()).unwrap();
    for _ in 0..10 {
        a.step(0.01).unwrap();
        b.step(0.01).unwrap();
    }
    assert_eq!(a.reduced_state(), b.reduced_state());
    assert_eq!(a.theta().to_bits(), b.theta().to_bits());
    assert_eq!(a.hinge_reaction(), b.hinge_reaction());
}

#[test]
fn the_reduced_body_refuses_a_deformable_wall_naming_the_keys() {
    let dir = out_dir("refused");
    let out = Command::new(env!("CARGO_BIN_EXE_pendulum-fem"))
        .arg("run")
        .args(QUIET)
        .args(["--set", "model.kind=reduced", "--set", "wall.kind=deformable", "-o"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let msg = String::from_utf8_lossy(&out.stderr);
    assert!(
        msg.contains("model.kind = \"reduced\"") && msg.contains("wall.kind = \"deformable\""),
        "{msg}"
    );
    assert!(!dir.join("results.csv").exists(), "nothing written");
}
