//! The actuator torque: the term against finite differences, its resultant (a pure couple `M` for
//! the follower, `M cos θ` for the fixed-direction load, no net force), the time profiles and the
//! table file's errors; then whole runs of the real pendulum against the rigid-body equations,
//! the energy balance and the command line.
//!
//! One file for one claim (the torque term is right, from its load to a whole run), longer than
//! 600 lines because each check is a test of its own.

use crate::common;
use common::Extremes;

use pendulum_fem::assembly::Pattern;
use pendulum_fem::config::{self, TorqueProfile as Kind};
use pendulum_fem::simulation::{Simulation, StepRecord, HINGE_BOUNDARY};
use pendulum_fem::terms::{StepContext, Term, Torque, TorqueMode};
use pendulum_fem::{mesh, Config, Error, Mesh};

use common::exact::{CENTROID_DISTANCE as EXACT_D, INERTIA as EXACT_INERTIA, MASS as EXACT_MASS};

/// The displacement that turns the configuration `X + deform` rigidly by `phi` about the pivot.
fn rotated(mesh: &Mesh, phi: f64, deform: &[f64]) -> Vec<f64> {
    let (s, c) = phi.sin_cos();
    mesh.nodes
        .iter()
        .enumerate()
        .flat_map(|(n, p)| {
            let q = [p[0] + deform[2 * n], p[1] + deform[2 * n + 1]];
            [c * q[0] - s * q[1] - p[0], s * q[0] + c * q[1] - p[1]]
        })
        .collect()
}

fn torque_on(mesh: &Mesh, mode: TorqueMode, amplitude: f64) -> Torque {
    let profile = config::Torque {
        profile: Kind::Constant,
        amplitude,
        follower: mode == TorqueMode::Follower,
        ..Default::default()
    };
    Torque::from_config(mesh, HINGE_BOUNDARY, &profile).unwrap()
}

/// The hinge edge's degrees of freedom, a step of 10 nm, 1e-6 relative; the Hessian's scale is
/// the force per metre of the edge's size (its entries are forces over 0.015 m).
fn check_derivatives(term: &Torque, mesh: &Mesh, u: &[f64], label: &str) {
    let pattern = Pattern::new(mesh, &term.hessian_entries());
    let mut g = vec![0.0; u.len()];
    term.add_gradient(u, &StepContext::at(u, 0.0, 0.0, None), &mut g);
    let g_scale = g.iter().map(|v| v.abs()).max_of();
    let probe = common::Probe {
        dofs: &term.dofs,
        step: 1e-8,
        tolerance: 1e-6,
        hessian_scale: Some(g_scale / 0.015),
    };
    common::check_derivatives(term, &pattern, u, &probe, label);
}

#[test]
fn follower_energy_gradient_and_hessian_match_finite_differences() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 4, 4);
    let term = torque_on(&mesh, TorqueMode::Follower, 2.5);
    for phi in [0.0, 0.7, 2.0, -2.9] {
        let u = rotated(&mesh, phi, &common::wiggle(2 * mesh.num_nodes(), 1e-4, 0.0));
        check_derivatives(&term, &mesh, &u, &format!("follower at {phi} rad"));
    }
}

#[test]
fn fixed_direction_load_gradient_matches_finite_differences_and_has_no_stiffness() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 4, 4);
    let term = torque_on(&mesh, TorqueMode::Fixed, 2.5);
    assert!(term.hessian_entries().is_empty());
    let u = rotated(&mesh, 0.8, &common::wiggle(2 * mesh.num_nodes(), 1e-4, 0.0));
    check_derivatives(&term, &mesh, &u, "fixed");
}

