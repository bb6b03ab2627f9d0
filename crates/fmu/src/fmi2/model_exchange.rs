//! The Model Exchange functions: exported so that the library loads in every importer, each
//! refused with `fmi2Error` and a message (this FMU offers Co-Simulation only).

use super::{Boolean, Real};
use crate::ffi::lifecycle::refused;

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

const CO_SIMULATION_ONLY: &str = "this FMU offers Co-Simulation only, not Model Exchange";

refused! {
    fmi2EnterEventMode() => CO_SIMULATION_ONLY;
    fmi2NewDiscreteStates(_info: *mut EventInfo) => CO_SIMULATION_ONLY;
    fmi2EnterContinuousTimeMode() => CO_SIMULATION_ONLY;
    fmi2CompletedIntegratorStep(
        _no_set_fmu_state_prior_to_current_point: Boolean,
        _enter_event_mode: *mut Boolean,
        _terminate_simulation: *mut Boolean
    ) => CO_SIMULATION_ONLY;
    fmi2SetTime(_time: Real) => CO_SIMULATION_ONLY;
    fmi2SetContinuousStates(_x: *const Real, _nx: usize) => CO_SIMULATION_ONLY;
    fmi2GetDerivatives(_dx: *mut Real, _nx: usize) => CO_SIMULATION_ONLY;
    fmi2GetEventIndicators(_indicators: *mut Real, _ni: usize) => CO_SIMULATION_ONLY;
    fmi2GetContinuousStates(_x: *mut Real, _nx: usize) => CO_SIMULATION_ONLY;
    fmi2GetNominalsOfContinuousStates(_x: *mut Real, _nx: usize) => CO_SIMULATION_ONLY;
}
