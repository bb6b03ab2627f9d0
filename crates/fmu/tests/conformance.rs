//! FMI 2.0 Co-Simulation conformance, through the exported C functions as an importer calls them:
//! every call the state machine forbids returns `fmi2Error` with a logged message naming the
//! function and the state (and changes nothing); null arrays, bad step sizes, a communication point
//! off the FMU's time and damaged serialized states are refused; a caught panic leaves the instance
//! in an error state that only `fmi2Reset` (or `fmi2FreeInstance`) leaves; a step that would need
//! too many internal steps is refused at once; `fmi2Reset` replays a run bit for bit.
//!
//! The logger here is a plain six-argument C function: the FMU calls the variadic
//! `fmi2CallbackLogger` always with the format `"%s"` and one string, which the x86-64 System V and
//! AArch64 Linux calling conventions pass where a fixed sixth argument is read (fmpy's logger type
//! relies on the same).
//!
//! One claim, the FMI 2.0 state machine through the raw C ABI, past 600 lines because every
//! forbidden call is a test of its own.

#![allow(non_snake_case)]

use std::cell::RefCell;
use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::time::Instant;

use pendulum_fem_fmu::variables::{by_name, guid, Kind, Role, VARIABLES};
use pendulum_fem_fmu::Instance;

type Component = *mut c_void;
type State = *mut c_void;
type Logger = unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char, *const c_char);

#[repr(C)]
struct CallbackFunctions {
    logger: Option<Logger>,
    allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    step_finished: Option<unsafe extern "C" fn(*mut c_void, c_int)>,
    component_environment: *mut c_void,
}

const OK: c_int = 0;
const ERROR: c_int = 3;
const CO_SIMULATION: c_int = 1;
const LAST_SUCCESSFUL_TIME: c_int = 2;

extern "C" {
    fn fmi2Instantiate(
        name: *const c_char,
        fmu_type: c_int,
        guid: *const c_char,
        resources: *const c_char,
        functions: *const CallbackFunctions,
        visible: c_int,
        logging_on: c_int,
    ) -> Component;
    fn fmi2FreeInstance(c: Component);
    fn fmi2SetDebugLogging(c: Component, on: c_int, n: usize, categories: *const *const c_char) -> c_int;
    fn fmi2SetupExperiment(
        c: Component,
        tol_defined: c_int,
        tol: f64,
        t0: f64,
        stop_defined: c_int,
        stop: f64,
    ) -> c_int;
    fn fmi2EnterInitializationMode(c: Component) -> c_int;
    fn fmi2ExitInitializationMode(c: Component) -> c_int;
    fn fmi2Terminate(c: Component) -> c_int;
    fn fmi2Reset(c: Component) -> c_int;
    fn fmi2GetReal(c: Component, vr: *const c_uint, nvr: usize, value: *mut f64) -> c_int;
    fn fmi2GetInteger(c: Component, vr: *const c_uint, nvr: usize, value: *mut c_int) -> c_int;
    fn fmi2GetBoolean(c: Component, vr: *const c_uint, nvr: usize, value: *mut c_int) -> c_int;
    fn fmi2GetString(c: Component, vr: *const c_uint, nvr: usize, value: *mut *const c_char) -> c_int;
    fn fmi2SetReal(c: Component, vr: *const c_uint, nvr: usize, value: *const f64) -> c_int;
    fn fmi2SetInteger(c: Component, vr: *const c_uint, nvr: usize, value: *const c_int) -> c_int;
    fn fmi2SetBoolean(c: Component, vr: *const c_uint, nvr: usize, value: *const c_int) -> c_int;
    fn fmi2SetString(c: Component, vr: *const c_uint, nvr: usize, value: *const *const c_char) -> c_int;
    fn fmi2GetFMUstate(c: Component, state: *mut State) -> c_int;
    fn fmi2SetFMUstate(c: Component, state: State) -> c_int;
    fn fmi2FreeFMUstate(c: Component, state: *mut State) -> c_int;
    fn fmi2SerializedFMUstateSize(c: Component, state: State, size: *mut usize) -> c_int;
    fn fmi2SerializeFMUstate(c: Component, state: State, bytes: *mut c_char, size: usize) -> c_int;
    fn fmi2DeSerializeFMUstate(c: Component, bytes: *const c_char, size: usize, state: *mut State) -> c_int;
    fn fmi2DoStep(c: Component, t: f64, h: f64, no_set_prior: c_int) -> c_int;
    fn fmi2CancelStep(c: Component) -> c_int;
    fn fmi2GetStatus(c: Component, kind: c_int, value: *mut c_int) -> c_int;
    fn fmi2GetRealStatus(c: Component, kind: c_int, value: *mut f64) -> c_int;
    fn fmi2GetBooleanStatus(c: Component, kind: c_int, value: *mut c_int) -> c_int;
    fn fmi2EnterEventMode(c: Component) -> c_int;
    fn fmi2GetDerivatives(c: Component, dx: *mut f64, nx: usize) -> c_int;
    fn fmi2GetDirectionalDerivative(
        c: Component,
        unknown: *const c_uint,
        n_unknown: usize,
        known: *const c_uint,
        n_known: usize,
        dv_known: *const f64,
        dv_unknown: *mut f64,
    ) -> c_int;
    fn fmi2SetRealInputDerivatives(
        c: Component,
        vr: *const c_uint,
        nvr: usize,
        order: *const c_int,
        value: *const f64,
    ) -> c_int;
    fn fmi2GetRealOutputDerivatives(
        c: Component,
        vr: *const c_uint,
        nvr: usize,
        order: *const c_int,
        value: *mut f64,
    ) -> c_int;
}

