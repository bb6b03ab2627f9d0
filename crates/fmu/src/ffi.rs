//! The FMI 2.0 C interface: every `fmi2*` function of the standard, exported unmangled from the
//! shared object (importers such as fmpy resolve all of them when they load it).
//!
//! Each function converts its C arguments, runs the call on the [`Instance`] inside
//! [`std::panic::catch_unwind`] and converts the result back. A panic is logged, returned as
//! `fmi2Error` and puts the instance into its error state ([`crate::instance::Phase::Error`]): the state may be
//! half-updated, so every later call but `fmi2Reset` and `fmi2FreeInstance` is refused (and
//! `fmi2FreeFMUstate`, which only releases the master's memory). Nothing unwinds into the importer.
//! A null array with a positive length is refused with a message, never read. An `fmi2Component` is a `Box<Instance>` turned into
//! a raw pointer by `fmi2Instantiate` and back by `fmi2FreeInstance`; an `fmi2FMUstate` likewise a
//! `Box<FmuState>`. There are no globals: instances are independent.
//!
//! Messages go to the importer's logger with the format `"%s"` and the text as its argument (the
//! logger is variadic; a `%` in a message must never be read as a format).
//!
//! Model Exchange is not offered: its functions exist (so that the library loads everywhere) and
//! return `fmi2Error`.
//!
//! # Safety
//!
//! The functions are `unsafe extern "C"`: the caller (an FMI importer) must follow the FMI 2.0
//! standard: a component pointer from `fmi2Instantiate` not yet freed, arrays of the given length,
//! NUL-terminated strings, and no concurrent calls on one instance.
#![allow(clippy::missing_safety_doc)]
// the standard's function names
#![allow(non_snake_case)]

use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::instance::{FmuState, Instance, Phase, Status, GET_PHASES, LIVE_PHASES};

/// The phases in which the `fmi2Get*Status` functions answer.
const STATUS_PHASES: &[Phase] = &[Phase::StepMode, Phase::Terminated];
use crate::variables::{guid, Kind};

type Component = *mut c_void;
type FmuStatePtr = *mut c_void;
type ValueReference = c_uint;
type Real = f64;
type Integer = c_int;
type Boolean = c_int;
type FmiString = *const c_char;
type Byte = c_char;

/// `fmi2CallbackLogger`: variadic, called here with `"%s"` and one string.
type Logger = unsafe extern "C" fn(*mut c_void, FmiString, c_int, FmiString, FmiString, ...);

/// `fmi2CallbackFunctions` (only the logger is used; the other fields give the layout).
#[repr(C)]
#[allow(dead_code)]
pub struct CallbackFunctions {
    logger: Option<Logger>,
    allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    step_finished: Option<unsafe extern "C" fn(*mut c_void, c_int)>,
    component_environment: *mut c_void,
}

/// `fmi2EventInfo` (Model Exchange only; never written).
#[repr(C)]
#[allow(dead_code)]
pub struct EventInfo {
    new_discrete_states_needed: Boolean,
    terminate_simulation: Boolean,
    nominals_of_continuous_states_changed: Boolean,
    values_of_continuous_states_changed: Boolean,
    next_event_time_defined: Boolean,
    next_event_time: Real,
}

const FMI2_COSIMULATION: c_int = 1;
const FMI2_LAST_SUCCESSFUL_TIME: c_int = 2;
const FMI2_TERMINATED: c_int = 3;

/// Text for C: interior NULs (which C cannot carry) become spaces.
fn c_text(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).expect("no NUL left")
}

/// A log sink calling the importer's logger with `"%s"`.
fn log_sink(logger: Option<Logger>, env: *mut c_void, name: &str) -> crate::instance::LogSink {
    let name = c_text(name);
    Box::new(move |status: Status, category: &str, message: &str| {
        if let Some(logger) = logger {
            let (category, message) = (c_text(category), c_text(message));
            // SAFETY: the logger is the importer's fmi2CallbackLogger and `env` its component
            // environment; every string is NUL-terminated and outlives the call, and the one
            // variadic argument matches the format "%s".
            unsafe {
                logger(
                    env,
                    name.as_ptr(),
                    status as c_int,
                    category.as_ptr(),
                    c"%s".as_ptr(),
                    message.as_ptr(),
                )
            };
        }
    })
}

