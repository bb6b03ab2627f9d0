//! The FMI 3.0 functions this Co-Simulation FMU does not offer — Model Exchange, Scheduled
//! Execution, clocks and their intervals, configuration mode, dependencies and derivatives —
//! exported so that every importer loads the library, each refused with `fmi3Error` and a logged
//! message naming what the FMU offers instead (the instantiation functions log and return null).

use std::ffi::{c_int, c_void};

use super::{log_sink, Boolean, FmiString, Instance3, LogMessage};
use crate::ffi::pointers::text;
use crate::ffi::{with_instance, ValueReference};
use crate::instance::{EventSettings, Instance};

/// Refuses `what` on `instance` with `fmi3Error` and the message `"{what}: {why}"`.
fn refuse(instance: Instance3, what: &str, why: &str) -> c_int {
    with_instance(instance, what, |inst| inst.error(&format!("{what}: {why}")))
}

const CO_SIMULATION_ONLY: &str = "this FMU offers Co-Simulation only (fmi3InstantiateCoSimulation), not Model Exchange";
const NO_CLOCKS: &str = "this FMU has no clocks (no Scheduled Execution)";

/// Logs through `log_message` that `what` is not offered; returns null.
unsafe fn refuse_instantiation(
    what: &str,
    instance_name: FmiString,
    env: *mut c_void,
    log_message: Option<LogMessage>,
) -> Instance3 {
    let _ = std::panic::catch_unwind(|| {
        // SAFETY: a NUL-terminated name or null.
        let name = unsafe { text(instance_name) };
        let settings = EventSettings {
            event_mode_used: false,
            early_return_allowed: false,
        };
        Instance::new_fmi3(&name, false, log_sink(log_message, env), settings).error(&format!(
            "{what}: this FMU offers Co-Simulation only; instantiate it with fmi3InstantiateCoSimulation"
        ));
    });
    std::ptr::null_mut()
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

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfVariableDependencies(
    instance: Instance3,
    _value_reference: ValueReference,
    _n_dependencies: *mut usize,
) -> c_int {
    refuse(
        instance,
        "fmi3GetNumberOfVariableDependencies",
        "not provided; the dependencies are in <ModelStructure>",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetVariableDependencies(
    instance: Instance3,
    _dependent: ValueReference,
    _element_indices_of_dependent: *mut usize,
    _independents: *mut ValueReference,
    _element_indices_of_independents: *mut usize,
    _dependency_kinds: *mut c_int,
    _n_dependencies: usize,
) -> c_int {
    refuse(
        instance,
        "fmi3GetVariableDependencies",
        "not provided; the dependencies are in <ModelStructure>",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
    instance: Instance3,
    _unknowns: *const ValueReference,
    _n_unknowns: usize,
    _knowns: *const ValueReference,
    _n_knowns: usize,
    _seed: *const f64,
    _n_seed: usize,
    _sensitivity: *mut f64,
    _n_sensitivity: usize,
) -> c_int {
    refuse(
        instance,
        "fmi3GetDirectionalDerivative",
        "not provided (providesDirectionalDerivatives = false)",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetAdjointDerivative(
    instance: Instance3,
    _unknowns: *const ValueReference,
    _n_unknowns: usize,
    _knowns: *const ValueReference,
    _n_knowns: usize,
    _seed: *const f64,
    _n_seed: usize,
    _sensitivity: *mut f64,
    _n_sensitivity: usize,
) -> c_int {
    refuse(
        instance,
        "fmi3GetAdjointDerivative",
        "not provided (providesAdjointDerivatives = false)",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterConfigurationMode(instance: Instance3) -> c_int {
    refuse(
        instance,
        "fmi3EnterConfigurationMode",
        "this FMU has no structural parameters",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3ExitConfigurationMode(instance: Instance3) -> c_int {
    refuse(
        instance,
        "fmi3ExitConfigurationMode",
        "this FMU has no structural parameters",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetIntervalDecimal(
    instance: Instance3,
    _vr: *const ValueReference,
    _n_vr: usize,
    _intervals: *mut f64,
    _qualifiers: *mut c_int,
) -> c_int {
    refuse(instance, "fmi3GetIntervalDecimal", NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetIntervalFraction(
    instance: Instance3,
    _vr: *const ValueReference,
    _n_vr: usize,
    _counters: *mut u64,
    _resolutions: *mut u64,
    _qualifiers: *mut c_int,
) -> c_int {
    refuse(instance, "fmi3GetIntervalFraction", NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetShiftDecimal(
    instance: Instance3,
    _vr: *const ValueReference,
    _n_vr: usize,
    _shifts: *mut f64,
) -> c_int {
    refuse(instance, "fmi3GetShiftDecimal", NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetShiftFraction(
    instance: Instance3,
    _vr: *const ValueReference,
    _n_vr: usize,
    _counters: *mut u64,
    _resolutions: *mut u64,
) -> c_int {
    refuse(instance, "fmi3GetShiftFraction", NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetIntervalDecimal(
    instance: Instance3,
    _vr: *const ValueReference,
    _n_vr: usize,
    _intervals: *const f64,
) -> c_int {
    refuse(instance, "fmi3SetIntervalDecimal", NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetIntervalFraction(
    instance: Instance3,
    _vr: *const ValueReference,
    _n_vr: usize,
    _counters: *const u64,
    _resolutions: *const u64,
) -> c_int {
    refuse(instance, "fmi3SetIntervalFraction", NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetShiftDecimal(
    instance: Instance3,
    _vr: *const ValueReference,
    _n_vr: usize,
    _shifts: *const f64,
) -> c_int {
    refuse(instance, "fmi3SetShiftDecimal", NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetShiftFraction(
    instance: Instance3,
    _vr: *const ValueReference,
    _n_vr: usize,
    _counters: *const u64,
    _resolutions: *const u64,
) -> c_int {
    refuse(instance, "fmi3SetShiftFraction", NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EvaluateDiscreteStates(instance: Instance3) -> c_int {
    refuse(
        instance,
        "fmi3EvaluateDiscreteStates",
        "not provided (providesEvaluateDiscreteStates = false)",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3ActivateModelPartition(
    instance: Instance3,
    _clock_reference: ValueReference,
    _activation_time: f64,
) -> c_int {
    refuse(instance, "fmi3ActivateModelPartition", NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetOutputDerivatives(
    instance: Instance3,
    _vr: *const ValueReference,
    _n_vr: usize,
    _orders: *const i32,
    _values: *mut f64,
    _n_values: usize,
) -> c_int {
    refuse(
        instance,
        "fmi3GetOutputDerivatives",
        "not provided (maxOutputDerivativeOrder = 0)",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterContinuousTimeMode(instance: Instance3) -> c_int {
    refuse(instance, "fmi3EnterContinuousTimeMode", CO_SIMULATION_ONLY)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3CompletedIntegratorStep(
    instance: Instance3,
    _no_set_fmu_state_prior_to_current_point: bool,
    _enter_event_mode: *mut Boolean,
    _terminate_simulation: *mut Boolean,
) -> c_int {
    refuse(instance, "fmi3CompletedIntegratorStep", CO_SIMULATION_ONLY)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetTime(instance: Instance3, _time: f64) -> c_int {
    refuse(instance, "fmi3SetTime", CO_SIMULATION_ONLY)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetContinuousStates(instance: Instance3, _x: *const f64, _nx: usize) -> c_int {
    refuse(instance, "fmi3SetContinuousStates", CO_SIMULATION_ONLY)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetContinuousStateDerivatives(instance: Instance3, _dx: *mut f64, _nx: usize) -> c_int {
    refuse(instance, "fmi3GetContinuousStateDerivatives", CO_SIMULATION_ONLY)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetEventIndicators(instance: Instance3, _indicators: *mut f64, _n: usize) -> c_int {
    refuse(instance, "fmi3GetEventIndicators", CO_SIMULATION_ONLY)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetContinuousStates(instance: Instance3, _x: *mut f64, _nx: usize) -> c_int {
    refuse(instance, "fmi3GetContinuousStates", CO_SIMULATION_ONLY)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNominalsOfContinuousStates(
    instance: Instance3,
    _nominals: *mut f64,
    _nx: usize,
) -> c_int {
    refuse(instance, "fmi3GetNominalsOfContinuousStates", CO_SIMULATION_ONLY)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfEventIndicators(instance: Instance3, _n: *mut usize) -> c_int {
    refuse(instance, "fmi3GetNumberOfEventIndicators", CO_SIMULATION_ONLY)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfContinuousStates(instance: Instance3, _n: *mut usize) -> c_int {
    refuse(instance, "fmi3GetNumberOfContinuousStates", CO_SIMULATION_ONLY)
}