/// Messages the FMU logged: `(status, message)`.
type Log = RefCell<Vec<(c_int, String)>>;

unsafe extern "C" fn logger(
    env: *mut c_void,
    _name: *const c_char,
    status: c_int,
    _category: *const c_char,
    format: *const c_char,
    message: *const c_char,
) {
    // SAFETY: `env` is the `Log` of the `Fmu` that owns the instance; the FMU passes the format
    // "%s" and one NUL-terminated message (anything else is recorded as such, never read).
    unsafe {
        let format = CStr::from_ptr(format).to_string_lossy();
        let text = match format.as_ref() {
            "%s" => CStr::from_ptr(message).to_string_lossy().into_owned(),
            other => format!("logger called with the format {other:?}, not \"%s\""),
        };
        (*env.cast::<Log>()).borrow_mut().push((status, text));
    }
}

fn vr(name: &str) -> c_uint {
    by_name(name).unwrap_or_else(|| panic!("no variable {name}")).vr
}

/// One instance through the C interface, with its log; freed on drop.
struct Fmu {
    c: Component,
    log: Box<Log>,
}

impl Fmu {
    /// `fmi2Instantiate` (the instantiated state).
    fn new(name: &str) -> Self {
        Self::instantiate(name, CO_SIMULATION, &guid()).unwrap_or_else(|log| panic!("fmi2Instantiate failed: {log:?}"))
    }

    /// `fmi2Instantiate` with `fmu_type` and `guid`: the instance, or what it logged when it
    /// returned null.
    fn instantiate(name: &str, fmu_type: c_int, guid: &str) -> Result<Self, Vec<(c_int, String)>> {
        let log: Box<Log> = Box::default();
        let callbacks = CallbackFunctions {
            logger: Some(logger),
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: (&*log as *const Log).cast_mut().cast(),
        };
        let (name, guid) = (CString::new(name).unwrap(), CString::new(guid).unwrap());
        // SAFETY: NUL-terminated strings and a callback structure valid for the call; the log it
        // points to lives as long as the instance (both are owned by the returned value).
        let c = unsafe { fmi2Instantiate(name.as_ptr(), fmu_type, guid.as_ptr(), c"".as_ptr(), &callbacks, 0, 0) };
        if c.is_null() {
            return Err(log.take());
        }
        Ok(Self { c, log })
    }

    /// Set up at `t0`, initialised with `params` (step mode).
    fn started(t0: f64, params: &[(&str, f64)]) -> Self {
        let fmu = Self::new("started");
        fmu.start(t0, params);
        fmu
    }

    fn start(&self, t0: f64, params: &[(&str, f64)]) {
        // SAFETY: a live instance (here and in every method below).
        unsafe {
            assert_eq!(fmi2SetupExperiment(self.c, 0, 0.0, t0, 0, 0.0), OK, "{:?}", self.log);
            assert_eq!(fmi2EnterInitializationMode(self.c), OK, "{:?}", self.log);
        }
        for &(name, value) in params {
            assert_eq!(self.set(name, value), OK, "{name} = {value}: {:?}", self.log);
        }
        assert_eq!(unsafe { fmi2ExitInitializationMode(self.c) }, OK, "{:?}", self.log);
    }

    /// Sets a variable of any type by name.
    fn set(&self, name: &str, value: f64) -> c_int {
        let v = by_name(name).expect("variable");
        // SAFETY: one value reference and one value.
        unsafe {
            match v.kind {
                Kind::Real => fmi2SetReal(self.c, &v.vr, 1, &value),
                Kind::Integer => fmi2SetInteger(self.c, &v.vr, 1, &(value as c_int)),
                Kind::Boolean => fmi2SetBoolean(self.c, &v.vr, 1, &c_int::from(value != 0.0)),
            }
        }
    }

    /// Reads a variable of any type by name: `(status, value)`.
    fn get(&self, name: &str) -> (c_int, f64) {
        let v = by_name(name).expect("variable");
        // SAFETY: one value reference and room for one value.
        unsafe {
            match v.kind {
                Kind::Real => {
                    let mut x = f64::NAN;
                    (fmi2GetReal(self.c, &v.vr, 1, &mut x), x)
                }
                Kind::Integer => {
                    let mut x: c_int = -1;
                    (fmi2GetInteger(self.c, &v.vr, 1, &mut x), f64::from(x))
                }
                Kind::Boolean => {
                    let mut x: c_int = -1;
                    (fmi2GetBoolean(self.c, &v.vr, 1, &mut x), f64::from(x))
                }
            }
        }
    }

    /// Every output as IEEE bits (panics unless each read is OK).
    fn outputs(&self) -> Vec<u64> {
        VARIABLES
            .iter()
            .filter(|v| matches!(v.role, Role::Output(_)))
            .map(|v| {
                let (status, x) = self.get(v.name);
                assert_eq!(status, OK, "{}: {:?}", v.name, self.log);
                x.to_bits()
            })
            .collect()
    }

    fn step(&self, t: f64, h: f64) -> c_int {
        // SAFETY: a live instance.
        unsafe { fmi2DoStep(self.c, t, h, 0) }
    }