/// The panic payload as text.
fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// Runs `f` on the instance behind `c` unless the instance is in its error state (then the call is
/// refused with the reason): see [`with_instance_in_any_state`].
fn with_instance(c: Component, what: &str, f: impl FnOnce(&mut Instance) -> Status) -> c_int {
    with_instance_in_any_state(c, what, |inst| match inst.check_phase(what, LIVE_PHASES) {
        Ok(()) => f(inst),
        Err(status) => status,
    })
}

/// Runs `f` on the instance behind `c` in whatever phase it is: `fmi2Error` for a null component; a
/// caught panic is logged, returned as `fmi2Error` and puts the instance into its error state.
fn with_instance_in_any_state(c: Component, what: &str, f: impl FnOnce(&mut Instance) -> Status) -> c_int {
    if c.is_null() {
        return Status::Error as c_int;
    }
    let ptr = c.cast::<Instance>();
    // SAFETY: a non-null component is a live `Box<Instance>` from fmi2Instantiate (the caller's
    // contract), used by one thread at a time; the borrow ends with the closure.
    let result = catch_unwind(AssertUnwindSafe(|| {
        let inst = unsafe { &mut *ptr };
        if let Some(message) = inst.test_panic.take() {
            panic!("{message}");
        }
        f(inst)
    }));
    match result {
        Ok(status) => status as c_int,
        Err(payload) => {
            let text = panic_text(payload.as_ref());
            // SAFETY: as above; the panicking borrow has ended.
            let inst = unsafe { &mut *ptr };
            inst.enter_error_state(format!("entered when {what} failed with an internal error: {text}"));
            let _ = catch_unwind(AssertUnwindSafe(|| {
                inst.error(&format!(
                    "{what}: internal error: {text}; the instance is now in the error state, which only \
                     fmi2Reset or fmi2FreeInstance leave"
                ))
            }));
            Status::Error as c_int
        }
    }
}

/// `Err(fmi2Error)`, logged, when an array of `n > 0` values is null.
fn check_arrays(inst: &Instance, what: &str, n: usize, arrays: &[(&str, bool)]) -> Result<(), Status> {
    match arrays.iter().find(|(_, null)| *null) {
        Some((name, _)) if n > 0 => Err(inst.error(&format!("{what}: {name} is null with nvr = {n}"))),
        _ => Ok(()),
    }
}

/// `n` values at `p` (empty for `n = 0`, whatever `p`).
///
/// # Safety
/// For `n > 0`, `p` points to `n` initialised values that stay valid and unaliased for `'a`.
unsafe fn slice<'a, T>(p: *const T, n: usize) -> &'a [T] {
    if n == 0 || p.is_null() {
        &[]
    } else {
        // SAFETY: the caller's contract.
        unsafe { std::slice::from_raw_parts(p, n) }
    }
}

/// `n` writable values at `p` (empty for `n = 0`).
///
/// # Safety
/// For `n > 0`, `p` points to `n` writable values, valid and unaliased for `'a`.
unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> &'a mut [T] {
    if n == 0 || p.is_null() {
        &mut []
    } else {
        // SAFETY: the caller's contract.
        unsafe { std::slice::from_raw_parts_mut(p, n) }
    }
}