#[test]
fn follower_hessian_entries_are_written_even_when_the_torque_is_zero() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 4, 4);
    let term = torque_on(&mesh, TorqueMode::Follower, 0.0);
    let entries = term.hessian_entries();
    let nd = term.dofs.len();
    assert_eq!(entries.len(), nd * (nd + 1) / 2);
    let pattern = Pattern::new(&mesh, &entries);
    let mut k = vec![0.0; pattern.nnz()];
    let u = rotated(&mesh, 0.3, &vec![0.0; 2 * mesh.num_nodes()]);
    term.add_hessian(&u, &StepContext::at(&u, 0.0, 0.0, None), &pattern, &mut k); // must not panic on a missing entry
    assert!(k.iter().all(|v| *v == 0.0));
}

#[test]
fn the_generalised_force_has_zero_net_force() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 4, 4);
    for mode in [TorqueMode::Follower, TorqueMode::Fixed] {
        let term = torque_on(&mesh, mode, 3.0);
        for phi in [0.0, 1.2, 3.5] {
            let u = rotated(&mesh, phi, &common::wiggle(2 * mesh.num_nodes(), 1e-3, 0.0));
            let mut g = vec![0.0; u.len()];
            term.add_gradient(&u, &StepContext::at(&u, 0.0, 0.0, None), &mut g);
            let scale = g.iter().map(|v| v.abs()).max_of();
            let fx: f64 = g.iter().step_by(2).sum();
            let fy: f64 = g.iter().skip(1).step_by(2).sum();
            assert!(
                fx.abs() < 1e-13 * scale && fy.abs() < 1e-13 * scale,
                "{mode:?} at {phi}: net force ({fx}, {fy}), scale {scale}"
            );
        }
    }
}

/// `Σ_a x_a × f_a` computed here from the gradient and the mesh (independent of
/// `Torque::moment_about_pivot`, which is checked against it).
fn moment_of_gradient(mesh: &Mesh, term: &Torque, u: &[f64]) -> f64 {
    let mut g = vec![0.0; u.len()];
    term.add_gradient(u, &StepContext::at(u, 0.0, 0.0, None), &mut g);
    let m: f64 = mesh
        .nodes
        .iter()
        .enumerate()
        .map(|(n, p)| {
            let x = [p[0] + u[2 * n], p[1] + u[2 * n + 1]];
            // f = −g
            -(x[0] * g[2 * n + 1] - x[1] * g[2 * n])
        })
        .sum();
    assert!((m - term.moment_about_pivot(u, term.value(0.0))).abs() < 1e-12 * m.abs().max(1.0));
    m
}

#[test]
fn follower_moment_about_the_pivot_is_m_at_every_angle_and_deformation() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 4, 4);
    let m = 1.7;
    let term = torque_on(&mesh, TorqueMode::Follower, m);
    let mut worst = 0.0f64;
    for deg in [0.0, 30.0, 100.0, 179.0, 200.0, -170.0, 725.0] {
        for amp in [0.0, 2e-4, 2e-3] {
            // a deformation that also bends and stretches the hinge edge
            let u = rotated(
                &mesh,
                f64::to_radians(deg),
                &common::wiggle(2 * mesh.num_nodes(), amp, 0.0),
            );
            let moment = moment_of_gradient(&mesh, &term, &u);
            worst = [worst, (moment / m - 1.0).abs()].into_iter().max_of();
        }
    }
    println!("largest relative deviation of the follower moment from M: {worst:.2e}");
    assert!(worst < 1e-12, "{worst}");
}

#[test]
fn fixed_direction_moment_is_m_cos_theta() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 4, 4);
    let m = 1.7;
    let term = torque_on(&mesh, TorqueMode::Fixed, m);
    for deg in [0.0, 30.0, 60.0, 100.0, 200.0] {
        let th = f64::to_radians(deg);
        let u = rotated(&mesh, th, &vec![0.0; 2 * mesh.num_nodes()]);
        let moment = moment_of_gradient(&mesh, &term, &u);
        assert!(
            (moment - m * th.cos()).abs() < 1e-12 * m,
            "{deg}°: {moment} vs {}",
            m * th.cos()
        );
    }
}