    /// The FMU's time (`fmi2GetRealStatus(fmi2LastSuccessfulTime)`).
    fn time(&self) -> f64 {
        let mut t = f64::NAN;
        // SAFETY: room for one value.
        assert_eq!(
            unsafe { fmi2GetRealStatus(self.c, LAST_SUCCESSFUL_TIME, &mut t) },
            OK,
            "{:?}",
            self.log
        );
        t
    }

    /// The current FMU state, serialized.
    fn serialized_state(&self) -> Vec<u8> {
        let mut state: State = std::ptr::null_mut();
        let mut size = 0usize;
        // SAFETY: a state slot, a size and a buffer of that size.
        unsafe {
            assert_eq!(fmi2GetFMUstate(self.c, &mut state), OK, "{:?}", self.log);
            assert_eq!(fmi2SerializedFMUstateSize(self.c, state, &mut size), OK);
            let mut bytes = vec![0u8; size];
            assert_eq!(
                fmi2SerializeFMUstate(self.c, state, bytes.as_mut_ptr().cast(), size),
                OK
            );
            assert_eq!(fmi2FreeFMUstate(self.c, &mut state), OK);
            bytes
        }
    }

    /// `fmi2DeSerializeFMUstate` then, if that worked, `fmi2SetFMUstate`; the state is freed.
    fn deserialize_and_set(&self, bytes: &[u8]) -> (c_int, c_int) {
        let mut state: State = std::ptr::null_mut();
        // SAFETY: `bytes.len()` bytes and a state slot.
        unsafe {
            let read = fmi2DeSerializeFMUstate(self.c, bytes.as_ptr().cast(), bytes.len(), &mut state);
            if read != OK {
                assert!(state.is_null(), "a refused buffer makes no state");
                return (read, ERROR);
            }
            let set = fmi2SetFMUstate(self.c, state);
            assert_eq!(fmi2FreeFMUstate(self.c, &mut state), OK);
            (read, set)
        }
    }

    /// Asserts `status` is `fmi2Error` and a message logged since the last check contains every
    /// needle; forgets the log.
    #[track_caller]
    fn assert_refused(&self, status: c_int, needles: &[&str]) {
        let log = std::mem::take(&mut *self.log.borrow_mut());
        assert_eq!(status, ERROR, "expected fmi2Error ({needles:?}); log {log:?}");
        assert!(
            log.iter()
                .any(|(s, m)| *s == ERROR && needles.iter().all(|n| m.contains(n))),
            "no error message with {needles:?} in {log:?}"
        );
    }

    /// Forgets the log.
    fn clear_log(&self) {
        self.log.borrow_mut().clear();
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        // SAFETY: the instance of this value, freed once.
        unsafe { fmi2FreeInstance(self.c) };
    }
}