/// A C string as text (`""` for null).
///
/// # Safety
/// A non-null `p` is NUL-terminated and valid for the call.
unsafe fn text(p: FmiString) -> String {
    if p.is_null() {
        String::new()
    } else {
        // SAFETY: the caller's contract.
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    }
}

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> FmiString {
    c"default".as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> FmiString {
    c"2.0".as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: Component,
    logging_on: Boolean,
    _n_categories: usize,
    _categories: *const FmiString,
) -> c_int {
    with_instance(c, "fmi2SetDebugLogging", |inst| {
        inst.logging_on = logging_on != 0;
        Status::Ok
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: FmiString,
    fmu_type: c_int,
    fmu_guid: FmiString,
    _fmu_resource_location: FmiString,
    functions: *const CallbackFunctions,
    _visible: Boolean,
    logging_on: Boolean,
) -> Component {
    let made = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the importer passes NUL-terminated strings (or null) and a callback structure
        // that stays valid while the instance lives (FMI 2.0, 2.1.5).
        let (name, wanted) = unsafe { (text(instance_name), text(fmu_guid)) };
        // SAFETY: as above; null is tolerated (no logger then).
        let callbacks = unsafe { functions.as_ref() };
        let (logger, env) = callbacks.map_or((None, std::ptr::null_mut()), |f| (f.logger, f.component_environment));
        let inst = Instance::new(&name, logging_on != 0, log_sink(logger, env, &name));
        if fmu_type != FMI2_COSIMULATION {
            inst.error("fmi2Instantiate: this FMU offers Co-Simulation only (fmuType = fmi2CoSimulation)");
            return std::ptr::null_mut();
        }
        if !wanted.is_empty() && wanted != guid() {
            inst.error(&format!(
                "fmi2Instantiate: GUID {wanted} is not this binary's {} (a modelDescription.xml of another build)",
                guid()
            ));
            return std::ptr::null_mut();
        }
        Box::into_raw(Box::new(inst)).cast::<c_void>()
    }));
    made.unwrap_or(std::ptr::null_mut())
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: Component) {
    if !c.is_null() {
        // SAFETY: a component from fmi2Instantiate, freed once (the caller's contract).
        let inst = unsafe { Box::from_raw(c.cast::<Instance>()) };
        let _ = catch_unwind(AssertUnwindSafe(move || drop(inst)));
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: Component,
    _tolerance_defined: Boolean,
    _tolerance: Real,
    start_time: Real,
    _stop_time_defined: Boolean,
    _stop_time: Real,
) -> c_int {
    with_instance(c, "fmi2SetupExperiment", |inst| inst.setup_experiment(start_time))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Component) -> c_int {
    with_instance(c, "fmi2EnterInitializationMode", Instance::enter_initialization)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Component) -> c_int {
    with_instance(c, "fmi2ExitInitializationMode", Instance::exit_initialization)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: Component) -> c_int {
    with_instance(c, "fmi2Terminate", Instance::terminate)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: Component) -> c_int {
    with_instance_in_any_state(c, "fmi2Reset", |inst| {
        inst.reset();
        Status::Ok
    })
}

/// Reads `nvr` values of `kind` and converts them with `convert` into `value` (`what`: the function).
unsafe fn get_values<T>(
    c: Component,
    what: &str,
    kind: Kind,
    vr: *const ValueReference,
    nvr: usize,
    value: *mut T,
    convert: impl Fn(f64) -> T,
) -> c_int {
    with_instance(c, what, |inst| {
        if let Err(status) = check_arrays(inst, what, nvr, &[("vr", vr.is_null()), ("value", value.is_null())]) {
            return status;
        }
        // SAFETY: `vr` and `value` are arrays of `nvr` elements (FMI 2.0, 2.1.7).
        let (vrs, out) = unsafe { (slice(vr, nvr), slice_mut(value, nvr)) };
        let mut buffer = vec![0.0; nvr];
        let status = inst.get(kind, vrs, &mut buffer);
        if status == Status::Ok {
            for (o, &b) in out.iter_mut().zip(&buffer) {
                *o = convert(b);
            }
        }
        status
    })
}

/// Writes `nvr` values of `kind`, converted with `convert` (`what`: the function).
unsafe fn set_values<T: Copy>(
    c: Component,
    what: &str,
    kind: Kind,
    vr: *const ValueReference,
    nvr: usize,
    value: *const T,
    convert: impl Fn(T) -> f64,
) -> c_int {
    with_instance(c, what, |inst| {
        if let Err(status) = check_arrays(inst, what, nvr, &[("vr", vr.is_null()), ("value", value.is_null())]) {
            return status;
        }
        // SAFETY: `vr` and `value` are arrays of `nvr` elements (FMI 2.0, 2.1.7).
        let (vrs, values) = unsafe { (slice(vr, nvr), slice(value, nvr)) };
        let values: Vec<f64> = values.iter().map(|&v| convert(v)).collect();
        inst.set(kind, vrs, &values)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(c: Component, vr: *const ValueReference, nvr: usize, value: *mut Real) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { get_values(c, "fmi2GetReal", Kind::Real, vr, nvr, value, |v| v) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *mut Integer,
) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { get_values(c, "fmi2GetInteger", Kind::Integer, vr, nvr, value, |v| v as Integer) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *mut Boolean,
) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe {
        get_values(c, "fmi2GetBoolean", Kind::Boolean, vr, nvr, value, |v| {
            Boolean::from(v != 0.0)
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *mut FmiString,
) -> c_int {
    const WHAT: &str = "fmi2GetString";
    with_instance(c, WHAT, |inst| {
        let checked = inst
            .check_phase(WHAT, GET_PHASES)
            .and_then(|()| check_arrays(inst, WHAT, nvr, &[("vr", vr.is_null()), ("value", value.is_null())]));
        match (checked, nvr) {
            (Err(status), _) => status,
            (Ok(()), 0) => Status::Ok,
            (Ok(()), _) => inst.error("fmi2GetString: this FMU has no String variables"),
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(c: Component, vr: *const ValueReference, nvr: usize, value: *const Real) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { set_values(c, "fmi2SetReal", Kind::Real, vr, nvr, value, |v| v) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *const Integer,
) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { set_values(c, "fmi2SetInteger", Kind::Integer, vr, nvr, value, f64::from) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *const Boolean,
) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe {
        set_values(c, "fmi2SetBoolean", Kind::Boolean, vr, nvr, value, |v| {
            f64::from(u8::from(v != 0))
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *const FmiString,
) -> c_int {
    const WHAT: &str = "fmi2SetString";
    with_instance(c, WHAT, |inst| {
        let checked = inst
            .check_phase(WHAT, crate::instance::SET_PHASES)
            .and_then(|()| check_arrays(inst, WHAT, nvr, &[("vr", vr.is_null()), ("value", value.is_null())]));
        match (checked, nvr) {
            (Err(status), _) => status,
            (Ok(()), 0) => Status::Ok,
            (Ok(()), _) => inst.error("fmi2SetString: this FMU has no String variables"),
        }
    })
}

/// Stores `state` at `*slot`: into the existing `FmuState` there, or a new one.
///
/// # Safety
/// `slot` is valid; a non-null `*slot` is a live `Box<FmuState>` from this library.
unsafe fn store_state(slot: *mut FmuStatePtr, state: FmuState) {
    // SAFETY: the caller's contract.
    unsafe {
        if (*slot).is_null() {
            *slot = Box::into_raw(Box::new(state)).cast::<c_void>();
        } else {
            *(*slot).cast::<FmuState>() = state;
        }
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: Component, state: *mut FmuStatePtr) -> c_int {
    with_instance(c, "fmi2GetFMUstate", |inst| {
        if state.is_null() {
            return inst.error("fmi2GetFMUstate: FMUstate pointer is null");
        }
        match inst.get_state() {
            Ok(s) => {
                // SAFETY: `state` is the importer's fmi2FMUstate slot: null or a state of ours.
                unsafe { store_state(state, s) };
                Status::Ok
            }
            Err(status) => status,
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Component, state: FmuStatePtr) -> c_int {
    with_instance(c, "fmi2SetFMUstate", |inst| {
        if state.is_null() {
            return inst.error("fmi2SetFMUstate: FMUstate is null");
        }
        // SAFETY: a state made by fmi2GetFMUstate or fmi2DeSerializeFMUstate of this library.
        let s = unsafe { &*state.cast::<FmuState>() };
        inst.set_state(s)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: Component, state: *mut FmuStatePtr) -> c_int {
    // allowed in the error state too: it only releases the master's memory
    with_instance_in_any_state(c, "fmi2FreeFMUstate", |_| {
        // SAFETY: `state` is null or the slot of a state of ours, freed once (then nulled).
        unsafe {
            if !state.is_null() && !(*state).is_null() {
                drop(Box::from_raw((*state).cast::<FmuState>()));
                *state = std::ptr::null_mut();
            }
        }
        Status::Ok
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(c: Component, state: FmuStatePtr, size: *mut usize) -> c_int {
    with_instance(c, "fmi2SerializedFMUstateSize", |inst| {
        if state.is_null() || size.is_null() {
            return inst.error("fmi2SerializedFMUstateSize: null FMUstate or size");
        }
        // SAFETY: a state of ours and a writable size (the caller's contract).
        unsafe { *size = (*state.cast::<FmuState>()).to_bytes().len() };
        Status::Ok
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: Component,
    state: FmuStatePtr,
    serialized: *mut Byte,
    size: usize,
) -> c_int {
    with_instance(c, "fmi2SerializeFMUstate", |inst| {
        if state.is_null() || serialized.is_null() {
            return inst.error("fmi2SerializeFMUstate: null FMUstate or buffer");
        }
        // SAFETY: a state of ours (the caller's contract).
        let bytes = unsafe { &*state.cast::<FmuState>() }.to_bytes();
        if bytes.len() > size {
            return inst.error(&format!(
                "fmi2SerializeFMUstate: buffer of {size} bytes for a state of {} (ask fmi2SerializedFMUstateSize)",
                bytes.len()
            ));
        }
        // SAFETY: `serialized` has room for `size >= bytes.len()` bytes.
        let out = unsafe { slice_mut(serialized.cast::<u8>(), bytes.len()) };
        out.copy_from_slice(&bytes);
        Status::Ok
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: Component,
    serialized: *const Byte,
    size: usize,
    state: *mut FmuStatePtr,
) -> c_int {
    with_instance(c, "fmi2DeSerializeFMUstate", |inst| {
        if state.is_null() || (serialized.is_null() && size > 0) {
            return inst.error("fmi2DeSerializeFMUstate: null buffer or FMUstate slot");
        }
        // SAFETY: `serialized` holds `size` bytes (the caller's contract).
        let bytes = unsafe { slice(serialized.cast::<u8>(), size) };
        match FmuState::from_bytes(bytes) {
            Ok(s) => {
                // SAFETY: `state` is the importer's fmi2FMUstate slot: null or a state of ours.
                unsafe { store_state(state, s) };
                Status::Ok
            }
            Err(e) => inst.error(&format!("fmi2DeSerializeFMUstate: {e}")),
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: Component,
    _unknown: *const ValueReference,
    _n_unknown: usize,
    _known: *const ValueReference,
    _n_known: usize,
    _dv_known: *const Real,
    _dv_unknown: *mut Real,
) -> c_int {
    with_instance(c, "fmi2GetDirectionalDerivative", |inst| {
        inst.error("fmi2GetDirectionalDerivative: not provided (providesDirectionalDerivative = false)")
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: Component,
    current_communication_point: Real,
    communication_step_size: Real,
    _no_set_fmu_state_prior_to_current_point: Boolean,
) -> c_int {
    with_instance(c, "fmi2DoStep", |inst| {
        inst.do_step(current_communication_point, communication_step_size)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: Component) -> c_int {
    with_instance(c, "fmi2CancelStep", |inst| {
        inst.error("fmi2CancelStep: fmi2DoStep never returns fmi2Pending here")
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: Component,
    _vr: *const ValueReference,
    _nvr: usize,
    _order: *const Integer,
    _value: *const Real,
) -> c_int {
    with_instance(c, "fmi2SetRealInputDerivatives", |inst| {
        inst.error("fmi2SetRealInputDerivatives: inputs are held constant (canInterpolateInputs = false)")
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: Component,
    _vr: *const ValueReference,
    _nvr: usize,
    _order: *const Integer,
    _value: *mut Real,
) -> c_int {
    with_instance(c, "fmi2GetRealOutputDerivatives", |inst| {
        inst.error("fmi2GetRealOutputDerivatives: not provided (maxOutputDerivativeOrder = 0)")
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(c: Component, _kind: c_int, _value: *mut c_int) -> c_int {
    // fmi2DoStep never returns fmi2Pending, so there is no asynchronous status to ask for
    with_instance(c, "fmi2GetStatus", |inst| {
        match inst.check_phase("fmi2GetStatus", STATUS_PHASES) {
            Ok(()) => Status::Discard,
            Err(status) => status,
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(c: Component, kind: c_int, value: *mut Real) -> c_int {
    with_instance(c, "fmi2GetRealStatus", |inst| {
        if let Err(status) = inst.check_phase("fmi2GetRealStatus", STATUS_PHASES) {
            return status;
        }
        if kind != FMI2_LAST_SUCCESSFUL_TIME || value.is_null() {
            return Status::Discard;
        }
        // SAFETY: a writable fmi2Real (the caller's contract).
        unsafe { *value = inst.time() };
        Status::Ok
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(c: Component, _kind: c_int, _value: *mut Integer) -> c_int {
    with_instance(c, "fmi2GetIntegerStatus", |inst| {
        match inst.check_phase("fmi2GetIntegerStatus", STATUS_PHASES) {
            Ok(()) => Status::Discard,
            Err(status) => status,
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(c: Component, kind: c_int, value: *mut Boolean) -> c_int {
    with_instance(c, "fmi2GetBooleanStatus", |inst| {
        if let Err(status) = inst.check_phase("fmi2GetBooleanStatus", STATUS_PHASES) {
            return status;
        }
        if kind != FMI2_TERMINATED || value.is_null() {
            return Status::Discard;
        }
        // SAFETY: a writable fmi2Boolean (the caller's contract).
        unsafe { *value = 0 };
        Status::Ok
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(c: Component, _kind: c_int, _value: *mut FmiString) -> c_int {
    with_instance(c, "fmi2GetStringStatus", |inst| {
        match inst.check_phase("fmi2GetStringStatus", STATUS_PHASES) {
            Ok(()) => Status::Discard,
            Err(status) => status,
        }
    })
}

/// The Model Exchange functions: present so that the library loads in every importer, refused.
fn model_exchange(c: Component, what: &str) -> c_int {
    with_instance(c, what, |inst| {
        inst.error(&format!(
            "{what}: this FMU offers Co-Simulation only, not Model Exchange"
        ))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterEventMode(c: Component) -> c_int {
    model_exchange(c, "fmi2EnterEventMode")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2NewDiscreteStates(c: Component, _info: *mut EventInfo) -> c_int {
    model_exchange(c, "fmi2NewDiscreteStates")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterContinuousTimeMode(c: Component) -> c_int {
    model_exchange(c, "fmi2EnterContinuousTimeMode")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2CompletedIntegratorStep(
    c: Component,
    _no_set_fmu_state_prior_to_current_point: Boolean,
    _enter_event_mode: *mut Boolean,
    _terminate_simulation: *mut Boolean,
) -> c_int {
    model_exchange(c, "fmi2CompletedIntegratorStep")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetTime(c: Component, _time: Real) -> c_int {
    model_exchange(c, "fmi2SetTime")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetContinuousStates(c: Component, _x: *const Real, _nx: usize) -> c_int {
    model_exchange(c, "fmi2SetContinuousStates")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetDerivatives(c: Component, _dx: *mut Real, _nx: usize) -> c_int {
    model_exchange(c, "fmi2GetDerivatives")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetEventIndicators(c: Component, _indicators: *mut Real, _ni: usize) -> c_int {
    model_exchange(c, "fmi2GetEventIndicators")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetContinuousStates(c: Component, _x: *mut Real, _nx: usize) -> c_int {
    model_exchange(c, "fmi2GetContinuousStates")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetNominalsOfContinuousStates(c: Component, _x: *mut Real, _nx: usize) -> c_int {
    model_exchange(c, "fmi2GetNominalsOfContinuousStates")
}
