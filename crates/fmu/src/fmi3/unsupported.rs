//! The FMI 3.0 functions this Co-Simulation FMU does not offer — Model Exchange, Scheduled
//! Execution, clocks and their intervals, configuration mode, dependencies and derivatives —
//! exported so that every importer loads the library, each refused with `fmi3Error` and a logged
//! message naming what the FMU offers instead (the instantiation functions log and return null).

use std::ffi::{c_int, c_void};

use super::{log_sink, Boolean, FmiString, Instance3, LogMessage};
use crate::ffi::lifecycle::{instantiate, refused};
use crate::ffi::ValueReference;
use crate::instance::{EventSettings, Instance};

const CO_SIMULATION_ONLY: &str = "this FMU offers Co-Simulation only (fmi3InstantiateCoSimulation), not Model Exchange";
const NO_CLOCKS: &str = "this FMU has no clocks (no Scheduled Execution)";

/// Logs through `log_message` that `what` is not offered; returns null.
///
/// # Safety
/// `instance_name` is null or NUL-terminated.
unsafe fn refuse_instantiation(
    what: &str,
    instance_name: FmiString,
    env: *mut c_void,
    log_message: Option<LogMessage>,
) -> Instance3 {
    let make = |name: &str| {
        let settings = EventSettings {
            event_mode_used: false,
            early_return_allowed: false,
        };
        Instance::new_fmi3(name, false, log_sink(log_message, env), settings).error(&format!(
            "{what}: this FMU offers Co-Simulation only; instantiate it with fmi3InstantiateCoSimulation"
        ));
        None
    };
    // SAFETY: a NUL-terminated name or null; there is no token to compare.
    unsafe { instantiate(what, instance_name, std::ptr::null(), make) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    instance_name: FmiString,
    _instantiation_token: FmiString,
    _resource_path: FmiString,
    _visible: bool,
    _logging_on: bool,
    instance_environment: *mut c_void,
    log_message: Option<LogMessage>,
) -> Instance3 {
    // SAFETY: forwarded caller contract.
    unsafe {
        refuse_instantiation(
            "fmi3InstantiateModelExchange",
            instance_name,
            instance_environment,
            log_message,
        )
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    instance_name: FmiString,
    _instantiation_token: FmiString,
    _resource_path: FmiString,
    _visible: bool,
    _logging_on: bool,
    instance_environment: *mut c_void,
    log_message: Option<LogMessage>,
    _clock_update: *mut c_void,
    _lock_preemption: *mut c_void,
    _unlock_preemption: *mut c_void,
) -> Instance3 {
    // SAFETY: forwarded caller contract.
    unsafe {
        refuse_instantiation(
            "fmi3InstantiateScheduledExecution",
            instance_name,
            instance_environment,
            log_message,
        )
    }
}

refused! {
    fmi3GetNumberOfVariableDependencies(
        _value_reference: ValueReference,
        _n_dependencies: *mut usize
    ) => "not provided; the dependencies are in <ModelStructure>";
    fmi3GetVariableDependencies(
        _dependent: ValueReference,
        _element_indices_of_dependent: *mut usize,
        _independents: *mut ValueReference,
        _element_indices_of_independents: *mut usize,
        _dependency_kinds: *mut c_int,
        _n_dependencies: usize
    ) => "not provided; the dependencies are in <ModelStructure>";
    fmi3GetDirectionalDerivative(
        _unknowns: *const ValueReference,
        _n_unknowns: usize,
        _knowns: *const ValueReference,
        _n_knowns: usize,
        _seed: *const f64,
        _n_seed: usize,
        _sensitivity: *mut f64,
        _n_sensitivity: usize
    ) => "not provided (providesDirectionalDerivatives = false)";
    fmi3GetAdjointDerivative(
        _unknowns: *const ValueReference,
        _n_unknowns: usize,
        _knowns: *const ValueReference,
        _n_knowns: usize,
        _seed: *const f64,
        _n_seed: usize,
        _sensitivity: *mut f64,
        _n_sensitivity: usize
    ) => "not provided (providesAdjointDerivatives = false)";
    fmi3EnterConfigurationMode() => "this FMU has no structural parameters";
    fmi3ExitConfigurationMode() => "this FMU has no structural parameters";
    fmi3GetIntervalDecimal(
        _vr: *const ValueReference,
        _n_vr: usize,
        _intervals: *mut f64,
        _qualifiers: *mut c_int
    ) => NO_CLOCKS;
    fmi3GetIntervalFraction(
        _vr: *const ValueReference,
        _n_vr: usize,
        _counters: *mut u64,
        _resolutions: *mut u64,
        _qualifiers: *mut c_int
    ) => NO_CLOCKS;
    fmi3GetShiftDecimal(_vr: *const ValueReference, _n_vr: usize, _shifts: *mut f64) => NO_CLOCKS;
    fmi3GetShiftFraction(
        _vr: *const ValueReference,
        _n_vr: usize,
        _counters: *mut u64,
        _resolutions: *mut u64
    ) => NO_CLOCKS;
    fmi3SetIntervalDecimal(_vr: *const ValueReference, _n_vr: usize, _intervals: *const f64) => NO_CLOCKS;
    fmi3SetIntervalFraction(
        _vr: *const ValueReference,
        _n_vr: usize,
        _counters: *const u64,
        _resolutions: *const u64
    ) => NO_CLOCKS;
    fmi3SetShiftDecimal(_vr: *const ValueReference, _n_vr: usize, _shifts: *const f64) => NO_CLOCKS;
    fmi3SetShiftFraction(
        _vr: *const ValueReference,
        _n_vr: usize,
        _counters: *const u64,
        _resolutions: *const u64
    ) => NO_CLOCKS;
    fmi3EvaluateDiscreteStates() => "not provided (providesEvaluateDiscreteStates = false)";
    fmi3ActivateModelPartition(_clock_reference: ValueReference, _activation_time: f64) => NO_CLOCKS;
    fmi3GetOutputDerivatives(
        _vr: *const ValueReference,
        _n_vr: usize,
        _orders: *const i32,
        _values: *mut f64,
        _n_values: usize
    ) => "not provided (maxOutputDerivativeOrder = 0)";
    fmi3EnterContinuousTimeMode() => CO_SIMULATION_ONLY;
    fmi3CompletedIntegratorStep(
        _no_set_fmu_state_prior_to_current_point: bool,
        _enter_event_mode: *mut Boolean,
        _terminate_simulation: *mut Boolean
    ) => CO_SIMULATION_ONLY;
    fmi3SetTime(_time: f64) => CO_SIMULATION_ONLY;
    fmi3SetContinuousStates(_x: *const f64, _nx: usize) => CO_SIMULATION_ONLY;
    fmi3GetContinuousStateDerivatives(_dx: *mut f64, _nx: usize) => CO_SIMULATION_ONLY;
    fmi3GetEventIndicators(_indicators: *mut f64, _n: usize) => CO_SIMULATION_ONLY;
    fmi3GetContinuousStates(_x: *mut f64, _nx: usize) => CO_SIMULATION_ONLY;
    fmi3GetNominalsOfContinuousStates(_nominals: *mut f64, _nx: usize) => CO_SIMULATION_ONLY;
    fmi3GetNumberOfEventIndicators(_n: *mut usize) => CO_SIMULATION_ONLY;
    fmi3GetNumberOfContinuousStates(_n: *mut usize) => CO_SIMULATION_ONLY;
}