/// A call that may be forbidden, with the function name its message must carry.
type Call = (&'static str, fn(&Fmu) -> c_int);

/// A state of the state machine: its name in messages, how to reach it from a new instance, and the
/// calls FMI 2.0 forbids in it.
type Forbidden = (&'static str, fn(&Fmu), &'static [Call]);

fn setup_experiment(f: &Fmu) -> c_int {
    // SAFETY: a live instance.
    unsafe { fmi2SetupExperiment(f.c, 0, 0.0, 0.0, 0, 0.0) }
}
fn enter_initialization(f: &Fmu) -> c_int {
    // SAFETY: a live instance.
    unsafe { fmi2EnterInitializationMode(f.c) }
}
fn exit_initialization(f: &Fmu) -> c_int {
    // SAFETY: a live instance.
    unsafe { fmi2ExitInitializationMode(f.c) }
}
fn terminate(f: &Fmu) -> c_int {
    // SAFETY: a live instance.
    unsafe { fmi2Terminate(f.c) }
}
fn do_step(f: &Fmu) -> c_int {
    f.step(0.0, 0.01)
}
fn get_theta(f: &Fmu) -> c_int {
    f.get("theta").0
}
fn get_contact_count(f: &Fmu) -> c_int {
    f.get("contact_count").0
}
fn get_impact(f: &Fmu) -> c_int {
    f.get("impact").0
}
fn set_theta_start(f: &Fmu) -> c_int {
    f.set("theta_start", 0.2)
}
fn set_wall_kind(f: &Fmu) -> c_int {
    f.set("wall_kind", 1.0)
}
fn set_tau(f: &Fmu) -> c_int {
    f.set("tau", 0.1)
}
fn get_real_status(f: &Fmu) -> c_int {
    let mut t = 0.0;
    // SAFETY: room for one value.
    unsafe { fmi2GetRealStatus(f.c, LAST_SUCCESSFUL_TIME, &mut t) }
}

#[test]
fn do_step_before_initialisation_is_an_error_naming_the_state() {
    let fmu = Fmu::new("early");
    fmu.assert_refused(fmu.step(0.0, 0.01), &["fmi2DoStep", "instantiated state"]);
    assert_eq!(setup_experiment(&fmu), OK);
    assert_eq!(enter_initialization(&fmu), OK);
    fmu.assert_refused(fmu.step(0.0, 0.01), &["fmi2DoStep", "initialization mode state"]);
    assert_eq!(exit_initialization(&fmu), OK, "refused calls changed nothing");
    assert_eq!(fmu.step(0.0, 0.01), OK);
}

#[test]
fn do_step_and_setting_the_input_after_terminate_are_errors_naming_the_state() {
    let fmu = Fmu::started(0.0, &[]);
    assert_eq!(fmu.step(0.0, 0.01), OK);
    let before = fmu.outputs();
    assert_eq!(terminate(&fmu), OK);
    fmu.assert_refused(fmu.step(0.01, 0.01), &["fmi2DoStep", "terminated state"]);
    fmu.assert_refused(fmu.set("tau", 0.5), &["fmi2SetReal", "terminated state"]);
    assert_eq!(fmu.outputs(), before, "outputs can still be read, unchanged");
    assert_eq!(fmu.get("tau"), (OK, 0.0));
}

#[test]
fn a_fixed_parameter_set_in_step_mode_is_an_error_naming_it_and_the_state() {
    let fmu = Fmu::started(0.0, &[("theta_start", 0.3)]);
    fmu.assert_refused(
        fmu.set("theta_start", 0.2),
        &["fmi2SetReal", "theta_start", "step mode state"],
    );
    fmu.assert_refused(
        fmu.set("wall_kind", 1.0),
        &["fmi2SetInteger", "wall_kind", "step mode state"],
    );
    assert_eq!(fmu.get("theta_start"), (OK, 0.3));
    assert_eq!(fmu.get("wall_kind"), (OK, 0.0));
    assert_eq!(fmu.set("tau", 0.1), OK, "the input is settable in step mode");
    assert_eq!(fmu.step(0.0, 0.01), OK);
}

#[test]
fn terminate_returns_ok_from_step_mode_only() {
    let fmu = Fmu::new("terminate");
    fmu.assert_refused(terminate(&fmu), &["fmi2Terminate", "instantiated state"]);
    assert_eq!(setup_experiment(&fmu), OK);
    assert_eq!(enter_initialization(&fmu), OK);
    fmu.assert_refused(terminate(&fmu), &["fmi2Terminate", "initialization mode state"]);
    assert_eq!(exit_initialization(&fmu), OK);
    assert_eq!(terminate(&fmu), OK);
    fmu.assert_refused(terminate(&fmu), &["fmi2Terminate", "terminated state"]);
}

#[test]
fn every_call_the_state_machine_forbids_is_an_error_naming_function_and_state() {
    let table: [Forbidden; 4] = [
        (
            "instantiated state",
            |_| {},
            &[
                ("fmi2ExitInitializationMode", exit_initialization),
                ("fmi2Terminate", terminate),
                ("fmi2DoStep", do_step),
                ("fmi2GetReal", get_theta),
                ("fmi2GetInteger", get_contact_count),
                ("fmi2GetBoolean", get_impact),
                ("fmi2GetRealStatus", get_real_status),
            ],
        ),
        (
            "initialization mode state",
            |f| {
                assert_eq!(setup_experiment(f), OK);
                assert_eq!(enter_initialization(f), OK);
            },
            &[
                ("fmi2SetupExperiment", setup_experiment),
                ("fmi2EnterInitializationMode", enter_initialization),
                ("fmi2Terminate", terminate),
                ("fmi2DoStep", do_step),
                ("fmi2GetRealStatus", get_real_status),
            ],
        ),
        (
            "step mode state",
            |f| f.start(0.0, &[]),
            &[
                ("fmi2SetupExperiment", setup_experiment),
                ("fmi2EnterInitializationMode", enter_initialization),
                ("fmi2ExitInitializationMode", exit_initialization),
                ("fmi2SetReal", set_theta_start),
                ("fmi2SetInteger", set_wall_kind),
            ],
        ),
        (
            "terminated state",
            |f| {
                f.start(0.0, &[]);
                assert_eq!(terminate(f), OK);
            },
            &[
                ("fmi2SetupExperiment", setup_experiment),
                ("fmi2EnterInitializationMode", enter_initialization),
                ("fmi2ExitInitializationMode", exit_initialization),
                ("fmi2Terminate", terminate),
                ("fmi2DoStep", do_step),
                ("fmi2SetReal", set_tau),
                ("fmi2SetReal", set_theta_start),
                ("fmi2SetInteger", set_wall_kind),
            ],
        ),
    ];
    for (state, reach, calls) in table {
        let fmu = Fmu::new(state);
        reach(&fmu);
        fmu.clear_log();
        for &(function, call) in calls {
            fmu.assert_refused(call(&fmu), &[function, state]);
        }
    }
    // a refused call is no transition: the run goes on
    let fmu = Fmu::started(0.0, &[]);
    fmu.assert_refused(
        enter_initialization(&fmu),
        &["fmi2EnterInitializationMode", "step mode"],
    );
    assert_eq!(fmu.step(0.0, 0.01), OK);
}

#[test]
fn null_arrays_with_values_to_read_or_write_are_errors() {
    let fmu = Fmu::started(0.0, &[]);
    let (real, integer, boolean) = (vr("theta"), vr("contact_count"), vr("impact"));
    let (tau, wall) = (vr("tau"), vr("wall_kind"));
    let null_vr: *const c_uint = std::ptr::null();
    let (mut x, mut i, mut s): (f64, c_int, *const c_char) = (0.0, 0, std::ptr::null());
    let text = c"x".as_ptr();
    // SAFETY: every non-null pointer points to one value; null ones come with nvr = 1 (refused
    // before they are read) or nvr = 0.
    unsafe {
        let cases: [(&str, c_int, c_int); 8] = [
            (
                "fmi2GetReal",
                fmi2GetReal(fmu.c, null_vr, 1, &mut x),
                fmi2GetReal(fmu.c, &real, 1, std::ptr::null_mut()),
            ),
            (
                "fmi2GetInteger",
                fmi2GetInteger(fmu.c, null_vr, 1, &mut i),
                fmi2GetInteger(fmu.c, &integer, 1, std::ptr::null_mut()),
            ),
            (
                "fmi2GetBoolean",
                fmi2GetBoolean(fmu.c, null_vr, 1, &mut i),
                fmi2GetBoolean(fmu.c, &boolean, 1, std::ptr::null_mut()),
            ),
            (
                "fmi2GetString",
                fmi2GetString(fmu.c, null_vr, 1, &mut s),
                fmi2GetString(fmu.c, &real, 1, std::ptr::null_mut()),
            ),
            (
                "fmi2SetReal",
                fmi2SetReal(fmu.c, null_vr, 1, &0.1),
                fmi2SetReal(fmu.c, &tau, 1, std::ptr::null()),
            ),
            (
                "fmi2SetInteger",
                fmi2SetInteger(fmu.c, null_vr, 1, &1),
                fmi2SetInteger(fmu.c, &wall, 1, std::ptr::null()),
            ),
            (
                "fmi2SetBoolean",
                fmi2SetBoolean(fmu.c, null_vr, 1, &1),
                fmi2SetBoolean(fmu.c, &wall, 1, std::ptr::null()),
            ),
            (
                "fmi2SetString",
                fmi2SetString(fmu.c, null_vr, 1, &text),
                fmi2SetString(fmu.c, &tau, 1, std::ptr::null()),
            ),
        ];
        let log = fmu.log.borrow().clone();
        for (function, null_vr_status, null_value_status) in cases {
            for (status, array) in [(null_vr_status, "vr is null"), (null_value_status, "value is null")] {
                assert_eq!(status, ERROR, "{function} with {array}");
                assert!(
                    log.iter()
                        .any(|(s, m)| *s == ERROR && m.starts_with(function) && m.contains(array)),
                    "{function}: no message with `{array}` in {log:?}"
                );
            }
        }
        // no values at all: nothing to read, nothing refused
        assert_eq!(fmi2GetReal(fmu.c, null_vr, 0, std::ptr::null_mut()), OK);
        assert_eq!(fmi2SetReal(fmu.c, null_vr, 0, std::ptr::null()), OK);
        assert_eq!(fmi2GetString(fmu.c, null_vr, 0, std::ptr::null_mut()), OK);
    }
    assert_eq!(fmu.get("tau"), (OK, 0.0), "nothing was set");
    assert_eq!(fmu.step(0.0, 0.01), OK);
}

#[test]
fn a_negative_or_non_finite_step_size_is_an_error_and_changes_nothing() {
    let fmu = Fmu::started(0.0, &[]);
    let before = fmu.outputs();
    for h in [-0.01, -1e-300, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        fmu.assert_refused(fmu.step(0.0, h), &["fmi2DoStep", "communicationStepSize"]);
    }
    assert_eq!(fmu.outputs(), before);
    assert_eq!(fmu.time(), 0.0);
}

#[test]
fn a_communication_point_off_by_a_masters_rounding_is_accepted_and_a_real_mismatch_refused() {
    let fmu = Fmu::started(0.0, &[]);
    assert_eq!(fmu.step(0.0, 0.01), OK);
    // syssimx's bisection: points about 1e-8 s off the FMU's time, either side
    assert_eq!(fmu.step(0.01 + 1e-8, 0.0), OK);
    assert_eq!(fmu.step(0.01 - 1e-8, 0.01), OK, "{:?}", fmu.log);
    assert_eq!(fmu.time(), 0.02, "the FMU keeps its own clock");
    let before = fmu.outputs();
    for t in [0.02 + 1e-4, 0.02 - 1e-4, 0.03, 0.0, f64::NAN] {
        fmu.assert_refused(fmu.step(t, 0.01), &["fmi2DoStep", "currentCommunicationPoint", "0.02"]);
    }
    assert_eq!(fmu.outputs(), before);
    assert_eq!(fmu.time(), 0.02);
}

/// A small deterministic generator of garbage (xorshift64).
fn garbage(seed: u64, n: usize) -> Vec<u8> {
    let mut x = seed;
    (0..n)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x as u8
        })
        .collect()
}

