//! FMI behaviour of one instance, driven in Rust through [`Instance`] (the C functions only convert
//! arguments): defaults equal the CLI's, invalid parameters fail at `fmi2ExitInitializationMode`
//! with the key in the log, zero steps refresh, the master's time is accepted within rounding, a
//! long communication step equals its internal steps, a failed step changes nothing.

use std::cell::RefCell;
use std::rc::Rc;

use pendulum_fem_core::simulation::split::internal_steps;
use pendulum_fem_core::Config;
use pendulum_fem_fmu::instance::Phase;
use pendulum_fem_fmu::variables::{by_name, Kind, Role, VARIABLES};
use pendulum_fem_fmu::{Instance, Status};

type Log = Rc<RefCell<Vec<(Status, String)>>>;

fn instance() -> (Instance, Log) {
    let log: Log = Rc::default();
    let sink = log.clone();
    let inst = Instance::new(
        "test",
        false,
        Box::new(move |status, _category, message| sink.borrow_mut().push((status, message.to_string()))),
    );
    (inst, log)
}

fn set(inst: &mut Instance, name: &str, value: f64) -> Status {
    let v = by_name(name).expect("variable");
    inst.set(v.kind, &[v.vr], &[value])
}

fn get(inst: &mut Instance, name: &str) -> f64 {
    let v = by_name(name).expect("variable");
    let mut out = [f64::NAN];
    assert_eq!(inst.get(v.kind, &[v.vr], &mut out), Status::Ok, "get {name}");
    out[0]
}

/// An initialised instance with `params`.
fn started(params: &[(&str, f64)]) -> (Instance, Log) {
    let (mut inst, log) = instance();
    assert_eq!(inst.setup_experiment(0.0), Status::Ok);
    assert_eq!(inst.enter_initialization(), Status::Ok);
    for &(name, value) in params {
        assert_eq!(set(&mut inst, name, value), Status::Ok, "{name}");
    }
    assert_eq!(inst.exit_initialization(), Status::Ok, "{:?}", log.borrow());
    (inst, log)
}

fn outputs(inst: &mut Instance) -> Vec<u64> {
    VARIABLES
        .iter()
        .filter(|v| matches!(v.role, Role::Output(_)))
        .map(|v| get(inst, v.name).to_bits())
        .collect()
}

#[test]
fn parameter_defaults_are_the_cli_defaults() {
    let json = serde_json::to_value(Config::default()).expect("config as JSON");
    for v in VARIABLES {
        let Role::Config(key) = v.role else { continue };
        let value = key
            .split('.')
            .fold(&json, |node, part| &node[part])
            .as_f64()
            .unwrap_or_else(|| panic!("{key} is not a number in Config::default()"));
        assert_eq!(v.start, Some(value), "{} ({key})", v.name);
    }
    let theta = by_name("theta_start").unwrap().start.unwrap();
    assert_eq!(theta.to_degrees(), Config::default().initial.angle_deg);
    assert_eq!(
        by_name("max_internal_step").unwrap().start,
        Some(Config::default().time.dt)
    );
}

#[test]
fn invalid_parameters_fail_at_exit_initialization_naming_the_key() {
    for (name, value, needle) in [
        ("poisson_ratio", 0.7, "material.poisson_ratio"),
        ("mesh_order", 3.0, "mesh.order"),
        ("hole_radius", 0.07, "geometry.hole_radius"),
        ("max_internal_step", 0.0, "max_internal_step"),
    ] {
        let (mut inst, log) = instance();
        inst.enter_initialization();
        assert_eq!(set(&mut inst, name, value), Status::Ok);
        assert_eq!(inst.exit_initialization(), Status::Error, "{name} = {value}");
        let messages = log.borrow();
        assert!(
            messages.iter().any(|(s, m)| *s == Status::Error && m.contains(needle)),
            "{name}: {messages:?}"
        );
        assert_eq!(inst.phase, Phase::Initialization);
    }
}

