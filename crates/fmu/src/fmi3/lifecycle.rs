//! The exported FMI 3.0 functions of an instance's life and of co-simulation: version,
//! instantiation and freeing, initialisation, event mode, `fmi3DoStep`, termination and reset.

use std::ffi::c_int;

use super::{log_sink, put, Boolean, FmiString, Instance3, LogMessage};
use crate::ffi::lifecycle::{free_instance, instantiate, reset, set_debug_logging};
use crate::ffi::{with_instance, ValueReference};
use crate::instance::{EventSettings, Instance, Status};

#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> FmiString {
    c"3.0".as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    instance: Instance3,
    logging_on: bool,
    _n_categories: usize,
    _categories: *const FmiString,
) -> c_int {
    set_debug_logging(instance, "fmi3SetDebugLogging", logging_on)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instance_name: FmiString,
    instantiation_token: FmiString,
    _resource_path: FmiString,
    _visible: bool,
    logging_on: bool,
    event_mode_used: bool,
    early_return_allowed: bool,
    _required_intermediate_variables: *const ValueReference,
    _n_required_intermediate_variables: usize,
    instance_environment: *mut std::ffi::c_void,
    log_message: Option<LogMessage>,
    _intermediate_update: *mut std::ffi::c_void,
) -> Instance3 {
    let settings = EventSettings {
        event_mode_used,
        early_return_allowed,
    };
    let make = |name: &str| {
        let log = log_sink(log_message, instance_environment);
        Some(Instance::new_fmi3(name, logging_on, log, settings))
    };
    let what = "fmi3InstantiateCoSimulation: instantiationToken";
    // SAFETY: the importer passes NUL-terminated strings (or null).
    unsafe { instantiate(what, instance_name, instantiation_token, make) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(instance: Instance3) {
    // SAFETY: forwarded caller contract.
    unsafe { free_instance(instance) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    instance: Instance3,
    _tolerance_defined: bool,
    _tolerance: f64,
    start_time: f64,
    _stop_time_defined: bool,
    _stop_time: f64,
) -> c_int {
    with_instance(instance, "fmi3EnterInitializationMode", |inst| {
        match inst.setup_experiment(start_time) {
            Status::Ok => inst.enter_initialization(),
            refused => refused,
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3ExitInitializationMode(instance: Instance3) -> c_int {
    with_instance(instance, "fmi3ExitInitializationMode", Instance::exit_initialization)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterEventMode(instance: Instance3) -> c_int {
    with_instance(instance, "fmi3EnterEventMode", Instance::enter_event_mode)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3UpdateDiscreteStates(
    instance: Instance3,
    discrete_states_need_update: *mut Boolean,
    terminate_simulation: *mut Boolean,
    nominals_of_continuous_states_changed: *mut Boolean,
    values_of_continuous_states_changed: *mut Boolean,
    next_event_time_defined: *mut Boolean,
    next_event_time: *mut f64,
) -> c_int {
    with_instance(instance, "fmi3UpdateDiscreteStates", |inst| {
        let status = inst.update_discrete_states();
        if status == Status::Ok {
            // SAFETY: the importer's out-arguments (null tolerated).
            unsafe {
                // settled in one call; no termination, no time event
                put(discrete_states_need_update, 0);
                put(terminate_simulation, 0);
                put(nominals_of_continuous_states_changed, 0);
                put(values_of_continuous_states_changed, 0);
                put(next_event_time_defined, 0);
                put(next_event_time, 0.0);
            }
        }
        status
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterStepMode(instance: Instance3) -> c_int {
    with_instance(instance, "fmi3EnterStepMode", Instance::enter_step_mode)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3DoStep(
    instance: Instance3,
    current_communication_point: f64,
    communication_step_size: f64,
    _no_set_fmu_state_prior_to_current_point: bool,
    event_handling_needed: *mut Boolean,
    terminate_simulation: *mut Boolean,
    early_return: *mut Boolean,
    last_successful_time: *mut f64,
) -> c_int {
    with_instance(instance, "fmi3DoStep", |inst| {
        let end = inst.do_step_with_events(current_communication_point, communication_step_size);
        let (status, end) = match end {
            Ok(end) => (Status::Ok, end),
            Err(status) => {
                let now = inst.time();
                let unchanged = crate::instance::StepEnd {
                    event_handling_needed: false,
                    early_return: false,
                    last_successful_time: now,
                };
                (status, unchanged)
            }
        };
        // SAFETY: the importer's out-arguments (null tolerated).
        unsafe {
            put(event_handling_needed, u8::from(end.event_handling_needed));
            put(terminate_simulation, 0);
            put(early_return, u8::from(end.early_return));
            put(last_successful_time, end.last_successful_time);
        }
        status
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Terminate(instance: Instance3) -> c_int {
    with_instance(instance, "fmi3Terminate", Instance::terminate)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Reset(instance: Instance3) -> c_int {
    reset(instance, "fmi3Reset")
}