#[test]
fn garbage_bytes_to_deserialize_are_refused() {
    let fmu = Fmu::started(0.0, &[("theta_start", 0.3)]);
    assert_eq!(fmu.step(0.0, 0.01), OK);
    let good = fmu.serialized_state();
    let before = fmu.outputs();
    let mut damaged: Vec<(String, Vec<u8>)> = Vec::new();
    for (seed, n) in [(1, 0), (2, 1), (3, 33), (4, 1000), (5, good.len())] {
        damaged.push((format!("{n} random bytes"), garbage(seed, n)));
    }
    let mut header = good[..8].to_vec();
    header.extend(garbage(6, good.len() - 8));
    damaged.push(("the magic and random bytes".into(), header));
    for n in [7, 8, 33, 41, good.len() / 2, good.len() - 8, good.len() - 1] {
        damaged.push((format!("truncated to {n} bytes"), good[..n].to_vec()));
    }
    let mut longer = good.clone();
    longer.push(0);
    damaged.push(("one byte appended".into(), longer));
    for at in [3, 12, good.len() / 2] {
        let mut flipped = good.clone();
        flipped[at] ^= 0xff;
        damaged.push((format!("byte {at} of {} flipped", good.len()), flipped));
    }
    for (what, bytes) in damaged {
        let (read, _) = fmu.deserialize_and_set(&bytes);
        fmu.assert_refused(read, &["fmi2DeSerializeFMUstate", "serialized FMU state"]);
        assert_eq!(fmu.outputs(), before, "{what}: the instance is unchanged");
    }
    assert_eq!(
        fmu.deserialize_and_set(&good),
        (OK, OK),
        "the intact bytes still restore"
    );
}

