//! The Model Exchange functions: exported so that the library loads in every importer, each
//! refused with `fmi2Error` and a message (this FMU offers Co-Simulation only).

use std::ffi::c_int;

use super::with_instance;
use super::{Boolean, Component, Real};

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