#[test]
fn hub_angle_is_exact_for_rigid_rotations_and_continuous_through_180_degrees() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 4, 4);
    let term = torque_on(&mesh, TorqueMode::Follower, 1.0);
    let deform = common::wiggle(2 * mesh.num_nodes(), 1e-3, 0.0);
    let base = term.hub_angle(&deform, &StepContext::at(&deform, 0.0, 0.0, None));
    // rotating a deformed configuration by φ adds exactly φ; each turn of 0.25 rad is a step whose
    // context starts at the previous configuration with its unwrapped angle
    let (mut prev, mut prev_x) = (base, deform.clone());
    for k in 1..=40 {
        let phi = 0.25 * k as f64; // up to 10 rad: more than one and a half turns
        let x = rotated(&mesh, phi, &deform);
        let theta = term.hub_angle(&x, &StepContext::at(&prev_x, 0.0, prev, None));
        assert!(
            (theta - base - phi).abs() < 1e-12,
            "φ = {phi}: θ_hub − θ₀ = {}",
            theta - base
        );
        // the energy stays continuous (no jump of 2πM at ±π)
        assert!((theta - prev - 0.25).abs() < 1e-12);
        prev = theta;
        prev_x = x;
    }
}

#[test]
fn the_proxy_angle_stays_continuous_at_a_third_of_a_radian_per_step() {
    use pendulum_fem::rigid::{RigidProjection, Unwrap};
    let mesh = common::hanging_rectangle(0.015, 0.1, 2, 4);
    let proj = RigidProjection::new(&mesh);
    let deform = common::wiggle(2 * mesh.num_nodes(), 1e-4, 0.0);
    let mut unwrap = Unwrap::starting_at(proj.angle(&deform));
    let start = proj.angle(&deform);
    for k in 1..=120 {
        let phi = 0.3 * k as f64; // more than five turns
        let theta = unwrap.next(proj.angle(&rotated(&mesh, phi, &deform)));
        assert!(
            (theta - start - phi).abs() < 1e-12,
            "step {k}: {theta} vs {}",
            start + phi
        );
    }
}

#[test]
fn profiles_evaluate_as_documented() {
    let mut cfg = config::Torque {
        amplitude: 2.0,
        start: 0.5,
        duration: 0.25,
        frequency: 2.0,
        phase: 0.3,
        ..Default::default()
    };
    let mesh = common::hanging_rectangle(0.015, 0.1, 2, 2);
    let at = |cfg: &config::Torque, kind: Kind, t: f64| {
        let mut c = cfg.clone();
        c.profile = kind;
        Torque::from_config(&mesh, HINGE_BOUNDARY, &c).unwrap().value(t)
    };
    assert_eq!(at(&cfg, Kind::None, 1.0), 0.0);
    assert_eq!(at(&cfg, Kind::Constant, 0.0), 2.0);
    assert_eq!(at(&cfg, Kind::Step, 0.49), 0.0);
    assert_eq!(at(&cfg, Kind::Step, 0.5), 2.0);
    assert_eq!(at(&cfg, Kind::Ramp, 0.4), 0.0);
    assert!((at(&cfg, Kind::Ramp, 0.6) - 0.8).abs() < 1e-15);
    assert_eq!(at(&cfg, Kind::Ramp, 0.75), 2.0);
    assert_eq!(at(&cfg, Kind::Ramp, 3.0), 2.0);
    assert_eq!(at(&cfg, Kind::Sine, 0.4), 0.0);
    let expected = 2.0 * (std::f64::consts::TAU * 2.0 * 0.2 + 0.3).sin();
    assert!((at(&cfg, Kind::Sine, 0.7) - expected).abs() < 1e-15);
    cfg.duration = 0.0;
    cfg.profile = Kind::Ramp;
    assert!(matches!(
        Torque::from_config(&mesh, HINGE_BOUNDARY, &cfg),
        Err(Error::Config(_))
    ));
}