#[test]
fn a_flipped_bit_anywhere_in_a_serialized_state_is_refused() {
    let fmu = Fmu::started(0.0, &[]);
    assert_eq!(fmu.set("tau", 0.25), OK);
    for k in 0..3 {
        assert_eq!(fmu.step(f64::from(k) * 0.01, 0.01), OK);
    }
    let good = fmu.serialized_state();
    // the header (magic, tau, impact flag, last internal step, start time: 33 bytes) byte by byte,
    // then bytes spread over the snapshot and the trailing checksum
    let body = (33..good.len()).step_by(good.len() / 97);
    for at in (0..33).chain(body).chain(good.len() - 8..good.len()) {
        for bit in [0, 5] {
            let mut flipped = good.clone();
            flipped[at] ^= 1 << bit;
            let (read, _) = fmu.deserialize_and_set(&flipped);
            assert_eq!(read, ERROR, "bit {bit} of byte {at} (of {}) flipped", good.len());
        }
    }
    fmu.clear_log();
    assert_eq!(fmu.deserialize_and_set(&good), (OK, OK));
}

#[test]
fn a_state_serialized_at_a_nonzero_start_time_restores_the_time() {
    let t0 = 2.5;
    let a = Fmu::started(t0, &[("theta_start", 0.3)]);
    for k in 0..3 {
        assert_eq!(a.step(t0 + f64::from(k) * 0.01, 0.01), OK, "{:?}", a.log);
    }
    let t = a.time();
    assert!((t - 2.53).abs() < 1e-12, "{t}");
    let bytes = a.serialized_state();

    let b = Fmu::started(0.0, &[("theta_start", 0.3)]);
    assert_eq!(b.deserialize_and_set(&bytes), (OK, OK), "{:?}", b.log);
    assert_eq!(b.time().to_bits(), t.to_bits(), "the start time came with the state");
    b.assert_refused(b.step(0.0, 0.01), &["fmi2DoStep", "currentCommunicationPoint"]);
    assert_eq!(a.step(t, 0.01), OK);
    assert_eq!(b.step(t, 0.01), OK, "{:?}", b.log);
    assert_eq!(a.outputs(), b.outputs());
    assert_eq!(a.time().to_bits(), b.time().to_bits());
}

#[test]
fn a_step_needing_too_many_internal_steps_is_refused_at_once() {
    let fmu = Fmu::started(0.0, &[("max_internal_step", 1e-300)]);
    let before = fmu.outputs();
    let start = Instant::now();
    let status = fmu.step(0.0, 0.01);
    let took = start.elapsed();
    fmu.assert_refused(status, &["fmi2DoStep", "internal steps", "1000000"]);
    assert!(took.as_secs_f64() < 1.0, "refused after {took:?}");
    assert_eq!(fmu.outputs(), before);
    assert_eq!(fmu.time(), 0.0);
}

