//! The stepping interface: `step(dt)` with any `dt`, rollback of a failed step, the held torque
//! input, outputs on request, snapshots in memory and as bytes.

use crate::common;
use common::Extremes;

use pendulum_fem::commands::run::csv_values;
use pendulum_fem::config::TorqueProfile as Kind;
use pendulum_fem::{mesh, Config, Error, Simulation, Snapshot, StepRecord};

fn tutorial_sim(cfg: &Config) -> Simulation {
    let mesh = mesh::generate(cfg).expect("tutorial mesh");
    Simulation::from_config(cfg, mesh).expect("set-up")
}

/// Every CSV value of a record as IEEE bits, for bit-for-bit comparisons.
fn bits(r: &StepRecord) -> Vec<u64> {
    csv_values(r).iter().map(|x| x.to_bits()).collect()
}

#[test]
fn steps_without_records_equal_the_advance_loop_bit_for_bit() {
    // advance() records every step (energies, stresses); the stepper alone must not depend on
    // whether anyone looked
    let cfg = Config::default();
    let mut fixed = tutorial_sim(&cfg);
    let mut stepper = tutorial_sim(&cfg);
    let mut records = Vec::new();
    for _ in 0..100 {
        records.push(fixed.advance().expect("step converges"));
    }
    for _ in 0..100 {
        stepper.step(cfg.time.dt).expect("step converges");
    }
    let last = stepper.record(stepper.last_newton_iterations());
    assert_eq!(bits(&last), bits(records.last().unwrap()));
    assert_eq!(
        stepper.time(),
        1.0,
        "100 steps of 0.01 s land on 1 s exactly (100 · 0.01)"
    );
    assert_eq!(stepper.snapshot().to_bytes(), fixed.snapshot().to_bytes());
    assert_eq!(stepper.stress_evaluations(), 1, "only the one record computed stresses");
}

#[test]
fn steps_of_mixed_length_reach_the_fixed_run_at_one_second() {
    let cfg = Config::default();
    let mut fixed = tutorial_sim(&cfg);
    for _ in 0..100 {
        fixed.step(0.01).expect("step converges");
    }
    let mut mixed = tutorial_sim(&cfg);
    let lengths = [0.01, 0.003, 0.007];
    let mut k = 0;
    while mixed.time() + lengths[k % 3] < 1.0 - 1e-9 {
        mixed.step(lengths[k % 3]).expect("step converges");
        k += 1;
    }
    mixed.step_to(1.0).expect("last step converges");
    assert_eq!(mixed.time(), 1.0);
    assert!(k > 140, "{k} steps of mixed length");
    let (a, b) = (fixed.record(0), mixed.record(0));
    // Bound: both runs are second order; the fixed run's phase error after t is about
    // ω³ Δt² t / 24 (midpoint rule on ω ≈ 2π/T) times the amplitude θ_max; the mixed run (smaller
    // steps) is closer to the exact solution, so their difference stays below the fixed run's error.
    let omega = std::f64::consts::TAU / 0.8; // the period is about 0.8 s
    let theta_max = 20f64.to_radians();
    let bound = omega.powi(3) * 0.01f64.powi(2) * 1.0 / 24.0 * theta_max;
    let dtheta = (a.theta - b.theta).abs();
    assert!(
        dtheta < bound,
        "θ(1 s): fixed {} mixed {} (|Δ| {dtheta:.3e} > {bound:.3e})",
        a.theta,
        b.theta
    );
    assert!(dtheta > 0.0, "different step sequences cannot agree to the bit");
    // the energy-momentum scheme conserves the total energy at any step size (to the solver's
    // energy tolerance 1e-12 per step of the energy scale, ~1 J here): 1e-9 J over 150 steps
    assert!(
        (a.total - b.total).abs() < 1e-9,
        "total energy {} vs {}",
        a.total,
        b.total
    );
}

#[test]
fn a_step_with_a_non_positive_or_infinite_dt_is_an_error_naming_dt() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 2, 4);
    let mut sim = Simulation::from_config(&Config::default(), mesh).unwrap();
    for dt in [0.0, -0.01, f64::NAN, f64::INFINITY] {
        let msg = sim.step(dt).unwrap_err().to_string();
        assert!(msg.contains("dt") && msg.contains("allowed dt > 0"), "{msg}");
    }
    assert!(sim
        .step_to(0.0)
        .unwrap_err()
        .to_string()
        .contains("after the current time"));
    assert_eq!(sim.step, 0);
}

fn torque_config() -> Config {
    let mut cfg = Config::default();
    cfg.torque.profile = Kind::Constant;
    cfg.torque.amplitude = 1.0;
    cfg
}