#[test]
fn table_profile_interpolates_linearly_and_holds_its_end_values() {
    let dir = common::scratch("table-ok");
    let file = dir.join("torque.csv");
    std::fs::write(&file, "# actuator\ntime_s,torque_Nm\n0.1, 0.0\n0.3,2.0\n\n0.5,-1\n").unwrap();
    let cfg = config::Torque {
        profile: Kind::Table,
        file: Some(file),
        ..Default::default()
    };
    let mesh = common::hanging_rectangle(0.015, 0.1, 2, 2);
    let p = Torque::from_config(&mesh, HINGE_BOUNDARY, &cfg).unwrap();
    for (t, m) in [
        (0.0, 0.0),
        (0.1, 0.0),
        (0.2, 1.0),
        (0.3, 2.0),
        (0.45, -0.25),
        (0.5, -1.0),
        (9.0, -1.0),
    ] {
        assert!((p.value(t) - m).abs() < 1e-14, "M({t}) = {} vs {m}", p.value(t));
    }
}

#[test]
fn every_table_defect_is_an_error_naming_the_file_and_line() {
    let dir = common::scratch("table-bad");
    let mesh = common::hanging_rectangle(0.015, 0.1, 2, 2);
    let load = |name: &str, text: Option<&str>| -> String {
        let file = dir.join(name);
        if let Some(text) = text {
            std::fs::write(&file, text).unwrap();
        }
        let cfg = config::Torque {
            profile: Kind::Table,
            file: Some(file),
            ..Default::default()
        };
        let err = Torque::from_config(&mesh, HINGE_BOUNDARY, &cfg).expect_err(name);
        assert!(matches!(err, Error::Input(_) | Error::Config(_)), "{err:?}");
        let msg = err.to_string();
        assert!(msg.contains(name), "{name}: {msg}");
        msg
    };
    let msg = load("missing.csv", None);
    assert!(msg.contains("torque.file"), "{msg}");
    let msg = load("header.csv", Some("t,M\n0,1\n1,2\n"));
    assert!(
        msg.contains("header.csv:1") && msg.contains("time_s,torque_Nm"),
        "{msg}"
    );
    let msg = load("text.csv", Some("time_s,torque_Nm\n0,1\n0.5,abc\n"));
    assert!(msg.contains("text.csv:3") && msg.contains("abc"), "{msg}");
    let msg = load("order.csv", Some("time_s,torque_Nm\n0,1\n0.5,2\n0.5,3\n"));
    assert!(msg.contains("order.csv:4") && msg.contains("increase"), "{msg}");
    let msg = load("fields.csv", Some("time_s,torque_Nm\n0,1,2\n1,2\n"));
    assert!(msg.contains("fields.csv:2"), "{msg}");
    let msg = load("short.csv", Some("time_s,torque_Nm\n0,1\n"));
    assert!(msg.contains("at least 2"), "{msg}");
    let msg = load("empty.csv", Some(""));
    assert!(msg.contains("empty"), "{msg}");
    let msg = load("nan.csv", Some("time_s,torque_Nm\n0,1\n1,NaN\n"));
    assert!(msg.contains("nan.csv:3"), "{msg}");
}

#[test]
fn profile_none_adds_no_term_and_a_torque_adds_one() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 2, 4);
    let mut cfg = Config::default();
    let sim = Simulation::from_config(&cfg, mesh.clone()).unwrap();
    assert!(sim.model.torque.is_none() && sim.model.loads().count() == 0);
    cfg.torque.profile = Kind::Constant;
    cfg.torque.amplitude = 0.5;
    let sim = Simulation::from_config(&cfg, mesh).unwrap();
    assert!(sim.model.torque.is_some() && sim.model.loads().count() == 1);
    assert_eq!(sim.model.applied_torque(3.0, None), 0.5);
}