#[test]
fn a_caught_panic_leaves_the_instance_in_an_error_state_that_only_reset_leaves() {
    let fmu = Fmu::started(0.0, &[]);
    assert_eq!(fmu.step(0.0, 0.01), OK);
    let mut saved: State = std::ptr::null_mut();
    // SAFETY: a state slot.
    assert_eq!(unsafe { fmi2GetFMUstate(fmu.c, &mut saved) }, OK);
    let bytes = fmu.serialized_state();

    // SAFETY: an fmi2Component is the `Box<Instance>` that fmi2Instantiate made (ffi's contract);
    // no call on it is running.
    unsafe { &mut *fmu.c.cast::<Instance>() }.panic_on_next_call("provoked by the test");
    fmu.assert_refused(
        fmu.step(0.01, 0.01),
        &["fmi2DoStep", "internal error", "provoked by the test"],
    );

    let why = [
        "error state",
        "fmi2DoStep failed with an internal error",
        "provoked by the test",
        "fmi2Reset",
    ];
    let calls: [(&str, &dyn Fn() -> c_int); 22] = [
        ("fmi2DoStep", &|| fmu.step(0.01, 0.01)),
        ("fmi2DoStep", &|| fmu.step(0.01, 0.0)),
        ("fmi2GetReal", &|| fmu.get("theta").0),
        ("fmi2GetInteger", &|| fmu.get("contact_count").0),
        ("fmi2GetBoolean", &|| fmu.get("impact").0),
        ("fmi2SetReal", &|| fmu.set("tau", 0.1)),
        ("fmi2SetInteger", &|| fmu.set("wall_kind", 1.0)),
        ("fmi2SetBoolean", &|| unsafe {
            fmi2SetBoolean(fmu.c, std::ptr::null(), 0, std::ptr::null())
        }),
        ("fmi2GetString", &|| unsafe {
            fmi2GetString(fmu.c, std::ptr::null(), 0, std::ptr::null_mut())
        }),
        ("fmi2SetString", &|| unsafe {
            fmi2SetString(fmu.c, std::ptr::null(), 0, std::ptr::null())
        }),
        ("fmi2SetDebugLogging", &|| unsafe {
            fmi2SetDebugLogging(fmu.c, 1, 0, std::ptr::null())
        }),
        ("fmi2SetupExperiment", &|| setup_experiment(&fmu)),
        ("fmi2EnterInitializationMode", &|| enter_initialization(&fmu)),
        ("fmi2ExitInitializationMode", &|| exit_initialization(&fmu)),
        ("fmi2Terminate", &|| terminate(&fmu)),
        ("fmi2GetFMUstate", &|| {
            let mut s: State = std::ptr::null_mut();
            unsafe { fmi2GetFMUstate(fmu.c, &mut s) }
        }),
        ("fmi2SetFMUstate", &|| unsafe { fmi2SetFMUstate(fmu.c, saved) }),
        ("fmi2SerializedFMUstateSize", &|| {
            let mut n = 0usize;
            unsafe { fmi2SerializedFMUstateSize(fmu.c, saved, &mut n) }
        }),
        ("fmi2DeSerializeFMUstate", &|| fmu.deserialize_and_set(&bytes).0),
        ("fmi2GetRealStatus", &|| get_real_status(&fmu)),
        ("fmi2GetStatus", &|| {
            let mut s: c_int = 0;
            unsafe { fmi2GetStatus(fmu.c, 0, &mut s) }
        }),
        ("fmi2GetBooleanStatus", &|| {
            let mut s: c_int = 0;
            unsafe { fmi2GetBooleanStatus(fmu.c, 3, &mut s) }
        }),
    ];
    for (function, call) in calls {
        fmu.assert_refused(call(), &[&[function][..], &why[..]].concat());
    }
    // SAFETY: a live instance.
    fmu.assert_refused(unsafe { fmi2CancelStep(fmu.c) }, &["fmi2CancelStep", "error state"]);

    // freeing the master's state only releases memory: allowed
    // SAFETY: the state taken above, freed once.
    assert_eq!(unsafe { fmi2FreeFMUstate(fmu.c, &mut saved) }, OK);
    assert!(saved.is_null());

    // SAFETY: a live instance.
    assert_eq!(unsafe { fmi2Reset(fmu.c) }, OK, "{:?}", fmu.log);
    fmu.clear_log();
    fmu.start(0.0, &[]);
    assert_eq!(
        fmu.step(0.0, 0.01),
        OK,
        "after fmi2Reset the instance runs again: {:?}",
        fmu.log
    );
}

#[test]
fn a_panic_in_any_state_is_caught_and_the_instance_can_still_be_freed() {
    for started in [false, true] {
        let fmu = if started {
            Fmu::started(0.0, &[])
        } else {
            Fmu::new("fresh")
        };
        // SAFETY: as in the test above.
        unsafe { &mut *fmu.c.cast::<Instance>() }.panic_on_next_call("provoked by the test");
        fmu.assert_refused(setup_experiment(&fmu), &["fmi2SetupExperiment", "internal error"]);
        fmu.assert_refused(fmu.get("theta_start").0, &["fmi2GetReal", "error state"]);
        // dropping frees the instance (fmi2FreeInstance is allowed in the error state)
    }
}

/// 30 steps of 0.01 s with a torque sequence; the outputs of each step as bits.
fn torque_run(fmu: &Fmu) -> Vec<Vec<u64>> {
    fmu.start(0.0, &[("theta_start", 0.3), ("omega_start", -0.5)]);
    let mut out = vec![fmu.outputs()];
    for k in 0..30 {
        let t = f64::from(k) * 0.01;
        assert_eq!(fmu.set("tau", 0.4 * (7.0 * t).sin()), OK);
        assert_eq!(fmu.step(t, 0.01), OK, "step {k}: {:?}", fmu.log);
        out.push(fmu.outputs());
    }
    out
}

#[test]
fn reset_returns_to_the_instantiated_state_and_a_second_run_replays_the_first_bit_for_bit() {
    let fmu = Fmu::new("replay");
    let first = torque_run(&fmu);
    // SAFETY: a live instance.
    assert_eq!(unsafe { fmi2Reset(fmu.c) }, OK);
    fmu.assert_refused(fmu.step(0.3, 0.01), &["fmi2DoStep", "instantiated state"]);
    fmu.assert_refused(fmu.get("theta").0, &["fmi2GetReal", "instantiated state"]);
    let second = torque_run(&fmu);
    assert_eq!(first.len(), 31);
    for (k, (a, b)) in first.iter().zip(&second).enumerate() {
        assert_eq!(a, b, "outputs after step {k}");
    }
    let last = f64::from(29) * 0.01;
    assert_eq!(fmu.get("tau"), (OK, 0.4 * (7.0 * last).sin()));

    // a reset from step mode in the middle of a run, and from the terminated state, also replays
    // SAFETY: a live instance.
    unsafe {
        assert_eq!(fmi2Reset(fmu.c), OK);
        fmu.start(0.0, &[("theta_start", 0.1)]);
        assert_eq!(fmu.step(0.0, 0.05), OK);
        assert_eq!(fmi2Reset(fmu.c), OK);
    }
    assert_eq!(torque_run(&fmu), first);
    // SAFETY: a live instance.
    unsafe {
        assert_eq!(fmi2Terminate(fmu.c), OK);
        assert_eq!(fmi2Reset(fmu.c), OK);
    }
    assert_eq!(torque_run(&fmu), first);
}