#[test]
fn a_parameter_changed_after_an_output_was_read_changes_that_output() {
    let (mut inst, _) = instance();
    assert_eq!(inst.setup_experiment(0.0), Status::Ok);
    assert_eq!(inst.enter_initialization(), Status::Ok);
    assert_eq!(set(&mut inst, "theta_start", 0.35), Status::Ok);
    assert!((get(&mut inst, "theta") - 0.35).abs() < 1e-3);
    assert_eq!(set(&mut inst, "theta_start", 0.5), Status::Ok);
    assert!((get(&mut inst, "theta") - 0.5).abs() < 1e-3, "the model is rebuilt");
}

#[test]
fn a_zero_step_refreshes_and_the_master_time_is_accepted_within_rounding() {
    let (mut inst, log) = started(&[("theta_start", 0.35)]);
    let before = outputs(&mut inst);
    assert_eq!(inst.do_step(1e-8, 0.0), Status::Ok, "a zero step 1e-8 s off");
    assert_eq!(outputs(&mut inst), before, "a zero step changes nothing");
    assert_eq!(inst.do_step(0.0, 0.01), Status::Ok);
    assert_eq!(
        inst.do_step(0.01 + 5e-9, 0.01),
        Status::Ok,
        "1e-8-ish off the FMU's 0.01 s"
    );
    assert_eq!(inst.time(), 0.02, "the FMU keeps its own clock");
    assert_eq!(inst.do_step(0.03, 0.01), Status::Error, "10 ms off is another time");
    assert!(log.borrow().iter().any(|(_, m)| m.contains("not the FMU's time")));
}

#[test]
fn a_long_communication_step_equals_its_internal_steps() {
    let (mut long, _) = started(&[("theta_start", 0.35)]);
    let (mut short, _) = started(&[("theta_start", 0.35)]);
    // the split rule the FMU applies (pendulum_fem_core::simulation::split, tested there too)
    assert_eq!(internal_steps(0.05, 0.01, None), Ok((5, 0.01)));
    assert_eq!(
        internal_steps(0.010000000000000009, 0.01, None),
        Ok((1, 0.01)),
        "a master's rounding"
    );
    assert_eq!(internal_steps(0.025, 0.01, None), Ok((3, 0.025 / 3.0)));
    assert_eq!(long.do_step(0.0, 0.05), Status::Ok);
    for k in 0..5 {
        assert_eq!(short.do_step(k as f64 * 0.01, 0.01), Status::Ok);
    }
    assert_eq!(outputs(&mut long), outputs(&mut short));
    assert_eq!(long.time(), short.time());
}

#[test]
fn a_failed_step_is_an_error_naming_time_and_cause_and_changes_nothing() {
    // with one Newton iteration and no cut-back the first internal step still converges (the start
    // is in equilibrium and the rotational guess is close), a later one does not: the state goes
    // back to before the whole communication step
    let (mut inst, log) = started(&[("solver_max_iterations", 1.0), ("solver_max_cutbacks", 0.0)]);
    let before = outputs(&mut inst);
    assert_eq!(inst.do_step(0.0, 0.03), Status::Error);
    assert_eq!(outputs(&mut inst), before, "outputs as before the call");
    assert_eq!(inst.time(), 0.0);
    let messages = log.borrow();
    let (_, m) = messages.last().expect("a message");
    assert!(m.contains("from t = 0 s") && m.contains("Newton"), "{m}");
    assert!(m.contains("internal step 2 of 3") && m.contains("at t = 0.01 s"), "{m}");
}