#[test]
fn the_rigid_start_accelerates_with_the_delivered_moment() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 2, 4);
    for follower in [true, false] {
        let mut cfg = Config::default();
        cfg.gravity.g = 0.0;
        cfg.initial.angle_deg = 60.0;
        cfg.torque.profile = Kind::Constant;
        cfg.torque.amplitude = 0.2;
        cfg.torque.follower = follower;
        let mut sim = Simulation::from_config(&cfg, mesh.clone()).unwrap();
        let moment = if follower { 0.2 } else { 0.2 * 0.5 };
        let expected = moment / sim.model.inertia_pivot();
        let alpha = sim.record(0).alpha;
        assert!(
            (alpha / expected - 1.0).abs() < 1e-6,
            "follower {follower}: α₀ = {alpha} vs {expected}"
        );
    }
}

#[test]
fn every_profile_drives_a_run_that_converges_and_balances_energy() {
    // from rest without gravity: before the step or ramp starts there is no load at all
    let mesh = common::hanging_rectangle(0.015, 0.3, 2, 10);
    for kind in [Kind::Constant, Kind::Step, Kind::Ramp, Kind::Sine] {
        let mut cfg = Config::default();
        cfg.gravity.g = 0.0;
        cfg.initial.angle_deg = 0.0;
        cfg.time.dt = 0.005;
        cfg.time.end = 0.3;
        cfg.torque = config::Torque {
            profile: kind,
            amplitude: 0.05,
            start: 0.05,
            duration: 0.1,
            frequency: 4.0,
            phase: 0.0,
            ..Default::default()
        };
        let profile = Torque::from_config(&mesh, HINGE_BOUNDARY, &cfg.torque).unwrap();
        let mut sim = Simulation::from_config(&cfg, mesh.clone()).unwrap();
        let mut records = vec![sim.record(0)];
        for _ in 0..cfg.time.steps() {
            records.push(sim.advance().unwrap_or_else(|e| panic!("{kind:?}: {e}")));
        }
        for r in &records {
            assert_eq!(r.torque, profile.value(r.time), "{kind:?} at {}", r.time);
        }
        let balance = energy_balance(&records);
        assert!(balance < 1e-3, "{kind:?}: energy balance {balance}");
        assert!(sim.cutbacks == 0, "{kind:?}: {} cut-backs", sim.cutbacks);
    }
}

// ---------------------------------------------------------------------------------------------
// Whole runs on the real mesh (release mode)

fn run(cfg: &Config) -> (Simulation, Vec<StepRecord>) {
    let mesh = mesh::generate(cfg).expect("tutorial mesh");
    let mut sim = Simulation::from_config(cfg, mesh).expect("set-up");
    let inertia = sim.model.inertia_pivot();
    assert!((inertia / EXACT_INERTIA - 1.0).abs() < 1e-5, "I = {inertia}");
    let mut records = vec![sim.record(0)];
    for _ in 0..cfg.time.steps() {
        records.push(sim.advance().expect("step converges"));
    }
    (sim, records)
}

fn torque_config(amplitude: f64, g: f64, dt: f64, end: f64) -> Config {
    let mut cfg = Config::default();
    cfg.gravity.g = g;
    cfg.initial.angle_deg = 0.0;
    cfg.time.dt = dt;
    cfg.time.end = end;
    cfg.torque.profile = Kind::Constant;
    cfg.torque.amplitude = amplitude;
    cfg
}

/// `θ'' = f(θ)`, `θ(0) = θ'(0) = 0`, by RK4 with step `h`; `θ` at the times `ts` (multiples of `h`).
fn rigid_rk4(f: impl Fn(f64) -> f64, h: f64, ts: &[f64]) -> Vec<f64> {
    let (mut th, mut w, mut t) = (0.0f64, 0.0f64, 0.0f64);
    let mut out = Vec::new();
    for &target in ts {
        while t < target - 0.5 * h {
            let (k1t, k1w) = (w, f(th));
            let (k2t, k2w) = (w + 0.5 * h * k1w, f(th + 0.5 * h * k1t));
            let (k3t, k3w) = (w + 0.5 * h * k2w, f(th + 0.5 * h * k2t));
            let (k4t, k4w) = (w + h * k3w, f(th + h * k3t));
            th += h / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t);
            w += h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
            t += h;
        }
        out.push(th);
    }
    out
}

