//! The reduced body (`model.kind = "reduced"`, a floating frame with elastic modes) through the
//! command line's run driver (with its watchdog), against exact rigid rotation and against the
//! full model.
//!
//! Tolerances: the claims the reduced body's rule makes exactly (a free spin in its relative
//! equilibrium, the angular momentum under a torque, the energy) to 1e-9, the solver's tolerance
//! (1e-12 of the velocities per step) accumulated over a thousand steps with margin; the comparisons
//! with the full model at the bars of issue 20 (the differences found are in the asserts'
//! messages).

use crate::common;
use common::Extremes;

use std::path::{Path, PathBuf};

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

/// Runs the CLI with `sets` (`key=value`) into a fresh folder and returns it.
fn run(name: &str, sets: &[&str]) -> PathBuf {
    let dir = common::scratch(name);
    let mut cmd = common::bin();
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

/// The tutorial pendulum's moment of inertia about the pivot \[kg m²\]: ρ t times the polar moment
/// of its plate, integrated from the configuration's dimensions by `common::exact` (independent of
/// the program's mesh, whose curved edges give an inertia within 1e-7 of it).
fn tutorial_inertia() -> f64 {
    let cfg = pendulum_fem::Config::default();
    let (_, _, polar) = common::exact::plate_moments(&cfg.geometry);
    cfg.material.density * cfg.geometry.thickness * polar
}

fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).max_of()
}

/// The warnings a finished run wrote to its `status.json` (the `warnings` array's strings).
fn warnings(dir: &Path) -> Vec<String> {
    let status: pendulum_fem::commands::run::status::RunStatus =
        pendulum_fem::commands::run::status::RunStatus::read(&dir.join("status.json")).expect("status.json");
    assert_eq!(status.status, "ok", "{}", dir.display());
    status.warnings
}