#[test]
fn tau_is_held_and_reaches_the_acceleration_without_a_step() {
    let (mut inst, _) = started(&[("theta_start", 0.0)]);
    assert_eq!(inst.do_step(0.0, 0.01), Status::Ok);
    let alpha = get(&mut inst, "alpha");
    assert_eq!(set(&mut inst, "tau", 0.5), Status::Ok);
    let after = get(&mut inst, "alpha");
    assert!(after > alpha, "alpha depends on tau directly");
    // the same input again (fmpy sets every input every step) keeps the outputs
    let outs = outputs(&mut inst);
    assert_eq!(set(&mut inst, "tau", 0.5), Status::Ok);
    assert_eq!(outputs(&mut inst), outs);
    assert_eq!(get(&mut inst, "alpha"), after);
    let theta = get(&mut inst, "theta");
    assert_eq!(inst.do_step(0.01, 0.01), Status::Ok);
    assert!(
        get(&mut inst, "theta") > theta,
        "a positive torque turns the body counter-clockwise"
    );
    assert_eq!(get(&mut inst, "contact_count"), 0.0);
    assert!(get(&mut inst, "gap") > 0.0);
    let v = by_name("tau").unwrap();
    assert_eq!(v.kind, Kind::Real);
}

/// Steps a full and a reduced instance `steps` times by 10 ms, asserting every step and the reduced
/// one's total energy constant to 1e-12 of itself (the solver's tolerance); returns the largest
/// difference of their θ \[rad\].
fn side_by_side(full: &mut Instance, reduced: &mut Instance, log: &Log, steps: usize) -> f64 {
    let e0 = get(reduced, "total_energy");
    let mut worst: f64 = 0.0;
    for k in 0..steps {
        let t = 0.01 * k as f64;
        assert_eq!(full.do_step(t, 0.01), Status::Ok);
        assert_eq!(reduced.do_step(t, 0.01), Status::Ok, "{:?}", log.borrow());
        worst = worst.max((get(full, "theta") - get(reduced, "theta")).abs());
        let e = get(reduced, "total_energy");
        assert!((e - e0).abs() < 1e-12 * e0.abs(), "energy {e} against {e0} at step {k}");
    }
    worst
}

#[test]
fn the_reduced_body_runs_in_the_fmu_conserving_energy_and_near_the_full_model() {
    // model_kind = 1: the same swing within 1e-4 rad of the full body over 1 s at 10 ms (the bound
    // leaves room for the difference of the two time schemes' phase errors), its total energy
    // constant to 1e-12 of itself (the solver's tolerance)
    let (mut full, _) = started(&[]);
    let (mut reduced, log) = started(&[("model_kind", 1.0), ("modes", 4.0)]);
    let worst = side_by_side(&mut full, &mut reduced, &log, 100);
    assert!(worst > 0.0 && worst < 1e-4, "theta differs by {worst} rad");
    let (mut inst, log) = instance();
    inst.enter_initialization();
    assert_eq!(set(&mut inst, "model_kind", 2.0), Status::Ok);
    assert_eq!(inst.exit_initialization(), Status::Error);
    assert!(
        log.borrow().iter().any(|(_, m)| m.contains("model_kind = 2")),
        "{:?}",
        log.borrow()
    );
}

#[test]
fn the_reduced_body_strikes_the_deformable_wall_in_the_fmu_as_the_full_body_does() {
    // model_kind = 1 with wall_kind = 2: the block reduced beside the pendulum. Over 0.4 s at
    // 10 ms (one impact) θ stays within 1e-4 rad of the full body's and ω at 0.4 s within 5e-4
    // relative (the bounds leave room for the two schemes' phase errors at this step after the
    // impact), and the total energy is constant to 1e-12 of itself (the solver's tolerance)
    let (mut full, _) = started(&[("wall_kind", 2.0)]);
    let (mut reduced, log) = started(&[("wall_kind", 2.0), ("model_kind", 1.0)]);
    let worst = side_by_side(&mut full, &mut reduced, &log, 40);
    assert!(worst < 1e-4, "theta differs by {worst} rad");
    for inst in [&mut full, &mut reduced] {
        assert_eq!(get(inst, "contact_count"), 1.0, "one impact on the block");
    }
    let (wf, wr) = (get(&mut full, "omega"), get(&mut reduced, "omega"));
    assert!(
        wf > 0.0 && (wf - wr).abs() < 5e-4 * wf,
        "ω after the impact {wf} (full) and {wr} (reduced)"
    );
}