/// `max |Δtotal − W| / max |W|` over the run.
fn energy_balance(records: &[StepRecord]) -> f64 {
    let e0 = records[0].total;
    let w_max = records.iter().map(|r| r.torque_work.abs()).max_of();
    records.iter().map(|r| (r.total - e0 - r.torque_work).abs()).max_of() / w_max
}

/// Spin-up from rest without gravity, dt = 0.01 s for 1.5 s (the setting), up to 0.34 rad
/// per row. The average-acceleration rule is not energy-conserving for a spinning hyperelastic body
/// (Simo & Tarnow 1992): with it this run pumps energy into the stiff elastic modes until a step
/// fails. HHT-α (α = −0.05) damps those modes, and the rotation control splits the steps into
/// sub-steps of at most 3°, which keeps the chord error of the rotation (Δφ²/12) small.
#[test]
fn without_gravity_a_constant_torque_spins_the_pendulum_as_half_m_over_i_t_squared() {
    let mut cfg = torque_config(1.0, 0.0, 0.01, 1.5);
    cfg.time.scheme = pendulum_fem::config::Scheme::Hht;
    let (sim, records) = run(&cfg);
    let worst = records
        .iter()
        .filter(|r| r.time >= 0.1 - 1e-9)
        .map(|r| (r.theta / (0.5 * (1.0 / EXACT_INERTIA) * r.time * r.time) - 1.0).abs())
        .max_of();
    for w in records.windows(2) {
        let d = w[1].theta - w[0].theta;
        // continuous (unwrapped): increments stay positive and far below π
        assert!(d > 0.0 && d < 0.5, "θ jumps by {d} at t = {}", w[1].time);
    }
    let largest_step = records.windows(2).map(|w| w[1].theta - w[0].theta).max_of();
    let balance = energy_balance(&records);
    let last = records.last().unwrap();
    let strain_peak = records.iter().map(|r| r.strain).max_of();
    println!(
        "spin: θ(1.5 s) = {:.4} rad ({:.2} turns), largest relative deviation from ½(M/I)t² {worst:.2e}, \
         largest row increment {largest_step:.3} rad, energy balance {balance:.2e}, work {:.4} J, strain peak \
         {strain_peak:.2e} J, {} Newton iterations, {} cut-backs",
        last.theta,
        last.theta / std::f64::consts::TAU,
        last.torque_work,
        sim.total_iterations,
        sim.cutbacks
    );
    assert!(last.theta > 3.0 * std::f64::consts::TAU, "several turns");
    // the bar: within 0.5 % from 0.1 s on
    assert!(worst < 5e-3, "{worst}");
    // HHT dissipates a little with the unresolved elastic modes: a few thousandths of the work
    assert!(balance < 3e-3, "energy balance {balance}");
    // no elastic blow-up: the centrifugal strain energy at 34 rad/s is about 1e-4 J
    assert!(strain_peak < 1e-3, "strain energy {strain_peak} J");
    assert!(records.iter().all(|r| r.torque == 1.0));
}

#[test]
fn with_gravity_a_constant_torque_follows_the_rigid_equation_and_balances_energy() {
    let (m, g) = (1.0, 9.81);
    let cfg = torque_config(m, g, 0.005, 1.5);
    let (_, records) = run(&cfg);
    let ts: Vec<f64> = records.iter().map(|r| r.time).collect();
    let mgd = EXACT_MASS * g * EXACT_D;
    let exact = rigid_rk4(|th| (m - mgd * th.sin()) / EXACT_INERTIA, 1e-5, &ts);
    let worst = records
        .iter()
        .zip(&exact)
        .map(|(r, e)| (r.theta - e).abs().to_degrees())
        .max_of();
    let balance = energy_balance(&records);
    let peak = records.iter().map(|r| r.theta).max_of().to_degrees();
    println!(
        "torque + gravity: largest |θ − θ_rigid| = {worst:.2e} deg (peak {peak:.2} deg), energy balance {balance:.2e}"
    );
    assert!(worst < 0.2, "{worst} deg");
    assert!(balance < 1e-3, "energy balance {balance}");
}

