//! The exported FMI 2.0 functions of an instance's life: version and platform, instantiation and
//! freeing, experiment set-up, initialisation, `fmi2DoStep`, termination and reset.

use std::ffi::c_int;

use super::{log_sink, Boolean, CallbackFunctions, FmiString, Real};
use crate::ffi::lifecycle::{free_instance, instantiate, refused, reset, set_debug_logging};
use crate::ffi::{with_instance, Component};
use crate::instance::Instance;

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
    set_debug_logging(c, "fmi2SetDebugLogging", logging_on != 0)
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
    // SAFETY: the importer passes a callback structure that stays valid while the instance lives
    // (FMI 2.0, 2.1.5), or null (no logger then).
    let callbacks = unsafe { functions.as_ref() };
    let (logger, env) = callbacks.map_or((None, std::ptr::null_mut()), |f| (f.logger, f.component_environment));
    let make = |name: &str| {
        let inst = Instance::new(name, logging_on != 0, log_sink(logger, env, name));
        if fmu_type != FMI2_COSIMULATION {
            inst.error("fmi2Instantiate: this FMU offers Co-Simulation only (fmuType = fmi2CoSimulation)");
            return None;
        }
        Some(inst)
    };
    // SAFETY: the importer passes NUL-terminated strings (or null).
    unsafe { instantiate("fmi2Instantiate: GUID", instance_name, fmu_guid, make) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: Component) {
    // SAFETY: forwarded caller contract.
    unsafe { free_instance(c) }
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
    reset(c, "fmi2Reset")
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

refused! {
    fmi2CancelStep() => "fmi2DoStep never returns fmi2Pending here";
}