#[test]
fn a_failed_step_leaves_the_state_as_it_was_and_a_retry_is_the_clean_step() {
    for cfg in [Config::default(), torque_config()] {
        let mut failing = tutorial_sim(&cfg);
        let mut clean = tutorial_sim(&cfg);
        for _ in 0..10 {
            failing.step(0.01).unwrap();
            clean.step(0.01).unwrap();
        }
        let before = failing.snapshot();
        // impossible: the Newton decrement can never fall below 0 J
        let solver = failing.model.config.solver.clone();
        failing.model.config.solver.tolerance = 0.0;
        failing.model.config.solver.max_iterations = 3;
        failing.model.config.solver.max_cutbacks = pendulum_fem::config::Cutbacks::Count(2);
        let err = failing.step(0.02).unwrap_err();
        assert!(matches!(err, Error::TimeStep { step: 11, .. }), "{err}");
        assert_eq!(
            failing.snapshot().to_bytes(),
            before.to_bytes(),
            "state changed by a failed step"
        );
        assert_eq!(failing.snapshot(), before);
        // the retry (solver restored) is the step that never saw the failure, bit for bit,
        // factorisation included
        failing.model.config.solver = solver;
        for _ in 0..5 {
            failing.step(0.01).unwrap();
            clean.step(0.01).unwrap();
        }
        assert_eq!(failing.snapshot().to_bytes(), clean.snapshot().to_bytes());
    }
}

#[test]
fn a_held_torque_reproduces_the_constant_profile_run_bit_for_bit() {
    let constant = torque_config();
    let mut input = Config::default();
    input.torque.profile = Kind::Constant;
    input.torque.amplitude = 0.0; // declares the input
    let mut a = tutorial_sim(&constant);
    let mut b = tutorial_sim(&input);
    b.set_torque(1.0).unwrap();
    assert_eq!(b.held_torque(), Some(1.0));
    assert_eq!(bits(&a.record(0)), bits(&b.record(0)), "initial state with the torque");
    for _ in 0..50 {
        let (ia, ib) = (a.step(0.01).unwrap(), b.step(0.01).unwrap());
        assert_eq!(bits(&a.record(ia)), bits(&b.record(ib)), "t = {}", a.time());
    }
    assert!(b.record(0).torque_work > 0.1, "the held torque does work");
}

#[test]
fn set_torque_needs_a_torque_term_and_says_which_key_declares_it() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 2, 4);
    let mut sim = Simulation::from_config(&Config::default(), mesh).unwrap();
    let msg = sim.set_torque(1.0).unwrap_err().to_string();
    assert!(msg.contains("torque.profile"), "{msg}");
    let mut cfg = Config::default();
    cfg.torque.profile = Kind::Constant;
    let mesh = common::hanging_rectangle(0.015, 0.1, 2, 4);
    let mut sim = Simulation::from_config(&cfg, mesh).unwrap();
    assert!(sim.set_torque(f64::NAN).unwrap_err().to_string().contains("finite"));
}

#[test]
fn steps_compute_no_nodal_stresses_until_asked() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 2, 4);
    let mut sim = Simulation::from_config(&Config::default(), mesh).unwrap();
    for _ in 0..5 {
        sim.step(0.01).unwrap();
    }
    assert_eq!(sim.stress_evaluations(), 0);
    let e = sim.energies();
    assert!(e.kinetic > 0.0 && (e.total - (e.kinetic + e.strain + e.gravity)).abs() == 0.0);
    assert!(sim.hinge_reaction()[1] > 0.0, "the hinge holds the body up");
    assert!(sim.theta() < 20f64.to_radians() && sim.last_newton_iterations() > 0);
    assert_eq!(sim.displacement().len(), sim.velocity().len());
    assert_eq!(sim.stress_evaluations(), 0, "kinematic outputs compute no stresses");
    let vm = sim.von_mises_max();
    let nodal = sim.nodal_stress();
    assert_eq!(vm, nodal.von_mises.iter().cloned().max_of());
    assert_eq!(sim.stress_evaluations(), 2);
}

/// 30 steps from the current state: their records and the final snapshot bytes.
fn thirty_steps(sim: &mut Simulation) -> (Vec<Vec<u64>>, Vec<u8>) {
    let records = (0..30)
        .map(|_| {
            let its = sim.step(0.01).expect("step converges");
            bits(&sim.record(its))
        })
        .collect();
    (records, sim.snapshot().to_bytes())
}

#[test]
fn restore_and_the_same_steps_are_bit_identical_also_from_bytes_into_a_fresh_simulation() {
    for cfg in [Config::default(), torque_config()] {
        let mut sim = tutorial_sim(&cfg);
        for _ in 0..37 {
            sim.step(0.01).unwrap();
        }
        assert_eq!(sim.time(), 0.37);
        let snap = sim.snapshot();
        let first = thirty_steps(&mut sim);
        sim.restore(&snap).unwrap();
        assert_eq!(sim.snapshot().to_bytes(), snap.to_bytes());
        let again = thirty_steps(&mut sim);
        assert_eq!(first, again, "restore + the same steps");
        let bytes = snap.to_bytes();
        let read = Snapshot::from_bytes(&bytes, "mem").unwrap();
        assert_eq!(read.to_bytes(), bytes);
        assert_eq!((read.step(), read.time()), (37, 0.37));
        let mut fresh = tutorial_sim(&cfg);
        fresh.restore(&read).unwrap();
        assert_eq!(thirty_steps(&mut fresh), first, "from bytes into a fresh simulation");
    }
}