#[test]
fn a_fixed_direction_load_delivers_m_cos_theta() {
    let m = 1.0;
    let mut cfg = torque_config(m, 0.0, 0.005, 1.5);
    cfg.torque.follower = false;
    let (sim, records) = run(&cfg);
    let ts: Vec<f64> = records.iter().map(|r| r.time).collect();
    let exact = rigid_rk4(|th| m * th.cos() / EXACT_INERTIA, 1e-5, &ts);
    let worst = records
        .iter()
        .zip(&exact)
        .map(|(r, e)| (r.theta - e).abs().to_degrees())
        .max_of();
    // the moment actually delivered in the final state
    let term = Torque::from_config(&sim.model.mesh, HINGE_BOUNDARY, &cfg.torque).unwrap();
    let last = records.last().unwrap();
    let moment = term.moment_about_pivot(sim.displacement(), term.value(last.time));
    let peak = records.iter().map(|r| r.theta).max_of().to_degrees();
    let balance = energy_balance(&records);
    println!(
        "fixed direction: largest |θ − θ_rigid(M cos θ)| = {worst:.2e} deg (peak {peak:.1} deg); final moment \
         {moment:.6} vs M cos θ = {:.6}; energy balance {balance:.2e}",
        m * last.theta.cos()
    );
    assert!(peak > 120.0, "the drive fades past 90°: peak {peak}");
    assert!(worst < 0.2, "{worst} deg");
    assert!((moment - m * last.theta.cos()).abs() < 1e-4 * m);
    assert!(balance < 1e-3, "energy balance {balance}");
}