fn largest(a: &[f64]) -> f64 {
    a.iter().map(|v| v.abs()).max_of()
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
        .max_of();
    assert!(worst < 1e-9, "θ − θ₀ against 30 t: {worst:e} relative");
    for key in ["total_J", "angular_momentum_kg_m2_s"] {
        let drift = relative_drift(&c[key]);
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
    let worst = t.iter().zip(l).skip(1).map(|(t, l)| (l - t).abs() / t).max_of();
    assert!(worst < 1e-9, "L(t) against M t: {worst:e} relative");
    let balance = c["total_J"]
        .iter()
        .zip(&c["torque_work_J"])
        .map(|(e, w)| (e - c["total_J"][0] - w).abs())
        .max_of()
        / largest(&c["torque_work_J"]);
    assert!(balance < 1e-9, "energy less the torque's work: {balance:e} of the work");
    // the rotation carries no phase error from the scheme: a ten times finer step turns it by the
    // same angle to 1e-6 (the displacement-based full model lags by (ω Δt)²/18 = 0.63 % here).
    // Against ½ (M/I₀) t², I₀ the rigid body's exact inertia, the flexible body lags, by less than
    // 1e-5: its centrifugal stretch raises I.
    let fine = run("spinup-fine", &sets("time.dt=0.001"));
    let f = columns(&fine.join("results.csv"));
    let (a, b) = (
        c["theta_rad"].last().unwrap() - c["theta_rad"][0],
        f["theta_rad"].last().unwrap() - f["theta_rad"][0],
    );
    assert!((a - b).abs() / b < 1e-6, "θ(1.5 s) at dt = 0.01: {a}, at 0.001: {b}");
    let rigid = 0.5 * 1.5 * 1.5 / tutorial_inertia();
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
    // steel is where the reduced body applies: its error estimate (8.7e-6) stays far below the bound
    assert!(warnings(&reduced).is_empty(), "{:?}", warnings(&reduced));
    let _ = std::fs::remove_dir_all(&full);
    let _ = std::fs::remove_dir_all(&reduced);
}

/// A run's events: (`event`, `time_s`).
type Events = Vec<(String, f64)>;

/// The CLI's events in a run's `events.csv`.
fn events(dir: &Path) -> Events {
    std::fs::read_to_string(dir.join("events.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[1].to_string(), f[0].parse::<f64>().unwrap())
        })
        .collect()
}

/// The first rebound after an impact that ends at `end`: the largest θ within 0.5 s, on the
/// parabola through the largest sample and its neighbours \[°\].
fn first_rebound(dir: &Path, end: f64) -> f64 {
    let c = columns(&dir.join("results.csv"));
    let (t, th) = (&c["time_s"], &c["theta_rad"]);
    let i = (1..t.len() - 1)
        .filter(|&i| t[i] > end && t[i] < end + 0.5)
        .max_by(|&a, &b| th[a].total_cmp(&th[b]))
        .expect("samples after the impact");
    let (a, b, c) = (th[i - 1], th[i], th[i + 1]);
    let d = (a - c) / (2.0 * (a - 2.0 * b + c));
    (b - 0.25 * (a - c) * d).to_degrees()
}

/// The largest |v − v₀| of a column, relative to |v₀|.
fn relative_drift(v: &[f64]) -> f64 {
    largest(&v.iter().map(|x| x - v[0]).collect::<Vec<_>>()) / v[0].abs()
}

/// The largest relative drift of a run's `total_J`.
fn energy_drift(dir: &Path) -> f64 {
    relative_drift(&columns(&dir.join("results.csv"))["total_J"])
}

/// Runs the full and the reduced model with `sets` and asserts `impacts` impacts in both, each
/// event of the same kind and within `tolerance` \[s\]; returns both folders and their events.
fn same_impacts(name: &str, sets: &[&str], impacts: usize, tolerance: f64) -> (PathBuf, PathBuf, Events, Events) {
    let full = run(&format!("{name}-full"), sets);
    let mut reduced_sets = sets.to_vec();
    reduced_sets.push("model.kind=reduced");
    let reduced = run(&format!("{name}-reduced"), &reduced_sets);
    let (ef, er) = (events(&full), events(&reduced));
    assert_eq!(ef.len(), 2 * impacts, "{impacts} impacts: {ef:?}");
    assert_eq!(ef.len(), er.len(), "{ef:?} against {er:?}");
    for ((kf, tf), (kr, tr)) in ef.iter().zip(&er) {
        assert_eq!(kf, kr);
        println!("{kf}: {tf} s (full), {tr} s (reduced)");
        assert!(
            (tf - tr).abs() < tolerance,
            "{kf} at {tf} s (full) and {tr} s (reduced)"
        );
    }
    (full, reduced, ef, er)
}

/// Runs the full and the reduced model with `sets` to one impact and asserts issue 20's bars for
/// it: the impact's start and end within 0.1 ms, the first rebound within 0.005°, the reduced
/// model's energy within 1e-8 relative; returns both folders.
fn same_first_impact(name: &str, sets: &[&str]) -> (PathBuf, PathBuf) {
    let (full, reduced, ef, er) = same_impacts(name, sets, 1, 1e-4);
    let (rf, rr) = (first_rebound(&full, ef[1].1), first_rebound(&reduced, er[1].1));
    println!("first rebound {rf:.6}° (full) and {rr:.6}° (reduced)");
    assert!(
        (rf - rr).abs() < 0.005,
        "first rebound {rf}° (full) and {rr}° (reduced)"
    );
    let balance = energy_drift(&reduced);
    assert!(
        balance < 1e-8,
        "the reduced model's energy drifts by {balance:e} relative"
    );
    (full, reduced)
}

#[test]
fn the_reduced_body_strikes_the_rigid_wall_as_the_full_model_does() {
    let (full, reduced) = same_first_impact("wall", &["wall.kind=rigid", "time.dt=0.01", "time.end=0.7"]);
    let _ = std::fs::remove_dir_all(&full);
    let _ = std::fs::remove_dir_all(&reduced);
}

#[test]
fn a_soft_reduced_block_warns_that_its_static_modes_miss_the_impact() {
    // E = 0.1 GPa: the impact lasts 2.9 periods of the block's lowest Ritz frequency, fewer than
    // crate::reduced::wall::QUASI_STATIC = 10, so its static modes miss the block's dynamics
    let sets = [
        "wall.kind=deformable",
        "wall.youngs_modulus=1e8",
        "time.end=0.3",
        "model.kind=reduced",
    ];
    let dir = run("soft-block", &sets);
    let w = warnings(&dir);
    assert!(
        w.len() == 1
            && w[0].contains("deformable wall")
            && w[0].contains("2.9 periods")
            && w[0].contains("model.kind = \"full\""),
        "{w:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_stiff_contact_with_the_reduced_block_runs_through_both_impacts_and_keeps_its_energy() {
    // 1e14 N/m³: both impacts, the energy balance at issue 20's 1e-8, and the block's warning
    // (the impact lasts fewer than QUASI_STATIC periods of its lowest frequency)
    let sets = [
        "wall.kind=deformable",
        "contact.stiffness=1e14",
        "time.end=0.8",
        "model.kind=reduced",
    ];
    let dir = run("stiff-block", &sets);
    let ev = events(&dir);
    assert_eq!(ev.len(), 4, "two impacts: {ev:?}");
    let balance = energy_drift(&dir);
    assert!(balance < 1e-8, "the energy drifts by {balance:e} relative");
    assert!(
        warnings(&dir).iter().any(|w| w.contains("deformable wall")),
        "{:?}",
        warnings(&dir)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_reduced_and_the_full_model_converge_to_the_same_impacts_as_the_step_shrinks() {
    // At dt = 0.01 s each swing between impacts carries the midpoint rule's phase error, and the
    // two models' errors differ once the first impact has excited their different high modes;
    // that error falls with dt², and at dt = 2 ms both models' impacts agree to 1e-5 s.
    let (full, reduced, _, _) = same_impacts(
        "wall-fine",
        &["wall.kind=rigid", "time.dt=0.002", "time.end=0.8"],
        2,
        1e-5,
    );
    let _ = std::fs::remove_dir_all(&full);
    let _ = std::fs::remove_dir_all(&reduced);
}

#[test]
fn the_reduced_body_rebounds_from_a_stiff_wall_as_high_as_the_converged_full_model() {
    // 1e14 N/m³: the impact lasts 0.16 ms and leaves about a fifth of the energy in vibration; the
    // full model converges to 17.40° (tests/wall.rs asserts it within 0.3°, as issue 20 asks here)
    let sets = [
        "wall.kind=rigid",
        "contact.stiffness=1e14",
        "time.dt=0.01",
        "time.end=0.7",
        "model.kind=reduced",
    ];
    let dir = run("stiff-wall", &sets);
    let ev = events(&dir);
    assert_eq!(ev[1].0, "impact_end", "{ev:?}");
    let rebound = first_rebound(&dir, ev[1].1);
    println!("stiff wall: first rebound {rebound:.4}° (converged full model 17.40°)");
    assert!((rebound - 17.40).abs() < 0.3, "first rebound {rebound}°");
    let balance = energy_drift(&dir);
    assert!(balance < 1e-8, "the energy drifts by {balance:e} relative");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_reduced_run_stopped_and_restarted_from_its_snapshot_replays_bit_for_bit() {
    use pendulum_fem::config::WallKind;
    use pendulum_fem::{Config, Simulation, Snapshot};
    // stopped at 0.2 s, before the impact at 0.24 s, replayed through it
    for wall in [WallKind::Rigid, WallKind::Deformable] {
        let mut cfg = Config::default();
        cfg.model.kind = pendulum_fem::config::ModelKind::Reduced;
        cfg.wall.kind = wall;
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
        assert_eq!(a.reduced_state(), b.reduced_state(), "{wall:?}");
        assert_eq!(a.theta().to_bits(), b.theta().to_bits(), "{wall:?}");
        assert_eq!(a.hinge_reaction(), b.hinge_reaction(), "{wall:?}");
        assert_eq!(a.energies(), b.energies(), "{wall:?}");
        if wall == WallKind::Deformable {
            assert_eq!(
                a.reduced_state().unwrap().wall_q.len(),
                9,
                "the block's weight and 8 face patches"
            );
            assert!(a.impacts() > 0, "the replay went through the impact");
        }
    }
}

/// The largest von Mises stress of a record, searched among the nodes whose bound can reach it,
/// is the same number, bit for bit, as the largest of every node's value: over a steel swing into
/// the rigid wall (impacts, ringing) and a soft head at 45° (large modal amplitudes), every step.
#[test]
fn the_reduced_largest_von_mises_stress_equals_the_largest_of_all_nodes_bit_for_bit() {
    use pendulum_fem::{Config, Simulation};
    let mut steel = Config::default();
    steel.model.kind = pendulum_fem::config::ModelKind::Reduced;
    steel.wall.kind = pendulum_fem::config::WallKind::Rigid;
    let mut soft = Config::default();
    soft.model.kind = pendulum_fem::config::ModelKind::Reduced;
    (
        soft.material.youngs_modulus,
        soft.material.poisson_ratio,
        soft.material.density,
    ) = (1e6, 0.45, 1000.0);
    soft.initial.angle_deg = 45.0;
    for (name, cfg) in [("steel against the wall", steel), ("soft", soft)] {
        let mesh = pendulum_fem::mesh::generate(&cfg).unwrap();
        let mut sim = Simulation::from_config(&cfg, mesh).unwrap();
        let mut all_steps = Vec::new();
        for step in 0..100 {
            sim.step(0.01).unwrap();
            let searched = sim.von_mises_max();
            let all = sim.nodal_stress().max_von_mises;
            assert_eq!(
                searched.to_bits(),
                all.to_bits(),
                "{name}, step {step}: {searched} Pa against {all} Pa"
            );
            all_steps.push(all);
        }
        let largest = all_steps.into_iter().max_of();
        assert!(largest > 0.0, "{name}: the stresses were all zero");
    }
}

/// A soft pendulum (issue 20's bar 5): E = 1 MPa, ν = 0.45, ρ = 1000 kg/m³, released at 45°.
const SOFT: [&str; 5] = [
    "material.poisson_ratio=0.45",
    "material.density=1000",
    "initial.angle_deg=45",
    "time.end=3",
    "time.dt=0.01",
];

#[test]
fn a_soft_reduced_pendulum_runs_through_and_warns_unless_it_stays_within_a_tenth_of_a_degree() {
    let soft = |e: &str, kind: &str| {
        let mut sets: Vec<String> = SOFT.iter().map(|s| s.to_string()).collect();
        sets.push(format!("material.youngs_modulus={e}"));
        sets.push(format!("model.kind={kind}"));
        let refs: Vec<&str> = sets.iter().map(String::as_str).collect();
        run(&format!("soft-{e}-{kind}"), &refs)
    };
    // E = 1 MPa: the run completes, and either θ stays within 0.1° of the full model's or the
    // error estimate warns
    let (full, reduced) = (soft("1e6", "full"), soft("1e6", "reduced"));
    let d_theta = largest_difference(
        &columns(&full.join("results.csv"))["theta_rad"],
        &columns(&reduced.join("results.csv"))["theta_rad"],
    )
    .to_degrees();
    let warned = warnings(&reduced);
    assert!(
        d_theta <= 0.1 || warned.iter().any(|w| w.contains("does not apply")),
        "θ {d_theta}° off the full model's without a warning"
    );
    assert_eq!(warned.len(), 1, "one warning: {warned:?}");
    // a rubber one (E = 0.1 MPa) always warns
    let rubber = soft("1e5", "reduced");
    let warned = warnings(&rubber);
    assert!(
        warned.len() == 1 && warned[0].contains("model.kind = \"full\""),
        "{warned:?}"
    );
    for dir in [full, reduced, rubber] {
        let _ = std::fs::remove_dir_all(dir);
    }
}

#[test]
fn a_second_reduced_run_reads_its_set_up_from_the_disk_cache_and_writes_the_same_results() {
    let cache = common::scratch("cache");
    let run_in = |cache: &Path, name: &str, sets: &[&str]| {
        let dir = common::scratch(name);
        let mut cmd = common::bin();
        cmd.arg("run")
            .args(QUIET)
            .args(["--set", "model.kind=reduced", "-o"])
            .arg(&dir);
        for s in sets {
            cmd.arg("--set").arg(s);
        }
        let out = cmd.env("PENDULUM_FEM_CACHE", cache).output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        (std::fs::read(dir.join("results.csv")).unwrap(), dir)
    };
    let run_cached = |name: &str| run_in(&cache, name, &[]);
    // the bodies' files (the folder keeps the run's mesh too, `mesh-<key>.bin`)
    let files = || -> Vec<PathBuf> {
        std::fs::read_dir(&cache)
            .map(|d| {
                d.map(|e| e.unwrap().path())
                    .filter(|p| {
                        p.file_name()
                            .is_some_and(|n| n.to_string_lossy().starts_with("reduced-"))
                    })
                    .collect()
            })
            .unwrap_or_default()
    };
    let (first, a) = run_cached("cache-first");
    let written = files();
    assert_eq!(written.len(), 1, "one body file: {written:?}");
    let stamp = std::fs::metadata(&written[0]).unwrap().modified().unwrap();
    let (second, b) = run_cached("cache-second");
    assert_eq!(first, second, "the cached body gives the same results, byte for byte");
    // a run that missed the cache would have written the file anew (a new modification time)
    assert_eq!(
        std::fs::metadata(&written[0]).unwrap().modified().unwrap(),
        stamp,
        "read, not rewritten"
    );
    // a damaged file is computed again and replaced, with the same results
    let mut bytes = std::fs::read(&written[0]).unwrap();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0xff;
    std::fs::write(&written[0], &bytes).unwrap();
    let (third, c) = run_cached("cache-damaged");
    assert_eq!(first, third);
    assert_ne!(
        std::fs::read(&written[0]).unwrap(),
        bytes,
        "the damaged file was replaced"
    );
    // a run with a torque term (its entries in the sparsity pattern change the set-up's rounding)
    // keeps its own body: a run without one, after it in the same cache, still gives `first`
    let other = common::scratch("cache-other");
    let (_, d) = run_in(
        &other,
        "cache-torque",
        &["torque.profile=\"constant\"", "torque.amplitude=0"],
    );
    let (after_torque, e) = run_in(&other, "cache-after-torque", &[]);
    assert_eq!(
        first, after_torque,
        "the results do not depend on which run filled the cache"
    );
    for dir in [a, b, c, d, e, cache, other] {
        let _ = std::fs::remove_dir_all(dir);
    }
}

#[test]
fn the_reduced_body_strikes_the_deformable_wall_as_the_full_model_does() {
    // the block reduced beside the pendulum (its static modes, crate::reduced::wall): at issue
    // 20's bars for the rigid wall, and the same impulse within 1e-6 relative (the block's
    // compliance under the head is the full model's)
    let sets = ["wall.kind=deformable", "time.dt=0.01", "time.end=0.7"];
    let (full, reduced) = same_first_impact("deformable", &sets);
    assert!(warnings(&reduced).is_empty(), "steel applies: {:?}", warnings(&reduced));
    let impulse = |dir: &Path| columns(&dir.join("events.csv"))["impulse_N_s"][1];
    let (jf, jr) = (impulse(&full), impulse(&reduced));
    assert!(
        (jf - jr).abs() < 1e-6 * jf,
        "impulse {jf} N s (full) and {jr} N s (reduced)"
    );
    let _ = std::fs::remove_dir_all(&full);
    let _ = std::fs::remove_dir_all(&reduced);
}