#[test]
fn a_snapshot_of_another_model_or_damaged_bytes_is_refused_with_a_clear_error() {
    let cfg = Config::default();
    let mut a = Simulation::from_config(&cfg, common::hanging_rectangle(0.015, 0.1, 2, 4)).unwrap();
    let mut b = Simulation::from_config(&cfg, common::hanging_rectangle(0.015, 0.1, 2, 5)).unwrap();
    a.step(0.01).unwrap();
    let snap = a.snapshot();
    let before = b.snapshot();
    let msg = b.restore(&snap).unwrap_err().to_string();
    assert!(
        msg.contains("another model") && msg.contains("configuration and mesh"),
        "{msg}"
    );
    assert_eq!(b.snapshot(), before, "a refused snapshot changes nothing");
    // another configuration on the same mesh
    let mut other = cfg.clone();
    other.material.density = 7000.0;
    let mut c = Simulation::from_config(&other, common::hanging_rectangle(0.015, 0.1, 2, 4)).unwrap();
    assert!(c.restore(&snap).unwrap_err().to_string().contains("another model"));
    // a longer time.end is the same model (a finished run can be continued)
    let mut longer = cfg.clone();
    longer.time.end = 5.0;
    let mut d = Simulation::from_config(&longer, common::hanging_rectangle(0.015, 0.1, 2, 4)).unwrap();
    d.restore(&snap).unwrap();
    // bytes: damaged, truncated, foreign, another version
    let bytes = snap.to_bytes();
    let mut damaged = bytes.clone();
    damaged[100] ^= 1;
    let msg = Snapshot::from_bytes(&damaged, "x.snap").unwrap_err().to_string();
    assert!(msg.contains("x.snap") && msg.contains("damaged"), "{msg}");
    let msg = Snapshot::from_bytes(&bytes[..bytes.len() / 2], "x.snap")
        .unwrap_err()
        .to_string();
    assert!(msg.contains("x.snap"), "{msg}");
    let msg = Snapshot::from_bytes(b"time_s,theta_rad\n", "x.snap")
        .unwrap_err()
        .to_string();
    assert!(msg.contains("not a pendulum-fem snapshot"), "{msg}");
    let mut version = bytes.clone();
    version[8] = 99;
    let msg = Snapshot::from_bytes(&version, "x.snap").unwrap_err().to_string();
    assert!(msg.contains("version 99"), "{msg}");
}

#[test]
fn a_held_torque_changed_during_the_run_does_work_that_balances_the_energy() {
    // zero-order hold: each step sees one torque value from its start to its end, so the
    // energy-momentum scheme's balance E − E₀ = W holds across the changes as well
    let mut cfg = Config::default();
    cfg.torque.profile = Kind::Constant;
    let mut sim = tutorial_sim(&cfg);
    let e0 = sim.energies().total;
    for (k, m) in [0.0, 0.5, -0.5, 0.0].into_iter().enumerate() {
        sim.set_torque(m).unwrap();
        assert_eq!(sim.model.applied_torque(sim.time(), sim.held_torque()), m);
        for _ in 0..15 {
            sim.step(0.01).unwrap();
        }
        let r = sim.record(0);
        assert_eq!(r.torque, m, "segment {k}");
    }
    let e = sim.energies();
    assert!(e.torque_work.abs() > 1e-3, "the torque did work: {}", e.torque_work);
    // bound: solver.energy_tolerance 1e-12 per step of the step's energy scale (~1 J), 60 steps
    let defect = (e.total - e0 - e.torque_work).abs();
    assert!(defect < 1e-9, "E − E₀ − W = {defect:e} J");
}

/// θ and the total energy after each of 100 steps of 1 ms, as IEEE bits.
fn trajectory(cfg: &Config) -> Vec<[u64; 2]> {
    let mut sim = tutorial_sim(cfg);
    (0..100)
        .map(|_| {
            sim.step(1e-3).expect("step");
            [sim.theta().to_bits(), sim.energies().total.to_bits()]
        })
        .collect()
}

/// Simulations stepped at the same time from several threads (a threaded scheduler's tasks: each
/// step hands itself to the one shared pool, whose idle threads spin for a step only while it is
/// the only one in flight) give each one's results alone, bit for bit.
#[test]
fn simulations_stepped_from_several_threads_at_once_give_their_results_alone() {
    let configs: Vec<Config> = [20.0, 45.0, 70.0]
        .iter()
        .map(|&angle| {
            let mut c = Config::default();
            c.initial.angle_deg = angle;
            c
        })
        .collect();
    let alone: Vec<_> = configs.iter().map(trajectory).collect();
    let together: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = configs.iter().map(|c| s.spawn(move || trajectory(c))).collect();
        handles.into_iter().map(|h| h.join().expect("thread")).collect()
    });
    assert_eq!(together, alone);
}