#[test]
fn a_torque_input_beyond_the_hubs_limit_is_refused_naming_the_limit_and_changes_nothing() {
    // the default geometry at E = 1e6 Pa: the hinge edge's traction stress is 3 |M| / (2 t w²)
    // = 6.67e5 Pa per N·m (w = 0.015 m, t = 0.01 m), so a fifth of the modulus is 0.3 N·m
    let fmu = Fmu::started(0.0, &[("youngs_modulus", 1e6)]);
    assert_eq!(fmu.set("tau", 0.25), OK, "{:?}", fmu.log);
    assert_eq!(fmu.step(0.0, 0.01), OK, "{:?}", fmu.log);
    let before = fmu.outputs();
    for tau in [-0.5, 0.31, 40.0] {
        fmu.assert_refused(fmu.set("tau", tau), &["tau", "outside the model", "at most 0.3 N·m"]);
    }
    assert_eq!(fmu.outputs(), before, "a refused input changes no output");
    // the held torque is still the last accepted one
    assert_eq!(fmu.get("tau"), (OK, 0.25));
    assert_eq!(fmu.step(0.01, 0.01), OK, "{:?}", fmu.log);
}

#[test]
fn instantiation_refuses_model_exchange_and_another_builds_guid_with_the_reason() {
    let model_exchange = 0;
    let log = Fmu::instantiate("me", model_exchange, &guid()).err().expect("refused");
    assert_eq!(
        log,
        [(
            ERROR,
            "fmi2Instantiate: this FMU offers Co-Simulation only (fmuType = fmi2CoSimulation)".to_string()
        )]
    );
    let other = "{00000000-0000-0000-0000-000000000000}";
    let log = Fmu::instantiate("other", CO_SIMULATION, other).err().expect("refused");
    let expected = format!(
        "fmi2Instantiate: GUID {other} is not this binary's {} (a modelDescription.xml of another build)",
        guid()
    );
    assert_eq!(log, [(ERROR, expected)]);
    // no GUID given: nothing to compare, the instance is made
    let fmu = Fmu::instantiate("no guid", CO_SIMULATION, "").unwrap_or_else(|log| panic!("{log:?}"));
    fmu.start(0.0, &[]);
    assert_eq!(fmu.step(0.0, 0.01), OK);
}

#[test]
fn functions_this_fmu_does_not_offer_answer_fmi2error_with_the_reason_and_change_nothing() {
    let fmu = Fmu::started(0.0, &[]);
    let before = fmu.outputs();
    fmu.clear_log();
    let theta = vr("theta");
    let (mut x, order) = (0.0, 1);
    let mut s: *const c_char = std::ptr::null();
    let text = c"x".as_ptr();
    // SAFETY: every pointer points to one value, with counts of one (or zero for Model Exchange's
    // state vectors, never read).
    let calls: [(c_int, &str); 8] = unsafe {
        [
            (
                fmi2EnterEventMode(fmu.c),
                "fmi2EnterEventMode: this FMU offers Co-Simulation only, not Model Exchange",
            ),
            (
                fmi2GetDerivatives(fmu.c, &mut x, 0),
                "fmi2GetDerivatives: this FMU offers Co-Simulation only, not Model Exchange",
            ),
            (
                fmi2GetDirectionalDerivative(fmu.c, &theta, 1, &theta, 1, &1.0, &mut x),
                "fmi2GetDirectionalDerivative: not provided (providesDirectionalDerivative = false)",
            ),
            (
                fmi2SetRealInputDerivatives(fmu.c, &theta, 1, &order, &1.0),
                "fmi2SetRealInputDerivatives: inputs are held constant (canInterpolateInputs = false)",
            ),
            (
                fmi2GetRealOutputDerivatives(fmu.c, &theta, 1, &order, &mut x),
                "fmi2GetRealOutputDerivatives: not provided (maxOutputDerivativeOrder = 0)",
            ),
            (
                fmi2CancelStep(fmu.c),
                "fmi2CancelStep: fmi2DoStep never returns fmi2Pending here",
            ),
            (
                fmi2GetString(fmu.c, &theta, 1, &mut s),
                "fmi2GetString: this FMU has no String variables",
            ),
            (
                fmi2SetString(fmu.c, &theta, 1, &text),
                "fmi2SetString: this FMU has no String variables",
            ),
        ]
    };
    let log = fmu.log.take();
    let expected: Vec<(c_int, String)> = calls.iter().map(|&(_, m)| (ERROR, m.to_string())).collect();
    assert_eq!(log, expected, "one message per refused call, in order");
    for (status, message) in calls {
        assert_eq!(status, ERROR, "{message}");
    }
    assert!(s.is_null(), "no String was written");
    // SAFETY: no value asked for, so no array is read.
    let none = unsafe { fmi2GetString(fmu.c, std::ptr::null(), 0, std::ptr::null_mut()) };
    assert_eq!(none, OK, "no String value asked for: nothing to refuse");
    assert_eq!(fmu.outputs(), before);
    assert_eq!(fmu.step(0.0, 0.01), OK, "{:?}", fmu.log);
}
