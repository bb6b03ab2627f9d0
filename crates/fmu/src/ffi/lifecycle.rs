//! The exported FMI functions of an instance's life: version and platform, instantiation and
//! freeing, experiment set-up, initialisation, `fmi2DoStep`, termination and reset.

use std::ffi::{c_int, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};

use super::pointers::text;
use super::{log_sink, with_instance, with_instance_in_any_state};
use super::{Boolean, CallbackFunctions, Component, FmiString, Real};
use crate::instance::{Instance, Status};
use crate::variables::guid;

const FMI2_COSIMULATION: c_int = 1;

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
        into_component(inst, "fmi2Instantiate: GUID", &wanted)
    }));
    made.unwrap_or(std::ptr::null_mut())
}

/// The instance as a component when `wanted` (the GUID or instantiation token of the model
/// description the importer read; empty: not given) is this binary's; else null, logged (`what`
/// names the function and the argument).
pub(crate) fn into_component(inst: Instance, what: &str, wanted: &str) -> Component {
    if !wanted.is_empty() && wanted != guid() {
        inst.error(&format!(
            "{what} {wanted} is not this binary's {} (a modelDescription.xml of another build)",
            guid()
        ));
        return std::ptr::null_mut();
    }
    Box::into_raw(Box::new(inst)).cast::<c_void>()
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: Component) {
    // SAFETY: forwarded caller contract.
    unsafe { free_instance(c) }
}

/// Frees an instance (`fmi2FreeInstance`, `fmi3FreeInstance`).
///
/// # Safety
/// `c` is null or a component of this library not yet freed.
pub(crate) unsafe fn free_instance(c: Component) {
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