fn cli_run(name: &str, sets: &[String]) -> (Vec<String>, Vec<Vec<f64>>) {
    let dir = common::scratch(name);
    let out = dir.join("out");
    let mut cmd = common::bin();
    cmd.args(["run", "--quiet", "--out"]).arg(&out);
    for s in [
        "time.end=0.1",
        "output.plots=false",
        "output.animation=false",
        "output.paraview=false",
        "output.viewer=false",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain(sets.iter().cloned())
    {
        cmd.arg("--set").arg(s);
    }
    let o = cmd.output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    pendulum_fem::store::Table::read(&out.join("results.csv"))
        .map(|t| (t.names, t.rows))
        .unwrap()
}

fn column(names: &[String], name: &str) -> usize {
    names
        .iter()
        .position(|n| n == name)
        .unwrap_or_else(|| panic!("no column {name} in {names:?}"))
}

#[test]
fn step_and_table_profiles_drive_a_run_from_the_command_line() {
    let (names, rows) = cli_run(
        "cli-step",
        &[
            "torque.profile=step".into(),
            "torque.amplitude=2".into(),
            "torque.start=0.045".into(),
        ],
    );
    let (ct, cm, cw, ce) = (
        column(&names, "time_s"),
        column(&names, "torque_Nm"),
        column(&names, "torque_work_J"),
        column(&names, "total_J"),
    );
    assert_eq!(rows.len(), 11);
    for r in &rows {
        let expected = if r[ct] >= 0.045 { 2.0 } else { 0.0 };
        assert_eq!(r[cm], expected, "t = {}", r[ct]);
    }
    let last = rows.last().unwrap();
    assert!(last[cw] > 0.0, "the torque does work");
    assert!((last[ce] - rows[0][ce] - last[cw]).abs() < 1e-3 * last[cw]);

    let dir = common::scratch("cli-table-file");
    let file = dir.join("drive.csv");
    std::fs::write(&file, "time_s,torque_Nm\n0,0\n0.1,2\n").unwrap();
    let (names, rows) = cli_run(
        "cli-table",
        &[
            "torque.profile=table".into(),
            format!("torque.file=\"{}\"", file.display()),
        ],
    );
    let (ct, cm) = (column(&names, "time_s"), column(&names, "torque_Nm"));
    assert_eq!(rows.len(), 11);
    for r in &rows {
        assert!((r[cm] - 20.0 * r[ct]).abs() < 1e-12, "t = {}: {}", r[ct], r[cm]);
    }
}

#[test]
fn a_torque_straining_a_soft_hub_past_a_fifth_of_its_modulus_is_refused_through_the_cli() {
    // the default geometry: rod half-width w = 0.015 m, thickness t = 0.01 m, so the hinge edge's
    // traction stress at its ends is σ = 3 |M| / (2 t w²) = 6.67e5 Pa per N·m (Gauss-exact weights
    // on the straight edge: ∫ X_x² ds = 2 w³ / 3)
    let mut cfg = Config::default();
    cfg.torque.profile = Kind::Constant;
    cfg.torque.amplitude = -0.5;
    let mesh = mesh::generate(&cfg).unwrap();
    let torque = Torque::from_config(&mesh, HINGE_BOUNDARY, &cfg.torque).unwrap();
    let exact = 3.0 * 0.5 / (2.0 * 0.01 * 0.015f64.powi(2));
    assert!(
        (torque.edge_stress(-0.5, 0.01) / exact - 1.0).abs() < 1e-12,
        "{} vs {exact}",
        torque.edge_stress(-0.5, 0.01)
    );
    let dir = common::scratch("hub");
    let run = |name: &str, lines: &str| {
        let file = dir.join(format!("{name}.toml"));
        std::fs::write(
            &file,
            format!(
                "[material]\nyoungs_modulus = 1e6\n[time]\nend = 0.02\n[output]\nplots = false\nanimation = false\n\
                 paraview = false\nviewer = false\n{lines}"
            ),
        )
        .unwrap();
        common::bin()
            .args(["run", "--config"])
            .arg(&file)
            .arg("--out")
            .arg(dir.join(name))
            .output()
            .unwrap()
    };
    // 0.5 N·m on E = 1e6 Pa: σ = 3.3e5 Pa, a third of the modulus
    let out = run("strong", "[torque]\nprofile = \"constant\"\namplitude = -0.5\n");
    let msg = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(!out.status.success(), "{msg}");
    for name in [
        "torque.amplitude",
        "material.youngs_modulus",
        "geometry.rod_half_width",
        "outside the model",
        "0.333",
    ] {
        assert!(msg.contains(name), "{name} missing from: {msg}");
    }
    assert!(
        !dir.join("strong").join("results.csv").exists(),
        "no results for a refused case"
    );
    // a table's largest sample counts, wherever it lies
    let table = dir.join("torque.csv");
    std::fs::write(&table, "time_s,torque_Nm\n0,0\n5,0.1\n6,0.5\n").unwrap();
    let out = run(
        "table",
        &format!("[torque]\nprofile = \"table\"\nfile = {:?}\n", table.to_str().unwrap()),
    );
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("outside the model"));
    // the largest torque allowed is a number however far past it the torque lies (`|M| E / σ`
    // overflowed to NaN): 0.2 × 1e6 Pa / 6.67e5 Pa per N·m
    for amplitude in ["-0.5", "1e300", "-1.7e308"] {
        let out = run(
            &format!("far{amplitude}"),
            &format!("[torque]\nprofile = \"constant\"\namplitude = {amplitude}\n"),
        );
        let msg = String::from_utf8_lossy(&out.stderr).to_string();
        assert!(
            msg.contains("a torque of at most 0.3 N·m in magnitude"),
            "{amplitude}: {msg}"
        );
        assert!(!msg.contains("NaN"), "{amplitude}: {msg}");
    }
    // 0.27 N·m: σ = 1.8e5 Pa, below a fifth of the modulus, runs
    let out = run("within", "[torque]\nprofile = \"constant\"\namplitude = -0.27\n");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(dir.join("within").join("results.csv").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}