#[test]
fn a_rubber_reduced_body_in_the_fmu_logs_one_warning_that_it_does_not_apply_and_steps_on() {
    // E = 0.1 MPa is far outside the linear modes: the reduced body's error estimate exceeds its
    // warning bound (`reduced::validity::WARNING_BOUND`) from the start
    let params = [
        ("model_kind", 1.0),
        ("youngs_modulus", 1e5),
        ("poisson_ratio", 0.45),
        ("density", 1000.0),
    ];
    let (mut inst, log) = started(&params);
    for k in 0..10 {
        assert_eq!(inst.do_step(0.01 * k as f64, 0.01), Status::Ok, "{:?}", log.borrow());
    }
    let warnings: Vec<String> = log
        .borrow()
        .iter()
        .filter(|(status, _)| *status == Status::Warning)
        .map(|(_, m)| m.clone())
        .collect();
    assert!(
        warnings.len() == 1 && warnings[0].contains("does not apply") && warnings[0].contains("model.kind = \"full\""),
        "{warnings:?}"
    );
    // steel stays silent
    let (mut steel, log) = started(&[("model_kind", 1.0)]);
    assert_eq!(steel.do_step(0.0, 0.01), Status::Ok);
    assert!(
        log.borrow().iter().all(|(s, _)| *s != Status::Warning),
        "{:?}",
        log.borrow()
    );
}

#[test]
fn a_mesh_max_size_that_bounds_no_element_logs_the_mesh_warning_and_the_model_builds() {
    // the tutorial's local sizes are absolute: a larger max_size than the default changes nothing
    let (mut inst, log) = started(&[("mesh_max_size", 0.1)]);
    let warnings: Vec<String> = log
        .borrow()
        .iter()
        .filter(|(status, _)| *status == Status::Warning)
        .map(|(_, m)| m.clone())
        .collect();
    assert!(
        warnings.len() == 1 && warnings[0].contains("mesh.max_size = 0.1 m changes nothing"),
        "{warnings:?}"
    );
    assert_eq!(inst.do_step(0.0, 0.01), Status::Ok, "{:?}", log.borrow());
    // the default max_size warns of nothing
    let (_, log) = started(&[]);
    assert!(
        log.borrow().iter().all(|(s, _)| *s != Status::Warning),
        "{:?}",
        log.borrow()
    );
}

/// The warnings an instance logged.
fn warnings(log: &Log) -> Vec<String> {
    log.borrow()
        .iter()
        .filter(|(status, _)| *status == Status::Warning)
        .map(|(_, m)| m.clone())
        .collect()
}

#[test]
fn a_parameter_set_where_it_has_no_effect_logs_a_warning_naming_it_and_what_makes_it_act() {
    // no wall: the contact stiffness acts on nothing
    let (mut inst, log) = started(&[("contact_stiffness", 1e10)]);
    let w = warnings(&log);
    assert!(
        w.len() == 1
            && w[0].starts_with("parameter contact_stiffness: contact.stiffness = ")
            && w[0].contains("has no effect: there is no wall (set wall.kind to \"rigid\" or \"deformable\")")
            && w[0].contains("wall.kind is the parameter wall_kind"),
        "{w:?}"
    );
    assert_eq!(inst.do_step(0.0, 0.01), Status::Ok, "{:?}", log.borrow());
    // the full body has no modes
    let (_, log) = started(&[("modes", 4.0)]);
    let w = warnings(&log);
    assert!(
        w.len() == 1 && w[0].contains("model.modes = 4 has no effect") && w[0].contains("model_kind"),
        "{w:?}"
    );
    // where they act, they warn of nothing
    let (_, log) = started(&[("contact_stiffness", 1e10), ("wall_kind", 1.0)]);
    assert!(warnings(&log).is_empty(), "{:?}", log.borrow());
    let (_, log) = started(&[("modes", 4.0), ("model_kind", 1.0)]);
    assert!(warnings(&log).is_empty(), "{:?}", log.borrow());
}
